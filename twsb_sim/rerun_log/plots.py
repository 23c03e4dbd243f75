"""Time series: the robot's state, and the filter's per-frame counts and scores.

Robot-state samples come from the frames and, when the run loop provides them, from the
state hook, so the plots follow pitch and torque peaks that fall between two scans.
Filter series have one sample per frame.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import rerun as rr

from twsb_sim.frame import Frame, RobotTruth
from twsb_sim.labels import is_pitch_variation
from twsb_sim.rerun_log import paths
from twsb_sim.rerun_log.timelines import Times


def log_robot_series(rec: rr.RecordingStream, times: Times, truths: Sequence[RobotTruth]) -> None:
    """Pitch, pitch rate, velocity and yaw rate (command and actual), wheel torques."""
    deg = math.degrees(1.0)
    columns = {
        paths.PLOT_PITCH: [[t.pitch_rad * deg] for t in truths],
        paths.PLOT_PITCH_RATE: [[t.pitch_rate_rad_s * deg] for t in truths],
        paths.PLOT_VELOCITY: [[t.command_velocity_mps, t.forward_velocity_mps] for t in truths],
        paths.PLOT_YAW_RATE: [
            [t.command_yaw_rate_rad_s * deg, t.yaw_rate_rad_s * deg] for t in truths
        ],
        paths.PLOT_WHEEL_TORQUE: [t.wheel_torques_nm for t in truths],
    }
    for path, values in columns.items():
        rec.send_columns(path, indexes=times, columns=rr.Scalars.columns(scalars=np.array(values)))


# (entity, series names, colours): logged once, static, so each plot has its legend
SERIES_STYLES = {
    paths.PLOT_PITCH: (["pitch [deg] (+ = nose down)"], [(255, 140, 0)]),
    paths.PLOT_PITCH_RATE: (["pitch rate [deg/s]"], [(255, 200, 80)]),
    paths.PLOT_VELOCITY: (["command [m/s]", "actual [m/s]"], [(150, 150, 150), (60, 160, 255)]),
    paths.PLOT_YAW_RATE: (["command [deg/s]", "actual [deg/s]"], [(150, 150, 150), (60, 200, 120)]),
    paths.PLOT_WHEEL_TORQUE: (["left [N·m]", "right [N·m]"], [(230, 90, 90), (90, 140, 230)]),
    paths.PLOT_BEAMS: (
        ["pitch-variation beams (truth)", "removed beams (filter)"],
        [(255, 140, 0), (40, 200, 80)],
    ),
    paths.PLOT_PRECISION_RECALL: (["precision", "recall"], [(60, 160, 255), (255, 80, 160)]),
    paths.PLOT_P_PV: (["max P(C_pv) of the clusters", "P_th"], [(255, 50, 50), (150, 150, 150)]),
}


def log_series_styles(rec: rr.RecordingStream) -> None:
    """Names and colours of every plotted series (static)."""
    for path, (names, colors) in SERIES_STYLES.items():
        rec.log(path, rr.SeriesLines(names=names, colors=colors), static=True)


def frame_counts(frame: Frame, result: Any | None) -> tuple[float, float, float, float]:
    """(pitch-variation beams, removed beams, precision, recall) of one frame.

    Counted over beams with a finite input range (DESIGN.md); precision is 1 where
    nothing is removed, recall NaN where there is no pitch-variation beam; the filter's
    numbers are NaN when no filter ran.
    """
    finite = np.isfinite(frame.scan.ranges)
    truth = is_pitch_variation(frame.labels) & finite
    n_truth = int(np.count_nonzero(truth))
    if result is None:
        return n_truth, math.nan, math.nan, math.nan
    removed = np.asarray(result.removed, dtype=bool) & finite
    tp = int(np.count_nonzero(truth & removed))
    n_removed = int(np.count_nonzero(removed))
    precision = tp / n_removed if n_removed else 1.0
    recall = tp / n_truth if n_truth else math.nan
    return n_truth, n_removed, precision, recall


def log_filter_series(
    rec: rr.RecordingStream,
    times: Times,
    frames: Sequence[Frame],
    results: Sequence[Any | None],
    p_th: float,
) -> None:
    """Beam counts (truth and removed), precision and recall, max P(C_pv) against P_th.

    Args:
        rec: the recording.
        times: one time per frame.
        frames: consecutive frames.
        results: the filter's result per frame, or None where no filter ran.
        p_th: the filter's detection threshold (NaN when no filter ran).
    """
    counts = np.array([frame_counts(f, r) for f, r in zip(frames, results, strict=True)])
    max_p_pv = [
        max((c.p_pv for c in r.clusters if not math.isnan(c.p_pv)), default=0.0)
        if r is not None
        else math.nan
        for r in results
    ]
    columns = {
        paths.PLOT_BEAMS: counts[:, :2],
        paths.PLOT_PRECISION_RECALL: counts[:, 2:],
        paths.PLOT_P_PV: np.column_stack((max_p_pv, np.full(len(frames), p_th))),
    }
    for path, values in columns.items():
        rec.send_columns(path, indexes=times, columns=rr.Scalars.columns(scalars=values))
