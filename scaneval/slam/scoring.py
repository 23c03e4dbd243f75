"""Scoring a SLAM trajectory: ATE (eq. 7) after a stated alignment, and tracking failure.

A run is a **tracking failure** (the paper's "–") when the system reports that it lost
track (:attr:`HectorSlam.lost`, a non-finite KISS-ICP pose, an exception), or when its
estimate diverges from the truth: after the alignment, some position is more than
``FAILURE_DISTANCE_M`` from the true one. The ATE is computed either way (and kept in the
results), but a failed run's table cell reads "–".
"""

from __future__ import annotations

import dataclasses

import numpy as np

from scaneval.trajectory import Alignment, AteResult, ate

FAILURE_DISTANCE_M = 1.0  # m: an aligned pose this far from the truth means tracking is lost
ALIGNMENT: Alignment = "se2"  # rotation and translation, no scale (evo_ape --align)


@dataclasses.dataclass(frozen=True)
class TrajectoryScore:
    """How well one SLAM run tracked.

    Attributes:
        ate: the ATE after :data:`ALIGNMENT`, or None when there was no usable estimate.
        failed: the run is a tracking failure (see the module docstring).
        failure: why, in words; "" when it did not fail.
    """

    ate: AteResult | None
    failed: bool
    failure: str

    @property
    def rmse_m(self) -> float:
        """ATE RMSE, m; NaN without an estimate."""
        return self.ate.rmse if self.ate is not None else float("nan")


def score_trajectory(
    estimated_poses: np.ndarray,
    true_poses: np.ndarray,
    stamps_s: np.ndarray | None = None,
    lost_at_scan: int | None = None,
    error: str = "",
    failure_distance_m: float = FAILURE_DISTANCE_M,
) -> TrajectoryScore:
    """Score an estimated trajectory against the truth at the same times.

    Args:
        estimated_poses: ``(n, 3)`` ``(x, y, theta)`` in the SLAM's map frame.
        true_poses: ``(n, 3)`` (or ``(n, 2)``) true poses in the world, same times.
        stamps_s: times of the poses, s, to say when a divergence happened.
        lost_at_scan: the scan at which the system reported losing track, or None.
        error: the message of an exception that ended the run, "" when none.
        failure_distance_m: the divergence threshold, m.

    Returns:
        The :class:`TrajectoryScore`.
    """
    estimated = np.asarray(estimated_poses, dtype=np.float64).reshape(-1, 3)
    truth = np.asarray(true_poses, dtype=np.float64)
    reasons = []
    if error:
        reasons.append(f"error: {error}")
    if lost_at_scan is not None:
        reasons.append(f"lost track at scan {lost_at_scan} (reported by the system)")
    finite = np.all(np.isfinite(estimated), axis=1)
    if len(estimated) != len(truth) or not finite.all():
        missing = len(truth) - int(finite.sum())
        reasons.append(f"{missing} of {len(truth)} poses missing or not finite")
    result = None
    if finite.sum() >= 2:
        result = ate(estimated[finite], truth[: len(estimated)][finite], align=ALIGNMENT)
        worst = int(np.argmax(result.errors))
        if result.max > failure_distance_m:
            when = f" at t={stamps_s[finite][worst]:.1f} s" if stamps_s is not None else ""
            reasons.append(
                f"diverged: {result.max:.2f} m from the truth{when} (> {failure_distance_m:g} m)"
            )
    elif not reasons:
        reasons.append("fewer than two poses")
    return TrajectoryScore(ate=result, failed=bool(reasons), failure="; ".join(reasons))
