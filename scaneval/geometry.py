"""SE(2) poses and scan points: the small geometry every matcher and metric shares.

A pose is a ``(3,)`` array ``(x, y, theta)`` (m, m, rad, counter-clockwise positive,
REP-103 axes). Read ``pose`` as "frame B in frame A": :func:`transform_points` maps points
given in B into A, and ``compose(a, b)`` is ``a`` followed by ``b`` (``a @ b`` as
matrices).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from pvfilter.scan import Scan


def _pose(pose: ArrayLike) -> np.ndarray:
    pose = np.asarray(pose, dtype=np.float64)
    if pose.shape != (3,):
        raise ValueError(f"pose: must be (x, y, theta), got shape {pose.shape}")
    return pose


def wrap_angle(angle: ArrayLike) -> np.ndarray:
    """Angles wrapped into ``[-pi, pi)``, rad."""
    return (np.asarray(angle, dtype=np.float64) + np.pi) % (2.0 * np.pi) - np.pi


def se2_matrix(pose: ArrayLike) -> np.ndarray:
    """The 3x3 homogeneous matrix of a pose ``(x, y, theta)``."""
    x, y, theta = _pose(pose)
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, -s, x], [s, c, y], [0.0, 0.0, 1.0]])


def pose_from_matrix(matrix: ArrayLike) -> np.ndarray:
    """The pose ``(x, y, theta)`` of a 3x3 homogeneous (or 2x3) SE(2) matrix."""
    matrix = np.asarray(matrix, dtype=np.float64)
    return np.array([matrix[0, 2], matrix[1, 2], np.arctan2(matrix[1, 0], matrix[0, 0])])


def compose(a: ArrayLike, b: ArrayLike) -> np.ndarray:
    """The pose ``a * b``: ``b`` expressed in the frame ``a`` is expressed in, theta wrapped."""
    a, b = _pose(a), _pose(b)
    c, s = np.cos(a[2]), np.sin(a[2])
    return np.array(
        [
            a[0] + c * b[0] - s * b[1],
            a[1] + s * b[0] + c * b[1],
            float(wrap_angle(a[2] + b[2])),
        ]
    )


def invert(pose: ArrayLike) -> np.ndarray:
    """The inverse pose: ``compose(pose, invert(pose))`` is the identity."""
    x, y, theta = _pose(pose)
    c, s = np.cos(theta), np.sin(theta)
    return np.array([-c * x - s * y, s * x - c * y, float(wrap_angle(-theta))])


def transform_points(points_xy: np.ndarray, pose: ArrayLike) -> np.ndarray:
    """Points mapped by a pose: ``R(theta) p + (x, y)``.

    Args:
        points_xy: points, m, shape ``(n, 2)``.
        pose: ``(x, y, theta)`` of the points' frame in the target frame.

    Returns:
        The mapped points, m, shape ``(n, 2)`` (NaN rows stay NaN).
    """
    x, y, theta = _pose(pose)
    c, s = np.cos(theta), np.sin(theta)
    points_xy = np.asarray(points_xy, dtype=np.float64).reshape(-1, 2)
    return points_xy @ np.array([[c, s], [-s, c]]) + np.array([x, y])


def scan_points(scan: Scan, mask: np.ndarray | None = None) -> np.ndarray:
    """The finite, valid end points of a scan in the sensor frame.

    Args:
        scan: the scan (REP-117: NaN, +/-inf and out-of-limits ranges are not points).
        mask: optional bool per beam; beams where it is True are dropped (e.g. a filter's
            ``removed`` mask).

    Returns:
        Points, m, shape ``(m, 2)``, in beam order.
    """
    keep = scan.valid_mask()
    if mask is not None:
        mask = np.asarray(mask, dtype=bool)
        if mask.shape != keep.shape:
            raise ValueError(f"mask: must have one value per beam ({keep.size}), got {mask.size}")
        keep &= ~mask
    return scan.points()[keep]
