"""The sensor's pose during a LiDAR revolution: recorded per physics step, looked up per beam.

A rotating LiDAR measures beam ``i`` at ``stamp + i * time_increment``; in between the
robot moves, turns and pitches. :class:`PoseTrack` holds the ``lidar`` site's pose at
the physics steps (500 Hz, evenly spaced) around a revolution and gives it at any time:
the position and the sensor's x and y axes linearly interpolated between the two
neighbouring steps (a beam lies in the x-y plane, so these two axes turn it into the
world; the rotation within one 2 ms step is below 0.01 rad, so the blended, renormalised
direction is off the exact one by ~1e-6 rad), held constant outside the recorded span
(the robot stood still before its reset).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

# the rotation matrix's first two columns from a unit quaternion (w, x, y, z): x axis
# (1 - 2(yy + zz), 2(xy + wz), 2(xz - wy)), y axis (2(xy - wz), 1 - 2(xx + zz), 2(yz + wx));
# all six as 2 (a + sign b) from the outer product q q' (flat index 4 i + j of q_i q_j)
_A = [10, 6, 7, 6, 5, 11]  # yy xy xz xy xx yz
_B = [15, 3, 2, 3, 15, 1]  # zz wz wy wz zz wx
_SIGN = np.array([1.0, 1.0, -1.0, -1.0, 1.0, 1.0])


def poses_from_quats(positions: np.ndarray, quats_wxyz: np.ndarray) -> np.ndarray:
    """``(k, 9)`` rows: position, x axis, y axis of positions ``(k, 3)`` and unit
    quaternions ``(k, 4)`` (w, x, y, z)."""
    q = np.asarray(quats_wxyz, dtype=np.float64).reshape(-1, 4)
    products = (q[:, :, None] * q[:, None, :]).reshape(-1, 16)  # one call, not 18
    out = np.empty((len(q), 9))
    out[:, :3] = positions
    axes = out[:, 3:]
    np.multiply(products.take(_B, axis=1), _SIGN, out=axes)
    axes += products.take(_A, axis=1)  # a + (-b) is a - b exactly
    axes *= 2.0
    np.subtract(1.0, axes[:, ::4], out=axes[:, ::4])  # the two diagonal terms
    return out


@dataclass(frozen=True, eq=False)
class PoseTrack:
    """Sensor poses at evenly spaced times ``t_first_s + j * dt_s``, ``j = 0 .. m - 1``.

    Attributes:
        t_first_s: time of the first pose, s.
        dt_s: time between poses, s (> 0).
        poses: ``(m, 9)`` per pose: the sensor origin in the world (m), its x axis (beam
            angle 0) and its y axis (beam angle 90 deg) in the world.
    """

    t_first_s: float
    dt_s: float
    poses: np.ndarray

    def __post_init__(self) -> None:
        if self.poses.ndim != 2 or self.poses.shape[1] != 9 or not len(self.poses):
            raise ValueError(f"poses: expected an (m >= 1, 9) array, got {self.poses.shape}")
        if not self.dt_s > 0:
            raise ValueError(f"dt_s: expected a value > 0, got {self.dt_s!r}")

    @classmethod
    def from_quats(
        cls, t_first_s: float, dt_s: float, positions: np.ndarray, quats_wxyz: np.ndarray
    ) -> PoseTrack:
        """A track from positions and orientations as unit quaternions (w, x, y, z)."""
        return cls(t_first_s, dt_s, poses_from_quats(positions, quats_wxyz))

    def _lerp(self, times_s: np.ndarray) -> np.ndarray:
        """``(k, 9)`` poses at each time (axes not renormalised)."""
        last = len(self.poses) - 1
        where = (np.asarray(times_s, float) - self.t_first_s) / self.dt_s
        where = np.minimum(np.maximum(where, 0.0), last)  # cheaper than np.clip's wrapper
        j = np.minimum(where.astype(np.intp), max(last - 1, 0))
        before = self.poses.take(j, axis=0)
        # the pose's change over each step, gathered: one gather and one subtraction of
        # (k, 9) fewer than gathering the pose after the step too
        steps = self.poses[1:] - self.poses[:-1] if last else self.poses - self.poses
        return before + (where - j)[:, None] * steps.take(j, axis=0)

    def at(self, time_s: float) -> tuple[np.ndarray, np.ndarray]:
        """Position ``(3,)`` and sensor-to-world rotation matrix ``(3, 3)`` at ``time_s``."""
        last = len(self.poses) - 1
        where = min(max((time_s - self.t_first_s) / self.dt_s, 0.0), float(last))
        j = min(int(where), max(last - 1, 0))
        k, a = min(j + 1, last), where - j
        pose = (self.poses[j] + a * (self.poses[k] - self.poses[j])).tolist()
        p, x, y = pose[:3], pose[3:6], pose[6:]
        norm = math.sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2])
        x = [c / norm for c in x]
        z = [x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]]
        norm = math.sqrt(z[0] * z[0] + z[1] * z[1] + z[2] * z[2])
        z = [c / norm for c in z]
        y = [z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]]
        return np.array(p), np.array([x, y, z]).T

    def beams(self, times_s: np.ndarray, dirs_sensor: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Each beam's origin ``(k, 3)`` and unit direction in the world ``(k, 3)``.

        Args:
            times_s: ``(k,)`` when each beam was measured, s.
            dirs_sensor: ``(k, 3)`` unit beam directions in the sensor's x-y plane.
        """
        poses = self._lerp(times_s)
        # a beam in the x-y plane needs only the sensor's x and y axes: d = c x + s y
        dirs = dirs_sensor[:, :1] * poses[:, 3:6] + dirs_sensor[:, 1:2] * poses[:, 6:9]
        dirs /= np.sqrt(np.einsum("ki,ki->k", dirs, dirs))[:, None]
        return poses[:, :3], dirs
