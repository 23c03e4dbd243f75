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


def axes_from_quats(quats_wxyz: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The rotated x and y axes ``(k, 3)`` of unit quaternions ``(k, 4)`` (w, x, y, z)."""
    w, x, y, z = np.asarray(quats_wxyz, dtype=np.float64).reshape(-1, 4).T
    x_axes = np.empty((len(w), 3))
    y_axes = np.empty((len(w), 3))
    x_axes[:, 0] = 1 - 2 * (y * y + z * z)
    x_axes[:, 1] = 2 * (x * y + w * z)
    x_axes[:, 2] = 2 * (x * z - w * y)
    y_axes[:, 0] = 2 * (x * y - w * z)
    y_axes[:, 1] = 1 - 2 * (x * x + z * z)
    y_axes[:, 2] = 2 * (y * z + w * x)
    return x_axes, y_axes


@dataclass(frozen=True, eq=False)
class PoseTrack:
    """Sensor poses at evenly spaced times ``t_first_s + j * dt_s``, ``j = 0 .. m - 1``.

    Attributes:
        t_first_s: time of the first pose, s.
        dt_s: time between poses, s (> 0).
        positions: ``(m, 3)`` sensor origin in the world, m.
        x_axes: ``(m, 3)`` the sensor's x axis (beam angle 0) in the world.
        y_axes: ``(m, 3)`` the sensor's y axis (beam angle 90 deg) in the world.
    """

    t_first_s: float
    dt_s: float
    positions: np.ndarray
    x_axes: np.ndarray
    y_axes: np.ndarray

    def __post_init__(self) -> None:
        m = len(self.positions)
        if not m or len(self.x_axes) != m or len(self.y_axes) != m:
            raise ValueError("positions: expected as many poses as axes, at least one")
        if not self.dt_s > 0:
            raise ValueError(f"dt_s: expected a value > 0, got {self.dt_s!r}")

    @classmethod
    def from_quats(
        cls, t_first_s: float, dt_s: float, positions: np.ndarray, quats_wxyz: np.ndarray
    ) -> PoseTrack:
        """A track from positions and orientations as unit quaternions (w, x, y, z)."""
        return cls(t_first_s, dt_s, np.asarray(positions, float), *axes_from_quats(quats_wxyz))

    def _lerp(self, times_s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Position, x axis and y axis at each time, ``(k, 3)`` each (axes not renormalised)."""
        last = len(self.positions) - 1
        where = (np.asarray(times_s, float) - self.t_first_s) / self.dt_s
        where = np.minimum(np.maximum(where, 0.0), last)  # cheaper than np.clip's wrapper
        j = np.minimum(where.astype(np.intp), max(last - 1, 0))
        a = (where - j)[:, None]
        j1 = np.minimum(j + 1, last)
        out = []
        for values in (self.positions, self.x_axes, self.y_axes):
            before = values.take(j, axis=0)
            out.append(before + a * (values.take(j1, axis=0) - before))
        return out[0], out[1], out[2]

    def at(self, time_s: float) -> tuple[np.ndarray, np.ndarray]:
        """Position ``(3,)`` and sensor-to-world rotation matrix ``(3, 3)`` at ``time_s``."""
        last = len(self.positions) - 1
        where = min(max((time_s - self.t_first_s) / self.dt_s, 0.0), float(last))
        j = min(int(where), max(last - 1, 0))
        k, a = min(j + 1, last), where - j
        p, x, y = ((v[j] + a * (v[k] - v[j])).tolist()
                   for v in (self.positions, self.x_axes, self.y_axes))  # fmt: skip
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
        origins, x_axes, y_axes = self._lerp(times_s)
        dirs = dirs_sensor[:, :1] * x_axes + dirs_sensor[:, 1:2] * y_axes
        dirs /= np.sqrt(np.einsum("ki,ki->k", dirs, dirs))[:, None]
        return origins, dirs
