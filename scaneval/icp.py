"""Point-to-point ICP with Arun's closed-form SVD step and a KD-tree."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike
from scipy.spatial import cKDTree

from scaneval.geometry import transform_points, wrap_angle
from scaneval.match_result import MatchResult, finite_points, result


def rigid_fit(source: np.ndarray, target: np.ndarray) -> np.ndarray:
    """Least-squares rigid pose mapping paired points ``source`` onto ``target`` (Arun's SVD).

    Args:
        source: points, m, shape ``(n, 2)``, ``n >= 2``.
        target: the paired points, m, shape ``(n, 2)``.

    Returns:
        ``(x, y, theta)`` minimising ``sum |R source_i + t - target_i|^2``.
    """
    mean_source, mean_target = source.mean(axis=0), target.mean(axis=0)
    covariance = (source - mean_source).T @ (target - mean_target)
    u, _, vt = np.linalg.svd(covariance)
    rotation = vt.T @ u.T
    if np.linalg.det(rotation) < 0.0:  # a reflection fits better: take the best rotation
        vt[-1] *= -1.0
        rotation = vt.T @ u.T
    translation = mean_target - rotation @ mean_source
    return np.array([translation[0], translation[1], np.arctan2(rotation[1, 0], rotation[0, 0])])


def icp(
    source_xy: ArrayLike,
    target_xy: ArrayLike,
    initial_pose: ArrayLike = (0.0, 0.0, 0.0),
    max_iterations: int = 50,
    max_correspondence_m: float = 1.0,
    tolerance: float = 1e-6,
    outlier_factor: float = 3.0,
) -> MatchResult:
    """Point-to-point ICP (Besl and McKay) with Arun's SVD step (ref. 25) and a KD-tree.

    Each iteration pairs every moved source point with its nearest target point, drops
    pairs farther apart than ``max_correspondence_m`` or than ``outlier_factor`` times the
    median pair distance (parts of one scan the other does not see), and refits the pose
    in closed form.

    Args:
        source_xy: points to align, m, shape ``(n, 2)``.
        target_xy: reference points, m, shape ``(m, 2)``.
        initial_pose: starting guess ``(x, y, theta)``, m, m, rad.
        max_iterations: iteration limit.
        max_correspondence_m: largest pair distance used, m.
        tolerance: stop when the pose changes by less than this between iterations
            (translation in m plus rotation in rad).
        outlier_factor: pairs farther apart than this many median pair distances are
            dropped; ``inf`` keeps every pair within ``max_correspondence_m``.

    Returns:
        The :class:`MatchResult`; ``converged`` is False when the iteration limit was hit
        or fewer than three pairs were left.
    """
    source, target = finite_points(source_xy), finite_points(target_xy)
    pose = np.asarray(initial_pose, dtype=np.float64).copy()
    tree = cKDTree(target)
    converged, iterations = False, 0
    if len(source) < 3 or len(target) < 3:
        return result(pose, source, tree, 0, False, max_correspondence_m)
    for iterations in range(1, max_iterations + 1):  # noqa: B007 - reported after the loop
        distance, index = tree.query(
            transform_points(source, pose), distance_upper_bound=max_correspondence_m
        )
        paired = np.isfinite(distance)
        if paired.any():
            paired &= distance <= outlier_factor * np.median(distance[paired])
        if paired.sum() < 3:
            break
        new_pose = rigid_fit(source[paired], target[index[paired]])
        step = np.hypot(*(new_pose[:2] - pose[:2])) + abs(wrap_angle(new_pose[2] - pose[2]))
        pose = new_pose
        if step < tolerance:
            converged = True
            break
    return result(pose, source, tree, iterations, converged, max_correspondence_m)
