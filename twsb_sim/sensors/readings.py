"""What the robot's own sensors told it around one scan: IMU, attitude estimate, odometry.

Every :class:`~twsb_sim.frame.Frame` of the simulator carries a :class:`SensorReadings`:
the IMU samples and odometry updates that reached the robot since the previous frame
(streams at their own rates, for consumers that want them all), and the values a
consumer of this scan would look up at its stamp, as ``tf`` would: the attitude
estimate, the base's and the LiDAR's pose in the ``odom`` frame, the odometry twist.
The noise-free state stays in :class:`~twsb_sim.frame.RobotTruth`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np


def _frozen(array: object, shape_tail: tuple[int, ...]) -> np.ndarray:
    """A read-only float64 array; one that already is (a view of a frozen block) is kept."""
    if (
        isinstance(array, np.ndarray)
        and array.dtype == np.float64
        and not array.flags.writeable
        and array.shape[1:] == shape_tail
    ):
        return array
    out = np.array(array, dtype=np.float64)
    if out.shape[1:] != shape_tail:
        out = out.reshape((-1, *shape_tail))
    out.flags.writeable = False
    return out


class Attitude(NamedTuple):
    """Pitch and roll (rad) as the robot's estimator gives them: positive nose down and
    left side up. Unpacks in the order filters take them: ``process(scan, *attitude)``."""

    pitch_rad: float
    roll_rad: float


@dataclass(frozen=True, eq=False, kw_only=True)
class ImuSamples:
    """IMU samples in time order, as they reached the robot's software.

    Attributes:
        stamps_s: ``(k,)`` arrival times (measurement time + latency), s.
        gyro_rad_s: ``(k, 3)`` angular velocity, imu frame, rad/s (noisy, biased, clipped).
        accel_mps2: ``(k, 3)`` specific force, imu frame, m/s² (gravity included).
        rpy_rad: ``(k, 3)`` the attitude estimate after each sample: roll, pitch, yaw.
    """

    stamps_s: np.ndarray
    gyro_rad_s: np.ndarray
    accel_mps2: np.ndarray
    rpy_rad: np.ndarray

    def __post_init__(self) -> None:
        put = object.__setattr__
        put(self, "stamps_s", _frozen(self.stamps_s, ()))
        for name in ("gyro_rad_s", "accel_mps2", "rpy_rad"):
            put(self, name, _frozen(getattr(self, name), (3,)))

    def __len__(self) -> int:
        return len(self.stamps_s)


@dataclass(frozen=True, eq=False, kw_only=True)
class OdometrySamples:
    """Wheel-odometry updates in time order.

    Attributes:
        stamps_s: ``(k,)`` s.
        pose_odom: ``(k, 3)`` x (m), y (m), yaw (rad) of ``base_footprint`` in ``odom``.
        twist: ``(k, 2)`` forward speed (m/s) and yaw rate (rad/s) over the last period.
    """

    stamps_s: np.ndarray
    pose_odom: np.ndarray
    twist: np.ndarray

    def __post_init__(self) -> None:
        put = object.__setattr__
        put(self, "stamps_s", _frozen(self.stamps_s, ()))
        put(self, "pose_odom", _frozen(self.pose_odom, (3,)))
        put(self, "twist", _frozen(self.twist, (2,)))

    def __len__(self) -> int:
        return len(self.stamps_s)


@dataclass(frozen=True, eq=False, kw_only=True)
class SensorReadings:
    """The robot's sensor view of one scan.

    Attributes:
        imu: IMU samples that arrived since the previous frame.
        odometry: odometry updates since the previous frame.
        attitude_rpy_rad: ``(3,)`` the estimate at the scan's stamp: roll, pitch, yaw
            (yaw from the gyro alone, 0 at the start).
        pose_base_in_odom: ``(3,)`` x, y, yaw of ``base_footprint`` in ``odom`` at the
            stamp (interpolated between odometry updates, as ``tf`` does).
        pose_lidar_in_odom: ``(3,)`` x, y, yaw of the LiDAR in ``odom`` at the stamp: the
            base's pose composed with the LiDAR's mounting offset (the filters' odometry).
        twist: ``(2,)`` forward speed (m/s) and yaw rate (rad/s) at the stamp.
    """

    imu: ImuSamples
    odometry: OdometrySamples
    attitude_rpy_rad: np.ndarray
    pose_base_in_odom: np.ndarray
    pose_lidar_in_odom: np.ndarray
    twist: np.ndarray

    def __post_init__(self) -> None:
        for name in ("attitude_rpy_rad", "pose_base_in_odom", "pose_lidar_in_odom", "twist"):
            object.__setattr__(self, name, _frozen(getattr(self, name), ()))

    @property
    def attitude(self) -> Attitude:
        """The estimated pitch and roll at the stamp (rad)."""
        return Attitude(float(self.attitude_rpy_rad[1]), float(self.attitude_rpy_rad[0]))
