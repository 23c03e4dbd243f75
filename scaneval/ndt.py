"""2D Normal Distributions Transform scan matching (Biber and Strasser 2003, ref. 26).

The target is summarised by a grid of cells, each holding the mean and covariance of its
points. The score of a pose is the sum over the moved source points of
``exp(-q^T S^-1 q / 2)``, ``q`` the point's offset from the mean of the cell it falls in,
``S`` that cell's covariance. Newton's method climbs the score, with the Hessian made
positive definite where needed and a backtracking line search. As in the paper, four
grids shifted by half a cell are summed, which smooths the cell borders.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from numpy.typing import ArrayLike
from scipy.spatial import cKDTree

from scaneval.geometry import transform_points
from scaneval.match_result import MatchResult, finite_points, result

MIN_POINTS_PER_CELL = 3  # a covariance from fewer points is degenerate
EIGENVALUE_RATIO = 1e-3  # Biber and Strasser: small eigenvalues raised to this share of the largest
MIN_VARIANCE = 1e-6  # m^2, for cells whose points all coincide
MAX_ROTATION_STEP = 0.1  # rad, per Newton step


@dataclasses.dataclass(frozen=True)
class NdtGrid:
    """Normal distributions of one grid over the target points.

    Attributes:
        origin: lower-left corner of cell (0, 0), m.
        cell_size: cell side, m.
        cell_of: cell number per grid position, shape ``(nx, ny)``; -1 for empty cells.
        means: mean point per cell, m, shape ``(k, 2)``.
        inverse_covariances: inverse covariance per cell, 1/m^2, shape ``(k, 2, 2)``.
    """

    origin: np.ndarray
    cell_size: float
    cell_of: np.ndarray
    means: np.ndarray
    inverse_covariances: np.ndarray

    @classmethod
    def build(cls, points: np.ndarray, cell_size: float, shift: np.ndarray) -> NdtGrid:
        """The grid over ``points`` whose cell corners are shifted by ``shift`` (m)."""
        origin = points.min(axis=0) - cell_size + shift
        index = np.floor((points - origin) / cell_size).astype(np.intp)
        shape = index.max(axis=0) + 2
        flat = index[:, 0] * shape[1] + index[:, 1]
        keys, cell, counts = np.unique(flat, return_inverse=True, return_counts=True)
        sums = np.column_stack(
            [
                np.bincount(cell, weights=w)
                for w in (*points.T, *(points[:, [0, 0, 1]] * points[:, [0, 1, 1]]).T)
            ]
        )
        kept = counts >= MIN_POINTS_PER_CELL
        counts, sums, keys = counts[kept], sums[kept], keys[kept]
        means = sums[:, :2] / counts[:, None]
        xx, xy, yy = (sums[:, 2:] / counts[:, None] - means[:, [0, 0, 1]] * means[:, [0, 1, 1]]).T
        covariances = np.stack((np.column_stack((xx, xy)), np.column_stack((xy, yy))), axis=1)
        values, vectors = np.linalg.eigh(covariances)
        floor = np.maximum(EIGENVALUE_RATIO * values[:, 1:], MIN_VARIANCE)
        values = np.maximum(values, floor)
        inverse = np.einsum("kij,kj,klj->kil", vectors, 1.0 / values, vectors)
        cell_of = np.full(int(shape[0] * shape[1]), -1, dtype=np.intp)
        cell_of[keys] = np.arange(keys.size)
        return cls(origin, cell_size, cell_of.reshape(shape), means, inverse)

    def lookup(self, points: np.ndarray) -> np.ndarray:
        """Cell number of every point, -1 outside the grid or in an empty cell."""
        index = np.floor((points - self.origin) / self.cell_size).astype(np.intp)
        inside = np.all((index >= 0) & (index < self.cell_of.shape), axis=1)
        cells = np.full(len(points), -1, dtype=np.intp)
        cells[inside] = self.cell_of[index[inside, 0], index[inside, 1]]
        return cells


def score_derivatives(
    grids: list[NdtGrid], source: np.ndarray, pose: np.ndarray
) -> tuple[float, np.ndarray, np.ndarray]:
    """NDT score of ``pose`` and its gradient and Hessian in ``(x, y, theta)``."""
    c, s = np.cos(pose[2]), np.sin(pose[2])
    moved = transform_points(source, pose)
    # d moved / d theta, and its second derivative
    d_theta = np.column_stack(
        (-s * source[:, 0] - c * source[:, 1], c * source[:, 0] - s * source[:, 1])
    )
    dd_theta = np.column_stack(
        (-c * source[:, 0] + s * source[:, 1], -s * source[:, 0] - c * source[:, 1])
    )
    score, gradient, hessian = 0.0, np.zeros(3), np.zeros((3, 3))
    for grid in grids:
        cells = grid.lookup(moved)
        hit = cells >= 0
        q = moved[hit] - grid.means[cells[hit]]
        inverse = grid.inverse_covariances[cells[hit]]
        jacobian = np.zeros((q.shape[0], 2, 3))
        jacobian[:, 0, 0] = jacobian[:, 1, 1] = 1.0
        jacobian[:, :, 2] = d_theta[hit]
        inverse_q = np.einsum("nij,nj->ni", inverse, q)
        weight = np.exp(-0.5 * np.einsum("ni,ni->n", q, inverse_q))
        slope = np.einsum("ni,nij->nj", inverse_q, jacobian)  # q^T S^-1 J
        curvature = np.einsum("nai,nab,nbj->nij", jacobian, inverse, jacobian)
        curvature[:, 2, 2] += np.einsum("ni,ni->n", inverse_q, dd_theta[hit])
        score += float(weight.sum())
        gradient -= weight @ slope
        hessian += np.einsum("n,ni,nj->ij", weight, slope, slope)
        hessian -= np.einsum("n,nij->ij", weight, curvature)
    return score, gradient, hessian


def newton_step(hessian: np.ndarray, gradient: np.ndarray, max_translation: float) -> np.ndarray:
    """A Newton step up the score, safe where the score is not concave.

    Where the Hessian has a non-negative eigenvalue (a saddle or a valley of the score)
    its magnitude is used instead, so the step still climbs; tiny eigenvalues are raised
    to a share of the largest. The step is then shortened to at most ``max_translation``
    (m) and ``MAX_ROTATION_STEP`` (rad), since the score is only locally quadratic.
    """
    values, vectors = np.linalg.eigh(-hessian)
    values = np.abs(values)
    values = np.maximum(values, EIGENVALUE_RATIO * max(values.max(), 1e-12))
    step = vectors @ ((vectors.T @ gradient) / values)
    shrink = max(np.hypot(step[0], step[1]) / max_translation, abs(step[2]) / MAX_ROTATION_STEP)
    return step / max(shrink, 1.0)


def build_grids(target: np.ndarray, cell_size: float) -> list[NdtGrid]:
    """The four grids over ``target``, shifted by half a cell along x, y and both."""
    half = 0.5 * cell_size
    shifts = np.array([[0.0, 0.0], [half, 0.0], [0.0, half], [half, half]])
    return [NdtGrid.build(target, cell_size, shift) for shift in shifts]


def climb(
    grids: list[NdtGrid],
    source: np.ndarray,
    pose: np.ndarray,
    max_iterations: int,
    tolerance: float,
) -> tuple[np.ndarray, int, bool]:
    """Newton iterations with backtracking from ``pose``: (pose, iterations, converged)."""
    score, gradient, hessian = score_derivatives(grids, source, pose)
    max_translation = 0.5 * grids[0].cell_size
    for iteration in range(1, max_iterations + 1):
        step = newton_step(hessian, gradient, max_translation)
        fraction = 1.0
        while fraction > 1e-3:
            candidate = pose + fraction * step
            new = score_derivatives(grids, source, candidate)
            if new[0] >= score:
                break
            fraction *= 0.5
        else:
            return pose, iteration, True  # no step along the Newton direction climbs
        moved = np.hypot(*(candidate[:2] - pose[:2])) + abs(candidate[2] - pose[2])
        pose, (score, gradient, hessian) = candidate, new
        if moved < tolerance:
            return pose, iteration, True
    return pose, max_iterations, False


def ndt(
    source_xy: ArrayLike,
    target_xy: ArrayLike,
    initial_pose: ArrayLike = (0.0, 0.0, 0.0),
    cell_size_m: float = 0.5,
    max_iterations: int = 50,
    tolerance: float = 1e-6,
    coarse_levels: int = 2,
    max_correspondence_m: float = 1.0,
) -> MatchResult:
    """2D NDT scan matching: Newton's method on the summed normal-distribution score.

    Coarse to fine: the pose is first refined on grids of ``2**k`` times the cell size,
    ``k = coarse_levels ... 1``, which widens the basin of convergence, then on the
    ``cell_size_m`` grids.

    Args:
        source_xy: points to align, m, shape ``(n, 2)``.
        target_xy: reference points, m, shape ``(m, 2)``; summarised per cell.
        initial_pose: starting guess ``(x, y, theta)``, m, m, rad.
        cell_size_m: side of the finest grid's cells, m.
        max_iterations: Newton iteration limit per level.
        tolerance: stop a level when a step moves the pose by less than this
            (translation in m plus rotation in rad).
        coarse_levels: coarser levels run first (0: the finest grid only).
        max_correspondence_m: only for the reported fitness (see
            :mod:`scaneval.match_result`).

    Returns:
        The :class:`MatchResult`; ``iterations`` counts all levels; ``converged`` is False
        when the finest level hit the iteration limit or the target had no cell with
        enough points.
    """
    source, target = finite_points(source_xy), finite_points(target_xy)
    pose = np.asarray(initial_pose, dtype=np.float64).copy()
    tree = cKDTree(target)
    if len(source) == 0 or len(target) < MIN_POINTS_PER_CELL:
        return result(pose, source, tree, 0, False, max_correspondence_m)
    total, converged = 0, False
    for level in range(coarse_levels, -1, -1):
        grids = build_grids(target, cell_size_m * 2**level)
        if len(grids[0].means) == 0:
            continue
        pose, iterations, converged = climb(grids, source, pose, max_iterations, tolerance)
        total += iterations
    return result(pose, source, tree, total, converged, max_correspondence_m)
