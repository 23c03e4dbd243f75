"""The IMU height gate: drop beams whose end point is outside a height band above the floor.

What Hector-SLAM and Cartographer users do when an IMU is present. Each beam's end point
is rotated by the measured pitch and roll (REP-103: positive pitch = nose down, positive
roll = left side up) into a level frame, and its height above the floor is

    z = h_s - x sin(pitch) + y cos(pitch) sin(roll)

with ``(x, y)`` the point in the sensor frame and ``h_s`` the scanner's height (``R =
R_y(pitch) R_x(roll)``, the ZYX convention with yaw left out).
"""

from __future__ import annotations

import math

import numpy as np

from pvfilter.scan import Scan


class ImuHeightGate:
    """Remove beams that end below or above a band of heights above the floor.

    Args:
        lidar_height_m: height of the scanner's origin above the floor when level, m.
        band_m: ``(low, high)``: beams ending lower than ``low`` or higher than ``high``
            above the floor are removed, m. The default keeps 5 cm to 2 m.
        axle_height_m: when given, the robot tilts about a point at this height (a TWSB's
            wheel axle), so the scanner's origin sinks to
            ``axle + (lidar_height - axle) cos(pitch) cos(roll)``; when ``None`` the
            origin stays at ``lidar_height_m``.
    """

    def __init__(
        self,
        lidar_height_m: float = 0.25,
        band_m: tuple[float, float] = (0.05, 2.0),
        axle_height_m: float | None = None,
    ) -> None:
        low, high = (float(b) for b in band_m)
        if not low < high:
            raise ValueError(f"band_m: need low < high, got {band_m}")
        if not math.isfinite(lidar_height_m) or lidar_height_m < 0.0:
            raise ValueError(
                f"lidar_height_m: must be a finite height >= 0 m, got {lidar_height_m}"
            )
        if axle_height_m is not None and not 0.0 <= axle_height_m <= lidar_height_m:
            raise ValueError(f"axle_height_m: must be in [0, lidar_height_m], got {axle_height_m}")
        self.lidar_height_m = float(lidar_height_m)
        self.band_m = (low, high)
        self.axle_height_m = axle_height_m

    def reset(self) -> None:
        """Nothing to forget: the gate keeps no state (present so every baseline reads alike)."""

    def sensor_height(self, pitch_rad: float, roll_rad: float) -> float:
        """Height of the scanner's origin above the floor, m."""
        if self.axle_height_m is None:
            return self.lidar_height_m
        arm = self.lidar_height_m - self.axle_height_m
        return self.axle_height_m + arm * math.cos(pitch_rad) * math.cos(roll_rad)

    def heights(self, scan: Scan, pitch_rad: float, roll_rad: float = 0.0) -> np.ndarray:
        """Height of every beam's end point above the floor, m (NaN for invalid beams)."""
        x, y = scan.points().T
        return (
            self.sensor_height(pitch_rad, roll_rad)
            - x * math.sin(pitch_rad)
            + y * math.cos(pitch_rad) * math.sin(roll_rad)
        )

    def process(
        self, scan: Scan, pitch_rad: float, roll_rad: float = 0.0, **context: object
    ) -> np.ndarray:
        """The beams to remove.

        Args:
            scan: the scan.
            pitch_rad: measured pitch, rad, positive nose down.
            roll_rad: measured roll, rad, positive left side up.
            **context: ignored, so every baseline can be called alike.

        Returns:
            Bool per beam, True where a valid beam ends outside the band.
        """
        height = self.heights(scan, pitch_rad, roll_rad)
        low, high = self.band_m
        with np.errstate(invalid="ignore"):
            return (height < low) | (height > high)
