"""The attitude a robot estimates from its own IMU: a complementary filter.

A TWSB robot's balance board typically runs a complementary filter (or Madgwick's) on
the raw gyro and accelerometer. The gyro is integrated through the Z-Y-X Euler-angle
kinematics (exact at any attitude), and roll and pitch are pulled towards the
accelerometer's gravity direction with time constant ``tau``:

    angle <- a * (angle + rate * dt) + (1 - a) * angle_from_accel,   a = tau / (tau + dt)

The accelerometer measures gravity *and* the robot's own acceleration, so braking and
shoves bias the estimate, and the gyro's bias drifts it between: the errors of a real
robot's estimate. Yaw is the gyro's integral alone (no magnetometer): it starts at 0.

Angles follow the project's convention: roll positive left side up, pitch positive nose
down (REP-103 rotations about x and y), yaw counter-clockwise.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from twsb_sim.sensors.checks import positive


@dataclass(frozen=True)
class AttitudeFilterConfig:
    """The robot's attitude estimator."""

    time_constant_s: float = 0.5  # s, how fast roll and pitch follow the accelerometer

    def __post_init__(self) -> None:
        positive("time_constant_s", self.time_constant_s, "s")


class ComplementaryFilter:
    """Roll, pitch and yaw from gyro and accelerometer samples, one sample at a time.

    Args:
        config: the time constant.
        sample_period_s: time between IMU samples, s.
    """

    def __init__(self, config: AttitudeFilterConfig, sample_period_s: float) -> None:
        self.config = config
        self.dt_s = sample_period_s
        self.gain = config.time_constant_s / (config.time_constant_s + sample_period_s)
        self.rpy_rad: tuple[float, float, float] | None = None  # None until the first sample

    def reset(self) -> None:
        """Forget the state: the next sample initialises from its accelerometer reading."""
        self.rpy_rad = None

    def update(self, readings: np.ndarray) -> np.ndarray:
        """Run the filter over ``k`` samples in time order.

        Args:
            readings: ``(k, 6)`` gyro x y z (rad/s) and accel x y z (m/s²), imu frame.

        Returns:
            ``(k, 3)`` roll, pitch, yaw (rad) after each sample.
        """
        if not len(readings):
            return np.empty((0, 3))
        a, dt = self.gain, self.dt_s
        ax, ay, az = readings[:, 3], readings[:, 4], readings[:, 5]
        b = 1.0 - a
        roll_pull = (b * np.arctan2(ay, az)).tolist()  # gravity's direction, all at once
        pitch_pull = (b * np.arctan2(-ax, np.hypot(ay, az))).tolist()
        if self.rpy_rad is None:
            roll, pitch, yaw = roll_pull[0] / b, pitch_pull[0] / b, 0.0
        else:
            roll, pitch, yaw = self.rpy_rad
        sin, cos, tau, pi = math.sin, math.cos, math.tau, math.pi
        out = []  # plain floats: this loop runs at the IMU rate
        for (wx, wy, wz), roll_in, pitch_in in zip(
            readings[:, :3].tolist(), roll_pull, pitch_pull, strict=True
        ):
            sr, cr, cp = sin(roll), cos(roll), cos(pitch)
            turn = sr * wy + cr * wz
            roll = a * (roll + (wx + turn * sin(pitch) / cp) * dt) + roll_in
            pitch = a * (pitch + (cr * wy - sr * wz) * dt) + pitch_in
            yaw += turn / cp * dt
            out.append((roll, pitch, (yaw + pi) % tau - pi))
        self.rpy_rad = out[-1]
        return np.array(out)


def quat_from_rpy(roll_rad: float, pitch_rad: float, yaw_rad: float) -> np.ndarray:
    """The unit quaternion (w, x, y, z) of Z-Y-X angles (yaw, then pitch, then roll)."""
    cr, sr = math.cos(roll_rad / 2), math.sin(roll_rad / 2)
    cp, sp = math.cos(pitch_rad / 2), math.sin(pitch_rad / 2)
    cy, sy = math.cos(yaw_rad / 2), math.sin(yaw_rad / 2)
    return np.array(
        [
            cy * cp * cr + sy * sp * sr,
            cy * cp * sr - sy * sp * cr,
            cy * sp * cr + sy * cp * sr,
            sy * cp * cr - cy * sp * sr,
        ]
    )
