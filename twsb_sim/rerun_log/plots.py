"""Time series: the robot's state, and the filter's per-frame counts and scores.

Robot-state samples come from the frames and, when the run loop provides them, from the
state hook, so the plots follow pitch and torque peaks that fall between two scans.
Filter series have one sample per frame.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import rerun as rr

from twsb_sim.frame import RobotTruth
from twsb_sim.rerun_log import paths
from twsb_sim.rerun_log.annotations import pitch_variation_mask
from twsb_sim.rerun_log.batch import FrameBatch
from twsb_sim.rerun_log.timelines import Times


def log_robot_series(rec: rr.RecordingStream, times: Times, truths: Sequence[RobotTruth]) -> None:
    """Pitch, pitch rate, velocity and yaw rate (command and actual), wheel torques."""
    v = np.array(
        [
            (t.pitch_rad, t.pitch_rate_rad_s, t.command_velocity_mps, t.forward_velocity_mps,
             t.command_yaw_rate_rad_s, t.yaw_rate_rad_s, *t.wheel_torques_nm)
            for t in truths
        ]
    )  # fmt: skip
    deg = math.degrees(1.0)
    columns = {
        paths.PLOT_PITCH: v[:, 0:1] * deg,
        paths.PLOT_PITCH_RATE: v[:, 1:2] * deg,
        paths.PLOT_VELOCITY: v[:, 2:4],
        paths.PLOT_YAW_RATE: v[:, 4:6] * deg,
        paths.PLOT_WHEEL_TORQUE: v[:, 6:8],
    }
    for path, values in columns.items():
        rec.send_columns(path, indexes=times, columns=rr.Scalars.columns(scalars=values))


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
    paths.PLOT_P_PV: (["max beam score", "P_th"], [(255, 50, 50), (150, 150, 150)]),
}


def log_series_styles(rec: rr.RecordingStream) -> None:
    """Names and colours of every plotted series (static)."""
    for path, (names, colors) in SERIES_STYLES.items():
        rec.log(path, rr.SeriesLines(names=names, colors=colors), static=True)


def filter_counts(batch: FrameBatch) -> np.ndarray:
    """Per frame: pitch-variation beams, removed beams, precision, recall; ``(K, 4)``.

    Counted over beams with a finite input range (docs/conventions.md); precision is 1 where
    nothing is removed, recall NaN where there is no pitch-variation beam; the filter's
    numbers are NaN for frames without a filter result.
    """
    finite = np.isfinite(batch.ranges)
    truth = pitch_variation_mask(batch.labels) & finite
    counts = np.full((len(batch), 4), np.nan)
    counts[:, 0] = truth.sum(axis=1)
    with_result = [i for i, r in enumerate(batch.results) if hasattr(r, "removed")]
    if with_result:
        removed = batch.subset(with_result).stack("removed", bool) & finite[with_result]
        tp = (truth[with_result] & removed).sum(axis=1)
        n_removed, n_truth = removed.sum(axis=1), counts[with_result, 0]
        counts[with_result, 1] = n_removed
        with np.errstate(divide="ignore", invalid="ignore"):
            counts[with_result, 2] = np.where(n_removed > 0, tp / n_removed, 1.0)
            counts[with_result, 3] = np.where(n_truth > 0, tp / n_truth, np.nan)
    return counts


def log_filter_series(rec: rr.RecordingStream, batch: FrameBatch, p_th: float) -> None:
    """Beam counts (truth and removed), precision and recall, the highest beam score
    against P_th.

    Args:
        rec: the recording.
        batch: consecutive frames (those without a filter result plot NaN).
        p_th: the filter's detection threshold (NaN when unknown).
    """
    counts = filter_counts(batch)
    # a beam's score is its cluster's P(C_pv) (the improved filter's: its claim score, at
    # least 0.01 on a new return): a beam is removed exactly when it exceeds P_th
    max_p_pv = np.full(len(batch), math.nan)
    scored = [i for i, r in enumerate(batch.results) if hasattr(r, "scores")]
    if scored:
        max_p_pv[scored] = batch.subset(scored).stack("scores", float).max(axis=1, initial=0.0)
    columns = {
        paths.PLOT_BEAMS: counts[:, :2],
        paths.PLOT_PRECISION_RECALL: counts[:, 2:],
        paths.PLOT_P_PV: np.column_stack((max_p_pv, np.full(len(batch), p_th))),
    }
    times = batch.times
    for path, values in columns.items():
        rec.send_columns(path, indexes=times, columns=rr.Scalars.columns(scalars=values))
