"""The Rerun sink: hands a run's frames, states and events to the ``log_<thing>`` functions.

:class:`RerunLogger` buffers what the run loop gives it and logs it in batches: one
``send_columns`` per entity every ``flush_every`` frames or ``max_latency_s`` of wall
time, whichever comes first, and at the end. A call into Rerun costs about the same for
one row as for hundreds, so batching is what keeps recording cheap. Its do-nothing twin is
:class:`twsb_sim.sinks.NullSink`.
"""

from __future__ import annotations

import math
import time
import warnings
from typing import TYPE_CHECKING, Any

import numpy as np
import rerun as rr

from twsb_sim.rerun_log import paths
from twsb_sim.rerun_log.annotations import (
    cluster_annotation_context,
    decision_annotation_context,
    label_annotation_context,
    legend,
)
from twsb_sim.rerun_log.batch import FrameBatch
from twsb_sim.rerun_log.blueprint import default_blueprint
from twsb_sim.rerun_log.events import log_events, log_shove, shove_in_world
from twsb_sim.rerun_log.geometry import log_house, log_robot_body, log_sensor_view_frame
from twsb_sim.rerun_log.plots import log_filter_series, log_robot_series, log_series_styles
from twsb_sim.rerun_log.robot import log_robot_poses, log_trajectory, log_trajectory_style
from twsb_sim.rerun_log.scans import (
    log_clusters,
    log_filter_decisions,
    log_level_view,
    log_lidar_hits,
    log_scan_styles,
    log_sensor_labels,
)
from twsb_sim.rerun_log.sensors import log_sensor_series, log_sensor_styles
from twsb_sim.rerun_log.timelines import frame_times, sim_times

if TYPE_CHECKING:
    from twsb_sim.frame import Frame, RobotTruth
    from twsb_sim.scenario import Scenario
    from twsb_sim.simulation import Simulation
    from twsb_sim.summary import RunSummary

DEFAULT_FLUSH_EVERY = 300  # frames per batch: 30 s of simulated time at 10 Hz
DEFAULT_MAX_LATENCY_S = 1.0  # wall time: a live viewer lags the run by at most about this
TRAJECTORY_HEIGHT_M = 0.005  # the trajectory is drawn just above the floor


class RerunLogger:
    """A run sink that logs a run to a Rerun recording (see :mod:`twsb_sim.rerun_log`).

    Several runs handed to one logger (e.g. the episodes of an env) follow each other on
    the timelines; the static geometry is the last run's.

    Args:
        rec: the recording to log to, its sinks (an .rrd file, a viewer) already set.
        state_rate_hz: rate of extra robot-state samples (the run loop's state hook) for
            the 3D pose and the plots, e.g. 50 Hz to catch wheel-torque spikes that the
            frames' 10 Hz miss (it costs about 10 % more run time); None: frames only.
        flush_every: frames buffered before a batch is logged.
        max_latency_s: wall time after which a batch is logged even if smaller (s).
        send_blueprint: send :func:`default_blueprint` as the recording's default layout.
        p_th: the filter's detection threshold P_th, drawn beside the clusters' P(C_pv).
        close_recording: at :meth:`close`, also disconnect the recording from its sinks
            (this writes an .rrd file's footer); for a logger that owns its recording.
    """

    def __init__(
        self,
        rec: rr.RecordingStream,
        state_rate_hz: float | None = None,
        flush_every: int = DEFAULT_FLUSH_EVERY,
        max_latency_s: float = DEFAULT_MAX_LATENCY_S,
        send_blueprint: bool = True,
        p_th: float = math.nan,
        close_recording: bool = False,
    ) -> None:
        if flush_every < 1:
            raise ValueError(f"flush_every: expected at least 1, got {flush_every}")
        self.rec = rec
        self.state_rate_hz = state_rate_hz or None  # read by the run loop
        self.flush_every = flush_every
        self.max_latency_s = max_latency_s
        self._last_flush = time.monotonic()
        self.send_blueprint = send_blueprint
        self.p_th = p_th
        self.close_recording = close_recording
        self._frames: list[Frame] = []
        self._results: list[Any | None] = []
        self._states: list[RobotTruth] = []
        self._events: list[tuple[float, int, str]] = []  # (sim_time s, frame, text)
        self._sim: Simulation | None = None
        self._scenario: Scenario | None = None
        self._runs = 0
        self._t0_s = 0.0  # where this run's time 0 sits on sim_time (later runs follow)
        self._frame0 = 0  # ... and its frame 0 on frame
        self._frames_logged = 0  # over all runs
        self._last_t_s = 0.0
        self._last_position: np.ndarray | None = None  # where the trajectory ends
        self._latest_frame_stamp = -math.inf  # s, of this run's latest scan
        self._start_xy_yaw = np.zeros(3)  # the robot's start: the odom frame's origin

    # -- the run loop's hooks -------------------------------------------------------------

    def on_start(self, scenario: Scenario, sim: Simulation) -> None:
        """Log what does not change during the run: house, robot body, classes, styles."""
        self.flush(final=True)  # what is left of the previous run
        if self._runs:  # a later run starts one frame period after the last one ended
            # (its first scan is stamped one revolution before its time 0)
            self._t0_s = self._last_t_s + 1.0 / scenario.lidar.rate_hz - sim.lidar.stamp_offset_s
            self._frame0 = self._frames_logged
        self._runs += 1
        self._sim, self._scenario, self._last_position = sim, scenario, None
        truth = sim.truth()  # where the odom frame starts
        self._start_xy_yaw = np.array([*truth.position_base_in_world[:2], truth.yaw_rad])
        self._latest_frame_stamp = -math.inf
        rec = self.rec
        if self.send_blueprint and self._runs == 1:
            truth = sim.truth()
            start = (*truth.position_base_in_world[:2], truth.yaw_rad)
            rec.send_blueprint(default_blueprint(start), make_active=False, make_default=True)
        rec.log("/", label_annotation_context(), static=True)
        rec.log(paths.SENSOR_DECISION, decision_annotation_context(), static=True)
        rec.log(paths.SENSOR_CLUSTERS, cluster_annotation_context(), static=True)
        rec.log(paths.LEGEND, legend(), static=True)
        log_house(rec, sim.house)
        log_robot_body(rec, sim.model, sim.handles.base_body_id, sim.handles.lidar_site_id)
        log_sensor_view_frame(rec, sim.lidar.range_max)
        log_series_styles(rec)
        log_sensor_styles(rec)
        log_scan_styles(rec)
        log_trajectory_style(rec)
        self._event(sim.time_s, f"run: {scenario.name} in {sim.house.name}")

    def on_state(self, truth: RobotTruth) -> None:
        self._states.append(truth)

    def on_frame(self, frame: Frame, filter_result: Any | None) -> None:
        if self._frames and len(frame.scan) != len(self._frames[0].scan):
            self.flush()  # a batch stacks scans of one length
        self._frames.append(frame)
        self._results.append(filter_result)
        if (
            len(self._frames) >= self.flush_every
            or time.monotonic() - self._last_flush > self.max_latency_s
        ):
            self.flush()

    def on_event(self, t_s: float, text: str) -> None:
        self._event(t_s, text)
        if text.startswith("shove"):
            self._log_shove_at(t_s)

    def close(self, summary: RunSummary) -> None:
        """Log what is left and how the run ended; flush the recording to its sinks."""
        t_s = self._sim.time_s if self._sim is not None else summary.simulated_s
        self._event(t_s, f"ended: {summary.end_reason}", frame=max(self._next_frame() - 1, 0))
        self.flush(final=True)
        try:
            if self.close_recording:
                self.rec.disconnect()  # flushes, and finishes an .rrd file
            else:
                self.rec.flush()
        except RuntimeError as error:  # a sink that failed (e.g. its port was taken)
            warnings.warn(f"the Rerun recording is incomplete: {error}", stacklevel=2)

    # -- batches --------------------------------------------------------------------------

    def flush(self, final: bool = False) -> None:
        """Log the buffered frames and states now.

        A scan reaches the logger one revolution after its stamp, and its truth is the
        state sample of that stamp: states newer than the latest scan wait for the next
        batch (unless ``final``), so that each instant is logged once.
        """
        frames, results, states = self._frames, self._results, self._states
        self._frames, self._results = [], []
        if frames:
            self._latest_frame_stamp = max(self._latest_frame_stamp, frames[-1].stamp_s)
        if final:
            self._states = []
        else:
            self._states = [s for s in states if s.stamp_s > self._latest_frame_stamp]
            states = [s for s in states if s.stamp_s <= self._latest_frame_stamp]
        self._last_flush = time.monotonic()
        if self._events:
            log_events(self.rec, *zip(*self._events, strict=True))
            self._events = []
        if frames:
            self._log_frames(frames, results)
        if frames or states:
            self._log_robot(frames, states)

    def _frame_times(self, frames: list[Frame]) -> list[rr.TimeColumn]:
        return frame_times(
            [self._t0_s + f.stamp_s for f in frames], [self._frame0 + f.index for f in frames]
        )

    def _log_frames(self, frames: list[Frame], results: list[Any | None]) -> None:
        rec, batch = self.rec, FrameBatch.of(frames, results, self._t0_s, self._frame0)
        log_lidar_hits(rec, batch)
        log_filter_series(rec, batch, self.p_th)
        log_sensor_series(rec, batch, self._t0_s, self._start_xy_yaw)
        if len(decided := batch.with_results("removed")):
            log_filter_decisions(rec, decided)
        if len(unfiltered := batch.without_results("removed")):  # no decision to show
            log_sensor_labels(rec, unfiltered)
        if len(clustered := batch.with_clusters()):  # the filter's clusters, if it has any
            log_clusters(rec, clustered)
        if len(viewed := batch.with_results("level_view_m")):  # the improved filter's
            log_level_view(rec, viewed)
        self._frames_logged = int(batch.indices[-1]) + 1
        self._last_t_s = float(batch.stamps_s[-1])

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

    def _next_frame(self) -> int:
        """The index on ``frame`` of the frame still to come (buffered ones included)."""
        return self._frame0 + self._frames[-1].index + 1 if self._frames else self._frames_logged

    def _event(self, t_s: float, text: str, frame: int | None = None) -> None:
        """A text-log line at ``t_s`` of this run (on ``frame``: the next frame, by default)."""
        frame = self._next_frame() if frame is None else frame
        self._events.append((self._t0_s + t_s, frame, text))

    def _log_shove_at(self, t_s: float) -> None:
        """An arrow for the scenario's shove that starts now (none if the scenario has none)."""
        sim, scenario = self._sim, self._scenario
        if sim is None or scenario is None:
            return
        starting = [s for s in scenario.shoves if abs(s.t_s - t_s) <= sim.dt_s / 2]
        if not starting:
            return
        shove = starting[0]
        point, force = shove_in_world(shove, sim.truth())
        start_frame = self._next_frame()
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
