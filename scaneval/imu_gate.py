"""The IMU height gate: drop beams whose end point is outside a height band above the floor.

What Hector-SLAM and Cartographer users do when an IMU is present. Each beam's end point
is rotated by the measured pitch and roll (REP-103: positive pitch = nose down, positive
roll = left side up) into a level frame, and its height above the floor is

    z = h_s - x sin(pitch) + y cos(pitch) sin(roll)

with ``(x, y)`` the point in the sensor frame and ``h_s`` the scanner's height (``R =
R_y(pitch) R_x(roll)``, the ZYX convention with yaw left out).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from numpy.typing import ArrayLike

from pvfilter.checks import check_number
from pvfilter.contract import check_attitude
from pvfilter.result import FilterResult, without_removed
from pvfilter.scan import Scan


@dataclasses.dataclass(frozen=True)
class ImuGateParams:
    """Parameters of :class:`ImuHeightGate`.

    Invalid values raise ``ValueError("<field>: <what was expected>, got <value>")``.

    Attributes:
        lidar_height_m: height of the scanner's origin above the floor when level, m.
        band_low_m: beams ending lower than this above the floor are removed, m.
        band_high_m: beams ending higher than this above the floor are removed, m.
        axle_height_m: the robot tilts about a point at this height (a TWSB's wheel axle),
            so the scanner's origin sinks to ``axle + (lidar_height - axle) cos(pitch)
            cos(roll)``; equal to ``lidar_height_m``, the origin stays where it is. The
            default is the improved filter's (a small home robot's wheel radius).
    """

    lidar_height_m: float = 0.25  # m
    band_low_m: float = 0.05  # m
    band_high_m: float = 2.0  # m
    axle_height_m: float = 0.08  # m

    def __post_init__(self) -> None:
        check_number("lidar_height_m", self.lidar_height_m, lower=0.0, unit="m", closed=True)
        check_number("band_low_m", self.band_low_m, lower=-math.inf, unit="m")
        check_number(
            "band_high_m", self.band_high_m, lower=self.band_low_m, unit="m", below="band_low_m"
        )
        check_number("axle_height_m", self.axle_height_m, lower=0.0, unit="m", closed=True)
        if self.axle_height_m > self.lidar_height_m:
            raise ValueError(
                f"axle_height_m: must be <= lidar_height_m ({self.lidar_height_m} m), "
                f"got {self.axle_height_m}"
            )


class ImuHeightGate:
    """Remove beams that end below or above a band of heights above the floor.

    A :class:`pvfilter.ScanFilter` that needs the robot inputs ``pitch_rad`` (and
    ``roll_rad``). Its ``scores`` are how far outside the band each beam ends, m (0 inside
    it): a beam is removed exactly when its score is above 0.

    Args:
        params: the parameters; :class:`ImuGateParams` defaults when omitted.
    """

    def __init__(self, params: ImuGateParams | None = None) -> None:
        self.params = params if params is not None else ImuGateParams()

    def reset(self) -> None:
        """Nothing to forget: the gate keeps no state."""

    def sensor_height(self, pitch_rad: float, roll_rad: float) -> float:
        """Height of the scanner's origin above the floor, m."""
        axle = self.params.axle_height_m
        arm = self.params.lidar_height_m - axle
        return axle + arm * math.cos(pitch_rad) * math.cos(roll_rad)

    def heights(self, scan: Scan, pitch_rad: float, roll_rad: float = 0.0) -> np.ndarray:
        """Height of every beam's end point above the floor, m (NaN for invalid beams)."""
        x, y = scan.points().T
        return (
            self.sensor_height(pitch_rad, roll_rad)
            - x * math.sin(pitch_rad)
            + y * math.cos(pitch_rad) * math.sin(roll_rad)
        )

    def process(
        self,
        scan: Scan,
        *,
        pitch_rad: float | None = None,
        roll_rad: float | None = None,
        pose_sensor_in_odom: ArrayLike | None = None,
    ) -> FilterResult:
        """Remove the beams that end outside the band.

        Args:
            scan: the scan.
            pitch_rad: measured pitch, rad, positive nose down (required).
            roll_rad: measured roll, rad, positive left side up (0 when not given).
            pose_sensor_in_odom: ignored.

        Raises:
            ValueError: no pitch given.
        """
        attitude = check_attitude(pitch_rad, roll_rad)
        if attitude is None:
            raise ValueError("pitch_rad: the IMU height gate needs the robot's attitude")
        height = self.heights(scan, *attitude)
        below = self.params.band_low_m - height
        above = height - self.params.band_high_m
        scores = np.nan_to_num(np.fmax(np.fmax(below, above), 0.0), nan=0.0)
        removed = scores > 0.0
        return FilterResult(without_removed(scan, removed), removed, scores)
