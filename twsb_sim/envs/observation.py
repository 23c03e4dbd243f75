"""The environments' observation: the latest scan, the robot's own IMU, attitude estimate
and wheel odometry, and the target.

The IMU, attitude and odometry entries are what the robot's sensors report (noise, bias,
latency, encoder ticks and calibration errors; ``docs/sensors.md``), not the truth, which
is in ``info``. Every entry is ``float32`` in a finite ``Box``, as learning code expects
(and ``check_env`` asks for). Two consequences, both documented in the README:

- **Scan ranges** lose REP-117's infinities: ``+inf`` (no return within ``range_max``)
  reads ``range_max``; ``-inf`` (closer than ``range_min``, and the beams blocked by the
  robot's own body) and ``NaN`` read ``0``. A real return is never below ``range_min``,
  so ``0`` is unambiguous. The REP-117 ranges are in ``info["scan_ranges_m"]``.
- **The IMU and the wheels saturate** like real sensors, at ``GYRO_RANGE_RAD_S``,
  ``ACCEL_RANGE_MPS2`` and ``WHEEL_SPEED_RANGE_RAD_S``; odometry positions are clipped at
  ``ODOMETRY_RANGE_M``.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from gymnasium import spaces

from twsb_sim.frame import RobotTruth
from twsb_sim.sensors.attitude import quat_from_rpy

GYRO_RANGE_RAD_S = math.radians(2000.0)  # rad/s, a common MEMS gyro's full scale
ACCEL_RANGE_MPS2 = 16.0 * 9.80665  # m/s², a common MEMS accelerometer's full scale (16 g)
WHEEL_SPEED_RANGE_RAD_S = 100.0  # rad/s, far beyond what the motors reach
ODOMETRY_RANGE_M = 1000.0  # m, far beyond any house
TWIST_RANGE = (10.0, 20.0)  # m/s, rad/s: far beyond what the robot does


class RobotSensors(NamedTuple):
    """What the robot's own sensors say now (see :class:`~twsb_sim.sensors.SensorSuite`)."""

    imu: np.ndarray  # (6,) latest gyro (rad/s) and accel (m/s²) reading, imu frame
    rpy_rad: np.ndarray  # (3,) attitude estimate: roll, pitch, yaw
    pose_odom: np.ndarray  # (3,) x m, y m, yaw rad of base_footprint in odom
    twist: np.ndarray  # (2,) forward m/s, yaw rate rad/s


def _box(limit: float | tuple[float, ...], shape: tuple[int, ...]) -> spaces.Box:
    high = np.broadcast_to(np.asarray(limit, dtype=np.float32), shape)
    return spaces.Box(low=-high, high=high, dtype=np.float32)


def observation_space(
    n_beams: int, range_max_m: float, target_limits: tuple[float, float]
) -> spaces.Dict:
    """The observation space of an environment.

    Args:
        n_beams: beams per scan.
        range_max_m: the LiDAR's maximum range, m.
        target_limits: largest |target velocity| (m/s) and |target yaw rate| (rad/s).
    """
    return spaces.Dict(
        {
            "scan": spaces.Box(0.0, range_max_m, shape=(n_beams,), dtype=np.float32),
            "imu_gyro": _box(GYRO_RANGE_RAD_S, (3,)),
            "imu_accel": _box(ACCEL_RANGE_MPS2, (3,)),
            "imu_quat": _box(1.0, (4,)),
            "attitude": _box(math.pi, (2,)),
            "wheel_speeds": _box(WHEEL_SPEED_RANGE_RAD_S, (2,)),
            "odometry": _box((ODOMETRY_RANGE_M, ODOMETRY_RANGE_M, math.pi), (3,)),
            "odometry_twist": _box(TWIST_RANGE, (2,)),
            "target": _box(target_limits, (2,)),
        }
    )


def encode_scan(ranges: np.ndarray, range_max_m: float) -> np.ndarray:
    """REP-117 ranges to the observation's finite encoding (see the module docstring)."""
    encoded = np.nan_to_num(ranges, nan=0.0, posinf=range_max_m, neginf=0.0)
    return np.clip(encoded, 0.0, range_max_m).astype(np.float32)


def make_observation(
    scan_ranges: np.ndarray,
    range_max_m: float,
    truth: RobotTruth,
    sensors: RobotSensors,
    target: tuple[float, float],
    space: spaces.Dict,
) -> dict[str, np.ndarray]:
    """Assemble one observation, each entry a new array clipped into its box.

    ``imu_quat`` is the estimator's orientation (yaw from the gyro alone, 0 at reset);
    ``attitude`` its pitch and roll (rad, + nose down, + left side up); ``odometry`` the
    encoders' dead reckoning in the odom frame (the robot's pose at reset is the origin).
    """

    def clip(name: str, value: np.ndarray | tuple[float, ...]) -> np.ndarray:
        box = space[name]
        return np.clip(np.asarray(value, dtype=np.float32), box.low, box.high)

    return {
        "scan": encode_scan(scan_ranges, range_max_m),
        "imu_gyro": clip("imu_gyro", sensors.imu[:3]),
        "imu_accel": clip("imu_accel", sensors.imu[3:]),
        "imu_quat": clip("imu_quat", quat_from_rpy(*sensors.rpy_rad)),
        "attitude": clip("attitude", (sensors.rpy_rad[1], sensors.rpy_rad[0])),
        "wheel_speeds": clip("wheel_speeds", truth.wheel_speeds_rad_s),
        "odometry": clip("odometry", sensors.pose_odom),
        "odometry_twist": clip("odometry_twist", sensors.twist),
        "target": clip("target", target),
    }
