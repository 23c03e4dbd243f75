"""The robot inputs of a simulated frame, as a filter receives them (:mod:`pvfilter.contract`).

What a real robot would hand its filter: the attitude its estimator computes from a noisy
IMU (pitch positive nose down, roll positive left side up, lag included) and the LiDAR's
pose in the odom frame from wheel odometry (slip included): ``frame.attitude_estimate``
and ``frame.lidar_pose_in_odom`` (:mod:`twsb_sim.sensors`). With ``truth=True`` the
filter gets the noise-free values instead: the IMU body's true attitude and the sensor's
true pose (the world serving as odom), as the paper fed its DATMO baseline SLAM poses,
and to measure what the realistic inputs cost. Frames made without the sensor models
(synthetic test frames) carry only the truth, and give it.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from typing import Any

import numpy as np

from twsb_sim.frame import Frame, RobotTruth


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


def robot_inputs(frame: Frame, names: Iterable[str], truth: bool = False) -> dict[str, Any]:
    """The robot inputs ``names`` (of :data:`pvfilter.ROBOT_INPUTS`) for ``frame``'s scan.

    Args:
        frame: the frame.
        names: the inputs wanted.
        truth: give the noise-free values instead of the robot's sensors' (see the module
            docstring).

    Raises:
        ValueError: a name that is not a robot input.
    """
    inputs: dict[str, Any] = {}
    sensors = frame.sensors is not None and not truth
    for name in names:
        if name in ("pitch_rad", "roll_rad"):
            attitude = frame.attitude_estimate if sensors else imu_pitch_roll(frame.truth.imu_quat)
            # as an angle, within +/- pi (the estimator's integral is not wrapped: a robot
            # that fell and rolled on reads several turns)
            inputs["pitch_rad"], inputs["roll_rad"] = (
                math.remainder(float(a), math.tau) for a in attitude
            )
        elif name == "pose_sensor_in_odom":
            inputs[name] = frame.lidar_pose_in_odom if sensors else sensor_pose_2d(frame.truth)
        else:
            raise ValueError(f"robot input: unknown {name!r}")
    return inputs
