"""What every scan matcher returns, and the fitness all of them report.

The fitness is the same for every matcher, so results compare across them: the mean
squared distance from each aligned source point to its nearest target point, over the
source points whose nearest target point is within ``max_correspondence_m``.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from numpy.typing import ArrayLike
from scipy.spatial import cKDTree

from scaneval.geometry import transform_points, wrap_angle


@dataclasses.dataclass(frozen=True)
class MatchResult:
    """The outcome of one scan match.

    Attributes:
        pose: ``(x, y, theta)`` of the source frame in the target frame, m, m, rad.
        fitness: mean squared nearest-neighbour distance of the aligned source points to
            the target, m^2, over those within the matcher's ``max_correspondence_m``;
            lower is better; ``inf`` when no point is that close.
        iterations: iterations (or rotation hypotheses, for HSM) the matcher ran.
        converged: True when the matcher met its stopping criterion before running out of
            iterations and had enough points to work with.
        inlier_fraction: share of the source points counted in ``fitness``.
    """

    pose: np.ndarray
    fitness: float
    iterations: int
    converged: bool
    inlier_fraction: float = 0.0


def finite_points(points_xy: ArrayLike) -> np.ndarray:
    """The rows of an ``(n, 2)`` array whose coordinates are both finite."""
    points_xy = np.asarray(points_xy, dtype=np.float64).reshape(-1, 2)
    return points_xy[np.isfinite(points_xy).all(axis=1)]


def fitness(
    aligned_source: np.ndarray, target_tree: cKDTree, max_correspondence_m: float
) -> tuple[float, float]:
    """Mean squared nearest distance, m^2, and inlier share of aligned source points."""
    if len(aligned_source) == 0 or target_tree.n == 0:
        return float("inf"), 0.0
    distance, _ = target_tree.query(aligned_source, distance_upper_bound=max_correspondence_m)
    inliers = np.isfinite(distance)
    if not inliers.any():
        return float("inf"), 0.0
    return float(np.mean(distance[inliers] ** 2)), float(inliers.mean())


def result(
    pose: np.ndarray,
    source: np.ndarray,
    target_tree: cKDTree,
    iterations: int,
    converged: bool,
    max_correspondence_m: float,
) -> MatchResult:
    """A :class:`MatchResult` with the shared fitness of ``pose``."""
    pose = np.array([pose[0], pose[1], float(wrap_angle(pose[2]))])
    value, share = fitness(transform_points(source, pose), target_tree, max_correspondence_m)
    return MatchResult(pose, value, iterations, converged, share)
