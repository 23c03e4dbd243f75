"""A bag's robot inputs at each scan's stamp, as the filters take them (:mod:`pvfilter.contract`).

- ``pitch_rad``, ``roll_rad`` from a ``sensor_msgs/Imu``'s orientation: the latest
  sample stamped at or before the scan (what an estimator had when the scan began);
  Z-Y-X angles of REP-103, pitch positive nose down. The IMU's frame is taken to be
  aligned with the body, as an attitude estimator publishes it.
- ``pose_sensor_in_odom`` from a ``nav_msgs/Odometry``: the pose of its child frame (the
  robot's base) in odom, between the updates around the scan's stamp as ``tf``
  interpolates them, composed with the LiDAR's mounting in that base frame.

Scans stamped before the first sample of a stream get no value from it (the filter runs
without that input until the stream starts).
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np


def pitch_roll(quat_wxyz: np.ndarray) -> tuple[float, float]:
    """Pitch (positive nose down) and roll (positive left side up), rad, of a unit
    quaternion ``(w, x, y, z)``: Z-Y-X Euler angles of REP-103."""
    w, x, y, z = (float(v) for v in quat_wxyz)
    pitch = math.asin(max(-1.0, min(1.0, 2.0 * (w * y - z * x))))
    roll = math.atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))
    return pitch, roll


def yaw_of(quat_wxyz: np.ndarray) -> float:
    """Heading, rad, of the x axis a quaternion ``(w, x, y, z)`` rotates, in the plane."""
    w, x, y, z = (float(v) for v in quat_wxyz)
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def compose_se2(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The planar pose ``a ∘ b``: ``b`` (x m, y m, yaw rad) given in ``a``'s frame."""
    c, s = math.cos(a[2]), math.sin(a[2])
    return np.array(
        [
            a[0] + c * b[0] - s * b[1],
            a[1] + s * b[0] + c * b[1],
            math.remainder(a[2] + b[2], math.tau),
        ]
    )


class AttitudeTrack:
    """IMU attitudes by stamp: the latest at or before a stamp.

    Args:
        stamps_ns: the samples' ``header.stamp``, ns (any order).
        quats_wxyz: their orientations, shape ``(m, 4)``.
    """

    def __init__(self, stamps_ns: np.ndarray, quats_wxyz: np.ndarray) -> None:
        order = np.argsort(stamps_ns, kind="stable")
        self.stamps_ns = np.asarray(stamps_ns, dtype=np.int64)[order]
        self._quats = np.asarray(quats_wxyz, dtype=np.float64).reshape(-1, 4)[order]

    def at(self, stamp_ns: int) -> dict[str, float]:
        """``{"pitch_rad", "roll_rad"}`` of the latest sample at or before ``stamp_ns``
        (empty before the first sample)."""
        j = int(np.searchsorted(self.stamps_ns, stamp_ns, side="right"))
        if j == 0:
            return {}
        pitch, roll = pitch_roll(self._quats[j - 1])
        return {"pitch_rad": pitch, "roll_rad": roll}


class PoseTrack:
    """Odometry poses by stamp, interpolated between updates, composed with the mounting.

    Args:
        stamps_ns: the updates' ``header.stamp``, ns (any order).
        poses: the base's planar poses in odom ``(x m, y m, yaw rad)``, shape ``(m, 3)``.
        mount: the LiDAR's planar pose in the base frame ``(x m, y m, yaw rad)``.
    """

    def __init__(self, stamps_ns: np.ndarray, poses: np.ndarray, mount: np.ndarray) -> None:
        order = np.argsort(stamps_ns, kind="stable")
        self.stamps_ns = np.asarray(stamps_ns, dtype=np.int64)[order]
        self._poses = np.asarray(poses, dtype=np.float64).reshape(-1, 3)[order]
        self.mount = np.asarray(mount, dtype=np.float64)

    def at(self, stamp_ns: int) -> dict[str, np.ndarray]:
        """``{"pose_sensor_in_odom"}`` at ``stamp_ns``: interpolated between the updates
        around it, the last one after the end (empty before the first update)."""
        stamps, poses = self.stamps_ns, self._poses
        j = int(np.searchsorted(stamps, stamp_ns, side="right"))
        if j == 0:
            return {}
        base = poses[j - 1]
        if j < len(stamps) and stamps[j] > stamps[j - 1] and stamps[j - 1] < stamp_ns:
            a = (stamp_ns - stamps[j - 1]) / (stamps[j] - stamps[j - 1])
            turn = math.remainder(poses[j, 2] - base[2], math.tau)
            base = np.array(
                [
                    base[0] + a * (poses[j, 0] - base[0]),
                    base[1] + a * (poses[j, 1] - base[1]),
                    math.remainder(base[2] + a * turn, math.tau),
                ]
            )
        return {"pose_sensor_in_odom": compose_se2(base, self.mount)}


def _matrix(quat_wxyz: np.ndarray) -> np.ndarray:
    w, x, y, z = np.asarray(quat_wxyz, dtype=np.float64) / np.linalg.norm(quat_wxyz)
    return np.array(
        [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
         [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
         [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]
    )  # fmt: skip


def _to_root(frame: str, parents: Mapping[str, tuple[str, np.ndarray]]) -> tuple[str, np.ndarray]:
    """The root of ``frame``'s tree and ``frame``'s pose in it (4x4)."""
    pose, seen = np.eye(4), {frame}
    while frame in parents:
        frame, transform = parents[frame]
        if frame in seen:
            break  # a loop in the tree: stop at the frame seen again
        seen.add(frame)
        step = np.eye(4)
        step[:3, :3], step[:3, 3] = _matrix(transform[3:]), transform[:3]
        pose = step @ pose
    return frame, pose


def mount_in_base(
    transforms: Mapping[tuple[str, str], np.ndarray], base: str, sensor: str
) -> np.ndarray | None:
    """The planar pose ``(x m, y m, yaw rad)`` of frame ``sensor`` in frame ``base``.

    Args:
        transforms: ``(parent, child)`` → ``(x, y, z, qw, qx, qy, qz)`` of the child in the
            parent, as ``tf`` messages give them.
        base: the odometry's child frame (the robot's base).
        sensor: the scans' frame.

    Returns:
        The 3-D pose flattened onto the base's plane (translation x, y; heading of the
        sensor's x axis), or None when no chain of transforms joins the two frames.
    """
    if base == sensor:
        return np.zeros(3)
    parents = {child: (parent, np.asarray(t)) for (parent, child), t in transforms.items()}
    root_base, base_pose = _to_root(base, parents)
    root_sensor, sensor_pose = _to_root(sensor, parents)
    if root_base != root_sensor:
        return None
    relative = np.linalg.solve(base_pose, sensor_pose)
    return np.array([relative[0, 3], relative[1, 3], math.atan2(relative[1, 0], relative[0, 0])])
