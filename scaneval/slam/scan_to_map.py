"""Gauss-Newton scan-to-map matching on an occupancy grid (Kohlbrecher et al. 2011, §IV-B).

The pose ``xi = (x, y, psi)`` of the sensor in the map minimises
``sum_i (1 - M(S_i(xi)))^2`` where ``S_i(xi) = R(psi) s_i + (x, y)`` is scan point ``s_i``
in the map and ``M`` the bilinearly interpolated occupancy probability. One Gauss-Newton
step is ``dxi = H^-1 sum_i J_i^T (1 - M(S_i))`` with ``J_i = grad M(S_i) dS_i/dxi`` and
``H = sum_i J_i^T J_i``.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from scaneval.slam.grid import OccupancyGrid

OCCUPIED_PROBABILITY = 0.6  # a point reading at least this map value lies on a known obstacle


@dataclasses.dataclass(frozen=True)
class ScanToMapResult:
    """The outcome of matching one scan against one map.

    Attributes:
        pose: ``(x, y, psi)`` of the sensor in the map frame, m, m, rad.
        hessian: ``H`` at the final pose (its inverse is Hector's pose covariance), 3x3.
        score: mean map value ``M`` at the matched points, in [0, 1].
        inlier_fraction: share of the points on a known obstacle
            (``M >= OCCUPIED_PROBABILITY``) after matching.
        iterations: Gauss-Newton steps taken.
        ok: False when a step could not be taken (a degenerate ``H``: no map gradient
            under the points, e.g. an empty map or a scan outside it).
    """

    pose: np.ndarray
    hessian: np.ndarray
    score: float
    inlier_fraction: float
    iterations: int
    ok: bool


def _map_terms(
    grid: OccupancyGrid, points_xy: np.ndarray, pose: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Map values ``M``, Jacobians ``J`` (n, 3) and residuals ``1 - M`` at ``pose``."""
    c, s = np.cos(pose[2]), np.sin(pose[2])
    px, py = points_xy[:, 0], points_xy[:, 1]
    world = np.column_stack((c * px - s * py + pose[0], s * px + c * py + pose[1]))
    values, gradient = grid.interpolate(world)
    # dS/dpsi = (-s px - c py, c px - s py)
    d_psi = gradient[:, 0] * (-s * px - c * py) + gradient[:, 1] * (c * px - s * py)
    jacobian = np.column_stack((gradient, d_psi))
    return values, jacobian, 1.0 - values


def match_scan_to_map(
    grid: OccupancyGrid,
    points_xy: np.ndarray,
    initial_pose: np.ndarray,
    iterations: int = 5,
    max_rotation_step_rad: float = 0.2,
) -> ScanToMapResult:
    """Align scan points to a map by Gauss-Newton from ``initial_pose``.

    Args:
        grid: the map.
        points_xy: scan end points in the sensor frame, m, shape ``(n, 2)``, finite.
        initial_pose: starting guess ``(x, y, psi)`` of the sensor in the map.
        iterations: Gauss-Newton steps.
        max_rotation_step_rad: a step turns by at most this much (Hector's 0.2 rad), so
            one bad step cannot spin the estimate around.

    Returns:
        The :class:`ScanToMapResult`.
    """
    pose = np.array(initial_pose, dtype=np.float64)
    ok, taken = True, 0
    for _ in range(iterations):
        _, jacobian, residual = _map_terms(grid, points_xy, pose)
        hessian = jacobian.T @ jacobian
        if hessian[0, 0] <= 0.0 or hessian[1, 1] <= 0.0:
            ok = False
            break
        try:
            step = np.linalg.solve(hessian, jacobian.T @ residual)
        except np.linalg.LinAlgError:
            ok = False
            break
        if not np.all(np.isfinite(step)):
            ok = False
            break
        step[2] = np.clip(step[2], -max_rotation_step_rad, max_rotation_step_rad)
        pose += step
        taken += 1
    pose[2] = (pose[2] + np.pi) % (2.0 * np.pi) - np.pi
    values, jacobian, _ = _map_terms(grid, points_xy, pose)
    return ScanToMapResult(
        pose=pose,
        hessian=jacobian.T @ jacobian,
        score=float(values.mean()) if len(values) else 0.0,
        inlier_fraction=float(np.mean(values >= OCCUPIED_PROBABILITY)) if len(values) else 0.0,
        iterations=taken,
        ok=ok,
    )
