"""The environments' observation: the latest scan, the IMU, wheel odometry and the target.

Every entry is ``float32`` in a finite ``Box``, as learning code expects (and
``check_env`` asks for). Two consequences, both documented in the README:

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

import numpy as np
from gymnasium import spaces

from twsb_sim.frame import RobotTruth

GYRO_RANGE_RAD_S = math.radians(2000.0)  # rad/s, a common MEMS gyro's full scale
ACCEL_RANGE_MPS2 = 16.0 * 9.80665  # m/s², a common MEMS accelerometer's full scale (16 g)
WHEEL_SPEED_RANGE_RAD_S = 100.0  # rad/s, far beyond what the motors reach
ODOMETRY_RANGE_M = 1000.0  # m, far beyond any house


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
            "wheel_speeds": _box(WHEEL_SPEED_RANGE_RAD_S, (2,)),
            "odometry": _box((ODOMETRY_RANGE_M, ODOMETRY_RANGE_M, math.pi), (3,)),
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
    odometry: np.ndarray,
    target: tuple[float, float],
    space: spaces.Dict,
) -> dict[str, np.ndarray]:
    """Assemble one observation, each entry a new array clipped into its box."""

    def clip(name: str, value: np.ndarray | tuple[float, ...]) -> np.ndarray:
        box = space[name]
        return np.clip(np.asarray(value, dtype=np.float32), box.low, box.high)

    return {
        "scan": encode_scan(scan_ranges, range_max_m),
        "imu_gyro": clip("imu_gyro", truth.imu_gyro_rad_s),
        "imu_accel": clip("imu_accel", truth.imu_accel_mps2),
        "imu_quat": clip("imu_quat", truth.imu_quat),
        "wheel_speeds": clip("wheel_speeds", truth.wheel_speeds_rad_s),
        "odometry": clip("odometry", odometry),
        "target": clip("target", target),
    }


class WheelOdometry:
    """Dead reckoning from the wheel angles, as a robot integrates its encoders.

    The pose is in the odometry frame: the robot's pose at reset is the origin. The wheel
    angles are relative to the body, as encoders measure them, so the body's pitch swing
    leaks into the travelled distance as it does on a real TWSB robot.

    Args:
        wheel_radius_m: wheel radius, m.
        track_width_m: distance between the wheels' contact points, m.
    """

    def __init__(self, wheel_radius_m: float, track_width_m: float) -> None:
        self.wheel_radius_m = wheel_radius_m
        self.track_width_m = track_width_m
        self.reset(np.zeros(2))

    def reset(self, wheel_angles_rad: np.ndarray) -> None:
        """Start again at the origin from the current encoder readings (left, right)."""
        self._last_angles = np.array(wheel_angles_rad, dtype=np.float64)
        self.pose = np.zeros(3)  # x m, y m, yaw rad, in the odometry frame

    def update(self, wheel_angles_rad: np.ndarray) -> np.ndarray:
        """Integrate the wheel rotation since the last call; return the pose (x, y, yaw)."""
        angles = np.asarray(wheel_angles_rad, dtype=np.float64)
        left, right = (angles - self._last_angles) * self.wheel_radius_m
        self._last_angles = angles
        distance = 0.5 * (left + right)
        turn = (right - left) / self.track_width_m
        x, y, yaw = self.pose
        heading = yaw + 0.5 * turn  # midpoint rule: exact for an arc's chord direction
        yaw += turn
        self.pose = np.array(
            [
                x + distance * math.cos(heading),
                y + distance * math.sin(heading),
                math.atan2(math.sin(yaw), math.cos(yaw)),
            ]
        )
        return self.pose.copy()
