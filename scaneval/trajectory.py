"""Absolute trajectory error (eq. 7) with a stated alignment, and time association."""

from __future__ import annotations

import dataclasses
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

Alignment = Literal["none", "se2", "sim2"]


@dataclasses.dataclass(frozen=True)
class AteResult:
    """Absolute trajectory error of an estimate against the truth.

    Attributes:
        rmse: eq. 7, the root mean squared position error after alignment, m.
        mean, median, max: of the per-pose position errors, m.
        errors: position error of every pose after alignment, m, shape ``(n,)``.
        align: the alignment applied to the estimate: ``"none"``, ``"se2"`` (rotation and
            translation) or ``"sim2"`` (and scale).
        alignment_pose: ``(x, y, theta)`` applied to the estimate, m, m, rad.
        scale: scale applied to the estimate (1 unless ``"sim2"``).
    """

    rmse: float
    mean: float
    median: float
    max: float
    errors: np.ndarray
    align: Alignment
    alignment_pose: np.ndarray
    scale: float


def positions(trajectory: ArrayLike, name: str) -> np.ndarray:
    """The ``(n, 2)`` positions of ``(n, 2)`` points or ``(n, 3)`` ``(x, y, theta)`` poses."""
    trajectory = np.asarray(trajectory, dtype=np.float64)
    if trajectory.ndim != 2 or trajectory.shape[1] not in (2, 3):
        raise ValueError(
            f"{name}: must be (n, 2) positions or (n, 3) poses, got {trajectory.shape}"
        )
    return trajectory[:, :2]


def umeyama(source: np.ndarray, target: np.ndarray, with_scale: bool) -> tuple[np.ndarray, float]:
    """Closed-form similarity (Umeyama 1991) minimising ``sum |s R source_i + t - target_i|^2``.

    Returns:
        ``((x, y, theta), s)``; ``s`` is 1 without scale.
    """
    mean_source, mean_target = source.mean(axis=0), target.mean(axis=0)
    centred_source, centred_target = source - mean_source, target - mean_target
    covariance = centred_target.T @ centred_source / len(source)
    u, singular, vt = np.linalg.svd(covariance)
    sign = np.diag([1.0, np.sign(np.linalg.det(u @ vt)) or 1.0])
    rotation = u @ sign @ vt
    variance = np.mean(np.sum(centred_source**2, axis=1))
    scale = float(np.trace(np.diag(singular) @ sign) / variance) if with_scale else 1.0
    translation = mean_target - scale * rotation @ mean_source
    theta = np.arctan2(rotation[1, 0], rotation[0, 0])
    return np.array([translation[0], translation[1], theta]), scale


def ate(
    estimated_xy_or_poses: ArrayLike,
    truth_xy_or_poses: ArrayLike,
    align: Alignment = "se2",
) -> AteResult:
    """Absolute trajectory error, eq. 7, over time-matched positions.

    Args:
        estimated_xy_or_poses: estimated positions ``(n, 2)`` or poses ``(n, 3)``, m.
        truth_xy_or_poses: true positions or poses at the same times, same length.
        align: ``"none"`` compares as given; ``"se2"`` first applies the rotation and
            translation that best fit the estimate onto the truth (Umeyama/Horn closed
            form); ``"sim2"`` also fits a scale.

    Returns:
        The :class:`AteResult`.
    """
    estimated = positions(estimated_xy_or_poses, "estimated_xy_or_poses")
    truth = positions(truth_xy_or_poses, "truth_xy_or_poses")
    if len(estimated) != len(truth) or len(truth) == 0:
        raise ValueError(
            f"estimated, truth: must be non-empty and time-matched, got {len(estimated)} "
            f"and {len(truth)} poses"
        )
    if align == "none":
        pose, scale = np.zeros(3), 1.0
    elif align in ("se2", "sim2"):
        pose, scale = umeyama(estimated, truth, with_scale=align == "sim2")
    else:
        raise ValueError(f"align: must be 'none', 'se2' or 'sim2', got {align!r}")
    c, s = np.cos(pose[2]), np.sin(pose[2])
    aligned = scale * estimated @ np.array([[c, s], [-s, c]]) + pose[:2]
    errors = np.linalg.norm(aligned - truth, axis=1)
    return AteResult(
        rmse=float(np.sqrt(np.mean(errors**2))),
        mean=float(errors.mean()),
        median=float(np.median(errors)),
        max=float(errors.max()),
        errors=errors,
        align=align,
        alignment_pose=pose,
        scale=scale,
    )


def associate(
    stamps_a: ArrayLike, stamps_b: ArrayLike, max_difference_s: float = 0.02
) -> tuple[np.ndarray, np.ndarray]:
    """Pair each stamp of ``a`` with the nearest stamp of ``b`` within ``max_difference_s``.

    Args:
        stamps_a, stamps_b: times, s, each sorted ascending.
        max_difference_s: largest accepted time difference, s.

    Returns:
        Index arrays ``(ia, ib)`` of the matched pairs, in the order of ``a`` (a stamp of
        ``b`` may serve more than one stamp of ``a``).
    """
    stamps_a = np.asarray(stamps_a, dtype=np.float64)
    stamps_b = np.asarray(stamps_b, dtype=np.float64)
    if stamps_b.size == 0:
        return np.zeros(0, dtype=np.intp), np.zeros(0, dtype=np.intp)
    last = stamps_b.size - 1
    right = np.clip(np.searchsorted(stamps_b, stamps_a), 0, last)
    left = np.clip(right - 1, 0, last)
    nearest = np.where(
        np.abs(stamps_b[left] - stamps_a) <= np.abs(stamps_b[right] - stamps_a), left, right
    )
    matched = np.abs(stamps_b[nearest] - stamps_a) <= max_difference_s
    return np.flatnonzero(matched), nearest[matched]
