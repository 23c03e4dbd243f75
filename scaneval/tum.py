"""TUM trajectory files: one pose per line, ``timestamp tx ty tz qx qy qz qw``.

The format of the TUM RGB-D benchmark, read by evo and most SLAM evaluation tools. Planar
poses ``(x, y, theta)`` are written at z = 0 with the quaternion of a rotation about z.
"""

from __future__ import annotations

import os

import numpy as np
from numpy.typing import ArrayLike


def xyz_quat_from_se2(poses_se2: ArrayLike) -> np.ndarray:
    """``(n, 7)`` rows ``tx ty tz qx qy qz qw`` of ``(n, 3)`` planar poses (z = 0)."""
    poses_se2 = np.asarray(poses_se2, dtype=np.float64).reshape(-1, 3)
    half = 0.5 * poses_se2[:, 2]
    zeros = np.zeros(len(poses_se2))
    return np.column_stack(
        (poses_se2[:, 0], poses_se2[:, 1], zeros, zeros, zeros, np.sin(half), np.cos(half))
    )


def se2_from_xyz_quat(xyz_quat: ArrayLike) -> np.ndarray:
    """``(n, 3)`` planar poses ``(x, y, yaw)`` of ``(n, 7)`` TUM rows (z and tilt dropped)."""
    xyz_quat = np.asarray(xyz_quat, dtype=np.float64).reshape(-1, 7)
    qx, qy, qz, qw = xyz_quat[:, 3:].T
    yaw = np.arctan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy**2 + qz**2))
    return np.column_stack((xyz_quat[:, 0], xyz_quat[:, 1], yaw))


def write_tum(path: str | os.PathLike, stamps: ArrayLike, poses_se2_or_xyz_quat: ArrayLike) -> None:
    """Write a trajectory as a TUM file.

    Args:
        path: the file to write (overwritten).
        stamps: time of every pose, s, shape ``(n,)``.
        poses_se2_or_xyz_quat: ``(n, 3)`` planar poses ``(x, y, theta)`` (m, m, rad) or
            ``(n, 7)`` rows ``tx ty tz qx qy qz qw``.
    """
    stamps = np.asarray(stamps, dtype=np.float64).reshape(-1)
    poses = np.asarray(poses_se2_or_xyz_quat, dtype=np.float64)
    if poses.ndim != 2 or poses.shape[1] not in (3, 7) or len(poses) != stamps.size:
        raise ValueError(
            f"poses_se2_or_xyz_quat: must be (n, 3) or (n, 7) with n = {stamps.size} stamps, "
            f"got {poses.shape}"
        )
    rows = xyz_quat_from_se2(poses) if poses.shape[1] == 3 else poses
    np.savetxt(path, np.column_stack((stamps, rows)), fmt="%.9f", delimiter=" ")


def read_tum(path: str | os.PathLike) -> tuple[np.ndarray, np.ndarray]:
    """Read a TUM file (``#`` comment lines are skipped).

    Returns:
        ``(stamps, xyz_quat)``: times, s, shape ``(n,)``, and rows ``tx ty tz qx qy qz qw``,
        shape ``(n, 7)``; :func:`se2_from_xyz_quat` turns them into planar poses.
    """
    table = np.loadtxt(path, dtype=np.float64, comments="#", ndmin=2)
    if table.size == 0:
        return np.zeros(0), np.zeros((0, 7))
    if table.shape[1] != 8:
        raise ValueError(f"{os.fspath(path)}: expected 8 columns per line, got {table.shape[1]}")
    return table[:, 0], table[:, 1:]
