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

from twsb_sim.kernel import kernel


def poses_from_quats(positions: np.ndarray, quats_wxyz: np.ndarray) -> np.ndarray:
    """``(k, 9)`` rows: position, x axis, y axis of positions ``(k, 3)`` and unit
    quaternions ``(k, 4)`` (w, x, y, z)."""
    q = np.asarray(quats_wxyz, dtype=np.float64).reshape(-1, 4)
    return _poses(np.asarray(positions, dtype=np.float64), q)


@kernel
def _poses(positions: np.ndarray, quats: np.ndarray) -> np.ndarray:
    """The rotation matrix's first two columns from a unit quaternion (w, x, y, z): x axis
    (1 - 2(yy + zz), 2(xy + wz), 2(xz - wy)), y axis (2(xy - wz), 1 - 2(xx + zz),
    2(yz + wx)), each sum taken as (second product) + (first) as numpy added them."""
    out = np.empty((len(quats), 9))
    for r in range(len(quats)):
        w, x, y, z = quats[r, 0], quats[r, 1], quats[r, 2], quats[r, 3]
        out[r, 0], out[r, 1], out[r, 2] = positions[r, 0], positions[r, 1], positions[r, 2]
        out[r, 3] = 1.0 - (z * z + y * y) * 2.0
        out[r, 4] = (w * z + x * y) * 2.0
        out[r, 5] = (-(w * y) + x * z) * 2.0
        out[r, 6] = (-(w * z) + x * y) * 2.0
        out[r, 7] = 1.0 - (z * z + x * x) * 2.0
        out[r, 8] = (w * x + y * z) * 2.0
    return out


@kernel
def _beams(
    poses: np.ndarray, t_first_s: float, dt_s: float, times_s: np.ndarray, dirs_sensor: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Each beam's origin and unit direction in the world (see :meth:`PoseTrack.beams`)."""
    last = len(poses) - 1
    top = max(last - 1, 0)
    origins, dirs = np.empty((len(times_s), 3)), np.empty((len(times_s), 3))
    pose = np.empty(9)
    for b in range(len(times_s)):
        where = (times_s[b] - t_first_s) / dt_s
        where = min(max(where, 0.0), float(last))  # held constant outside the span
        j = min(int(where), top)
        a = where - j
        after = j + 1 if last else j
        for k in range(9):
            pose[k] = poses[j, k] + a * (poses[after, k] - poses[j, k])
        # a beam in the x-y plane needs only the sensor's x and y axes: d = c x + s y
        c, s = dirs_sensor[b, 0], dirs_sensor[b, 1]
        d0 = c * pose[3] + s * pose[6]
        d1 = c * pose[4] + s * pose[7]
        d2 = c * pose[5] + s * pose[8]
        norm = math.sqrt((d0 * d0 + d2 * d2) + d1 * d1)
        dirs[b, 0], dirs[b, 1], dirs[b, 2] = d0 / norm, d1 / norm, d2 / norm
        origins[b, 0], origins[b, 1], origins[b, 2] = pose[0], pose[1], pose[2]
    return origins, dirs


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
        times = np.asarray(times_s, dtype=np.float64)
        return _beams(self.poses, self.t_first_s, self.dt_s, times, dirs_sensor)
