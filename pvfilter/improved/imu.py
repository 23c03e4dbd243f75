"""The optional IMU input: with pitch and roll known, the floor's line is predicted.

A point ``(x, y)`` of the scan plane lies ``z = h_s - x sin p + y cos p sin r`` above the
floor (p pitch, positive nose down; r roll, positive left side up; REP-103), where
``h_s`` is the scanner's height: ``axle + (h - axle) cos p cos r`` for a robot that tilts
about its wheel axle. A return with ``z`` near 0 is on the floor. Unlike a height band
around the scan plane, this test does not remove walls that a tilted plane meets high or
low: only hits on the floor itself.
"""

from __future__ import annotations

import math

import numpy as np

from pvfilter.improved.params import ImprovedParams


def scanner_height(pitch_rad: float, roll_rad: float, params: ImprovedParams) -> float:
    """Height of the scanner's origin above the floor, m, for the robot tilted as given."""
    arm = params.lidar_height_m - params.axle_height_m
    return params.axle_height_m + arm * math.cos(pitch_rad) * math.cos(roll_rad)


def heights_above_floor(
    points: np.ndarray, pitch_rad: float, roll_rad: float, params: ImprovedParams
) -> np.ndarray:
    """Height above the floor of each point of the scan plane, m.

    Args:
        points: sensor-frame points, m, ``(k, 2)``.
        pitch_rad: pitch, rad, positive nose down.
        roll_rad: roll, rad, positive left side up.
        params: ``lidar_height_m`` and ``axle_height_m`` are used.
    """
    return (
        scanner_height(pitch_rad, roll_rad, params)
        - points[:, 0] * math.sin(pitch_rad)
        + points[:, 1] * math.cos(pitch_rad) * math.sin(roll_rad)
    )


def floor_points(
    points: np.ndarray, pitch_rad: float, roll_rad: float, params: ImprovedParams
) -> np.ndarray:
    """Per point: it lies on the floor.

    That is, less than ``imu_floor_tolerance_m`` plus ``range * sin(imu_angle_error_deg)``
    above it: an error in the IMU's angles moves the predicted floor in proportion to
    the range.
    """
    heights = heights_above_floor(points, pitch_rad, roll_rad, params)
    ranges = np.hypot(points[:, 0], points[:, 1])
    slack = math.sin(math.radians(params.imu_angle_error_deg))
    return heights < params.imu_floor_tolerance_m + slack * ranges
