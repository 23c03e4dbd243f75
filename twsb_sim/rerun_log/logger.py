"""The Rerun sink: hands a run's frames, states and events to the ``log_<thing>`` functions.

:class:`RerunLogger` buffers what the run loop gives it and logs it in batches (one
``send_columns`` per entity every ``flush_every`` frames, and at the end), so recording
costs a few percent of the run. Its do-nothing twin is :class:`twsb_sim.sinks.NullSink`.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np
import rerun as rr

from twsb_sim.rerun_log import paths
from twsb_sim.rerun_log.annotations import decision_annotation_context, label_annotation_context
from twsb_sim.rerun_log.blueprint import default_blueprint
from twsb_sim.rerun_log.events import log_event, log_shove
from twsb_sim.rerun_log.geometry import log_house, log_robot_body, log_sensor_view_frame
from twsb_sim.rerun_log.plots import log_filter_series, log_robot_series, log_series_styles
from twsb_sim.rerun_log.robot import log_robot_poses, log_trajectory
from twsb_sim.rerun_log.scans import (
    log_clusters,
    log_filter_decisions,
    log_lidar_hits,
    log_sensor_labels,
)
from twsb_sim.rerun_log.timelines import frame_times, sim_times
from twsb_sim.timeline import heading_force_to_world

if TYPE_CHECKING:
    from twsb_sim.frame import Frame, RobotTruth
    from twsb_sim.scenario import Scenario
    from twsb_sim.simulation import Simulation
    from twsb_sim.summary import RunSummary

DEFAULT_STATE_RATE_HZ = 50.0  # robot-state samples between frames: smooth pitch and torques
DEFAULT_FLUSH_EVERY = 10  # frames per batch: 1 s of simulated time at 10 Hz
TRAJECTORY_HEIGHT_M = 0.005  # the trajectory is drawn just above the floor


class RerunLogger:
    """A run sink that logs a run to a Rerun recording (see :mod:`twsb_sim.rerun_log`).

    Several runs handed to one logger (e.g. the episodes of an env) follow each other on
    the timelines; the static geometry is the last run's.

    Args:
        rec: the recording to log to, its sinks (an .rrd file, a viewer) already set.
        state_rate_hz: rate of the robot-state samples between frames, for the 3D pose
            and the plots; None or 0 for the frames' 10 Hz only.
        flush_every: frames buffered before a batch is logged.
        send_blueprint: send :func:`default_blueprint` as the recording's default layout.
        p_th: the filter's detection threshold P_th, drawn beside the clusters' P(C_pv).
        close_recording: at :meth:`close`, also disconnect the recording from its sinks
            (this writes an .rrd file's footer); for a logger that owns its recording.
    """

    def __init__(
        self,
        rec: rr.RecordingStream,
        state_rate_hz: float | None = DEFAULT_STATE_RATE_HZ,
        flush_every: int = DEFAULT_FLUSH_EVERY,
        send_blueprint: bool = True,
        p_th: float = math.nan,
        close_recording: bool = False,
    ) -> None:
        if flush_every < 1:
            raise ValueError(f"flush_every: expected at least 1, got {flush_every}")
        self.rec = rec
        self.state_rate_hz = state_rate_hz or None  # read by the run loop
        self.flush_every = flush_every
        self.send_blueprint = send_blueprint
        self.p_th = p_th
        self.close_recording = close_recording
        self._frames: list[Frame] = []
        self._results: list[Any | None] = []
        self._states: list[RobotTruth] = []
        self._sim: Simulation | None = None
        self._scenario: Scenario | None = None
        self._runs = 0
        self._t0_s = 0.0  # where this run's time 0 sits on sim_time (later runs follow)
        self._frame0 = 0  # ... and its frame 0 on frame
        self._frames_logged = 0  # over all runs
        self._last_t_s = 0.0
        self._last_position: np.ndarray | None = None  # where the trajectory ends

    # -- the run loop's hooks -------------------------------------------------------------

    def on_start(self, scenario: Scenario, sim: Simulation) -> None:
        """Log what does not change during the run: house, robot body, classes, styles."""
        self.flush()
        if self._runs:  # a later run starts one frame period after the last one ended
            self._t0_s = self._last_t_s + 1.0 / scenario.lidar.rate_hz
            self._frame0 = self._frames_logged
        self._runs += 1
        self._sim, self._scenario, self._last_position = sim, scenario, None
        rec = self.rec
        if self.send_blueprint and self._runs == 1:
            truth = sim.truth()
            start = (*truth.position_base_in_world[:2], truth.yaw_rad)
            rec.send_blueprint(default_blueprint(start), make_active=False, make_default=True)
        rec.log("/", label_annotation_context(), static=True)
        rec.log(paths.SENSOR_DECISION, decision_annotation_context(), static=True)
        log_house(rec, sim.house)
        log_robot_body(rec, sim.model, sim.handles.base_body_id, sim.handles.lidar_site_id)
        log_sensor_view_frame(rec, sim.lidar.range_max)
        log_series_styles(rec)
        self._event(sim.time_s, f"run: {scenario.name} in {sim.house.name}")

    def on_state(self, truth: RobotTruth) -> None:
        self._states.append(truth)

    def on_frame(self, frame: Frame, filter_result: Any | None) -> None:
        self._frames.append(frame)
        self._results.append(filter_result)
        if len(self._frames) >= self.flush_every:
            self.flush()

    def on_event(self, t_s: float, text: str) -> None:
        self.flush()  # the data before the event goes out first
        self._event(t_s, text)
        if text.startswith("shove"):
            self._log_shove_at(t_s)

    def close(self, summary: RunSummary) -> None:
        """Log what is left and how the run ended; flush the recording to its sinks."""
        self.flush()
        t_s = self._sim.time_s if self._sim is not None else summary.simulated_s
        self._event(t_s, f"ended: {summary.end_reason}", frame=self._frames_logged - 1)
        self.rec.flush()
        if self.close_recording:
            self.rec.disconnect()

    # -- batches --------------------------------------------------------------------------

    def flush(self) -> None:
        """Log the buffered frames and states now."""
        frames, results, states = self._frames, self._results, self._states
        self._frames, self._results, self._states = [], [], []
        if frames:
            self._log_frames(frames, results)
        if frames or states:
            self._log_robot(frames, states)

    def _frame_times(self, frames: list[Frame]) -> list[rr.TimeColumn]:
        return frame_times(
            [self._t0_s + f.stamp_s for f in frames], [self._frame0 + f.index for f in frames]
        )

    def _log_frames(self, frames: list[Frame], results: list[Any | None]) -> None:
        rec, times = self.rec, self._frame_times(frames)
        log_lidar_hits(rec, times, frames)
        log_sensor_labels(rec, times, frames)
        log_filter_series(rec, times, frames, results, self.p_th)
        filtered = [(f, r) for f, r in zip(frames, results, strict=True) if r is not None]
        if filtered:  # frames the filter ran on
            kept_frames, kept_results = (list(column) for column in zip(*filtered, strict=True))
            kept_times = self._frame_times(kept_frames)
            log_filter_decisions(rec, kept_times, kept_frames, kept_results)
            log_clusters(rec, kept_times, kept_frames, kept_results)
        self._frames_logged = self._frame0 + frames[-1].index + 1
        self._last_t_s = self._t0_s + frames[-1].stamp_s

    def _log_robot(self, frames: list[Frame], states: list[RobotTruth]) -> None:
        """Poses, trajectory and state plots from frame and state samples, in time order."""
        frame_stamps = {f.stamp_s for f in frames}
        # a state sample at a frame's instant is the frame's truth: log that one only
        states = [s for s in states if s.stamp_s not in frame_stamps]
        samples = sorted([f.truth for f in frames] + states, key=lambda truth: truth.stamp_s)
        positions = np.array([truth.position_base_in_world for truth in samples])
        previous = positions[0] if self._last_position is None else self._last_position
        segments = np.stack((np.vstack((previous, positions[:-1])), positions), axis=1)
        segments[:, :, 2] = TRAJECTORY_HEIGHT_M
        self._last_position = positions[-1]
        self._last_t_s = max(self._last_t_s, self._t0_s + samples[-1].stamp_s)
        at_frame = np.isin([truth.stamp_s for truth in samples], list(frame_stamps))
        for mask, truths, times in (
            (at_frame, [f.truth for f in frames], self._frame_times(frames)),
            (~at_frame, states, sim_times([self._t0_s + s.stamp_s for s in states])),
        ):
            if truths:
                log_robot_poses(self.rec, times, truths)
                log_trajectory(self.rec, times, segments[mask])
                log_robot_series(self.rec, times, truths)

    # -- events ---------------------------------------------------------------------------

    def _event(self, t_s: float, text: str, frame: int | None = None) -> None:
        """A text-log line at ``t_s`` of this run (on ``frame``: the next frame, by default)."""
        log_event(self.rec, self._t0_s + t_s, self._frames_logged if frame is None else frame, text)

    def _log_shove_at(self, t_s: float) -> None:
        """An arrow for the scenario's shove that starts now (none if the scenario has none)."""
        sim, scenario = self._sim, self._scenario
        if sim is None or scenario is None:
            return
        starting = [s for s in scenario.shoves if abs(s.t_s - t_s) <= sim.dt_s / 2]
        if not starting:
            return
        shove, truth = starting[0], sim.truth()
        rotation = np.empty(9)
        mujoco.mju_quat2Mat(rotation, truth.quat_base_in_world)
        point = truth.position_base_in_world + rotation.reshape(3, 3) @ np.array(shove.point_m)
        force = heading_force_to_world(shove.force_n, truth.yaw_rad)
        start_frame = self._frames_logged
        # on the frame timeline it shows for at least one frame, even when shorter
        end_frame = max(
            self._frame0 + math.ceil(shove.end_s * scenario.lidar.rate_hz - 1e-9), start_frame + 1
        )
        label = f"shove {np.linalg.norm(force):.0f} N {shove.label}".rstrip()
        log_shove(
            self.rec,
            (self._t0_s + t_s, start_frame),
            (self._t0_s + shove.end_s, end_frame),
            point,
            force,
            label,
        )
