"""Every method under one interface: a frame in, a removed-beam mask out.

The Pitch Variation Filter sees the scan only. The baselines get what they need from the
simulator, as the paper fed them: the DATMO-like tracker the sensor's true pose in the
world (the paper gave DATMO SLAM poses), the IMU height gate the pitch and roll measured
by the robot's IMU.
"""

from __future__ import annotations

import math
from typing import Protocol

import numpy as np

from pvfilter import (
    FilterParams,
    FilterResult,
    ImprovedParams,
    ImprovedPitchVariationFilter,
    PitchVariationFilter,
)
from twsb_sim.frame import Frame, RobotTruth


class Method(Protocol):
    """A scan filter as the evaluation drives it."""

    name: str

    def reset(self) -> None:
        """Forget the history (a new sequence starts)."""

    def process(self, frame: Frame) -> np.ndarray:
        """The bool mask of the beams the method removes from ``frame.scan``."""


def sensor_pose_2d(truth: RobotTruth) -> np.ndarray:
    """The LiDAR's true SE(2) pose in the world: (x m, y m, heading of its x axis rad)."""
    rotation = truth.rotation_sensor_to_world
    x, y = truth.position_sensor_in_world[:2]
    return np.array([x, y, math.atan2(rotation[1, 0], rotation[0, 0])])


def imu_pitch_roll(imu_quat: np.ndarray) -> tuple[float, float]:
    """Pitch (positive = nose down) and roll, rad, of the IMU's orientation (w, x, y, z).

    Z-Y-X Euler angles of REP-103: pitch about the body's y axis, roll about its x axis.
    """
    w, x, y, z = (float(v) for v in imu_quat)
    sin_pitch = 2.0 * (w * y - z * x)
    pitch = math.asin(max(-1.0, min(1.0, sin_pitch)))
    roll = math.atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))
    return pitch, roll


class PvfMethod:
    """The Pitch Variation Filter; keeps its last result for the miss diagnosis."""

    def __init__(self, params: FilterParams | None = None, name: str = "PVF") -> None:
        self.name = name
        self.filter = PitchVariationFilter(params)
        self.last_result: FilterResult | None = None

    def reset(self) -> None:
        self.filter.reset()
        self.last_result = None

    def process(self, frame: Frame) -> np.ndarray:
        self.last_result = self.filter.process(frame.scan)
        return self.last_result.removed


class ImprovedMethod:
    """The improved filter; with ``imu`` it is also given the IMU's pitch and roll.

    Its state does not depend on ``p_th``, and a beam is removed exactly when its score
    exceeds ``p_th``, so one pass gives every threshold (:meth:`beam_scores`).
    """

    def __init__(
        self, params: ImprovedParams | None = None, imu: bool = False, name: str = "improved"
    ) -> None:
        self.name = name
        self.imu = imu
        self.filter = ImprovedPitchVariationFilter(params)
        self.last_result: FilterResult | None = None

    def reset(self) -> None:
        self.filter.reset()
        self.last_result = None

    def process(self, frame: Frame) -> np.ndarray:
        attitude = imu_pitch_roll(frame.truth.imu_quat) if self.imu else (None, None)
        self.last_result = self.filter.process(frame.scan, *attitude)
        return self.last_result.removed

    def beam_scores(self) -> np.ndarray:
        """Per beam of the last frame: removed at ``p_th`` exactly when this exceeds it."""
        return self.last_result.scores


class DatmoMethod:
    """The DATMO-like tracker, fed the sensor's true pose in the world."""

    def __init__(self, speed_threshold_mps: float, name: str = "DATMO-like") -> None:
        from scaneval.baselines import DatmoLikeFilter

        self.name = name
        self.filter = DatmoLikeFilter(speed_threshold_mps=speed_threshold_mps)

    def reset(self) -> None:
        self.filter.reset()

    def process(self, frame: Frame) -> np.ndarray:
        pose = sensor_pose_2d(frame.truth)
        return self.filter.process(frame.scan, pose_sensor_in_world=pose)

    def beam_scores(self) -> np.ndarray:
        """Speed of every beam's track after the last frame, m/s (NaN: no track).

        The tracking does not depend on the threshold, so one pass gives the mask of
        every threshold ``v``: ``beam_scores() > v``.
        """
        return self.filter.last_beam_speeds_mps


class ImuGateMethod:
    """The IMU height gate, fed the pitch and roll of the robot's IMU.

    It keeps the beams that end within ``half_band_m`` of the scanner's mounting height
    (one parameter to sweep: from a thin slice around the scan plane to everything).

    Args:
        lidar_height_m: the scanner's height above the floor when upright, m.
        half_band_m: half the height band kept, m.
        axle_height_m: the height the robot tilts about (its wheel axle), m.
        name: shown in reports.
    """

    def __init__(
        self,
        lidar_height_m: float,
        half_band_m: float,
        axle_height_m: float | None = None,
        name: str = "IMU gate",
    ) -> None:
        from scaneval.baselines import ImuHeightGate

        self.name = name
        band = (lidar_height_m - half_band_m, lidar_height_m + half_band_m)
        self.filter = ImuHeightGate(lidar_height_m, band, axle_height_m=axle_height_m)

    def reset(self) -> None:
        self.filter.reset()

    def process(self, frame: Frame) -> np.ndarray:
        pitch, roll = imu_pitch_roll(frame.truth.imu_quat)
        return self.filter.process(frame.scan, pitch, roll)


class NoFilterMethod:
    """Removes nothing."""

    name = "no filter"

    def reset(self) -> None:
        pass

    def process(self, frame: Frame) -> np.ndarray:
        return np.zeros(len(frame.scan), dtype=bool)
