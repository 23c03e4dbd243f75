"""The attitude a robot estimates from its own IMU: a complementary filter.

A TWSB robot's balance board typically runs a complementary filter (or Madgwick's) on
the raw gyro and accelerometer. The gyro is integrated through the Z-Y-X Euler-angle
kinematics (exact at any attitude), and roll and pitch are pulled towards the
accelerometer's gravity direction with time constant ``tau``:

    angle <- a * (angle + rate * dt) + (1 - a) * angle_from_accel,   a = tau / (tau + dt)

The accelerometer measures gravity *and* the robot's own acceleration, so braking and
shoves bias the estimate, and the gyro's bias drifts it between: the errors of a real
robot's estimate. Yaw is the gyro's integral alone (no magnetometer): it starts at 0.

The filter initialises as a robot's does at power-up, at rest: from the first sample
whose accelerometer measures about gravity (within ``REST_TOLERANCE``). A sample taken
in free fall (a robot set down just above the floor) or in a bump tells nothing of the
tilt; until the first sample at rest the estimate reads level.

Angles follow the project's convention: roll positive left side up, pitch positive nose
down (REP-103 rotations about x and y), yaw counter-clockwise.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from twsb_sim.kernel import kernel
from twsb_sim.sensors.checks import positive
from twsb_sim.sensors.imu import STANDARD_GRAVITY_MPS2

REST_TOLERANCE = 0.2  # share of g: a sample whose specific force is this near g starts it


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
        roll_pull = b * np.arctan2(ay, az)  # gravity's direction, all at once (numpy's
        pitch_pull = b * np.arctan2(-ax, np.hypot(ay, az))  # arctan2, as it always was)
        if self.rpy_rad is not None:
            out = _integrate(
                np.asarray(readings[:, :3]), roll_pull, pitch_pull, *self.rpy_rad, a, dt
            )
            self.rpy_rad = tuple(out[-1].tolist())
            return out
        # not yet initialised: from the first sample at rest on (before it: level)
        specific_force = np.sqrt(ax * ax + ay * ay + az * az)
        at_rest = (
            np.abs(specific_force - STANDARD_GRAVITY_MPS2) <= REST_TOLERANCE * STANDARD_GRAVITY_MPS2
        )
        out = np.zeros((len(readings), 3))
        if not np.count_nonzero(at_rest):
            return out
        k = int(np.argmax(at_rest))
        start = (roll_pull[k] / b, pitch_pull[k] / b, 0.0)
        gyro = np.asarray(readings[k:, :3])
        out[k:] = _integrate(gyro, roll_pull[k:], pitch_pull[k:], *start, a, dt)
        self.rpy_rad = tuple(out[-1].tolist())
        return out


@kernel
def _integrate(
    gyro: np.ndarray,
    roll_pull: np.ndarray,
    pitch_pull: np.ndarray,
    roll: float,
    pitch: float,
    yaw: float,
    gain: float,
    dt: float,
) -> np.ndarray:
    """The filter over ``k`` samples from ``(roll, pitch, yaw)``: ``(k, 3)`` estimates.

    ``roll_pull`` and ``pitch_pull`` are ``(1 - gain)`` times the accelerometer's angles.
    """
    out = np.empty((len(gyro), 3))
    for k in range(len(gyro)):
        wx, wy, wz = gyro[k, 0], gyro[k, 1], gyro[k, 2]
        sr, cr, cp = math.sin(roll), math.cos(roll), math.cos(pitch)
        turn = sr * wy + cr * wz
        roll = gain * (roll + (wx + turn * math.sin(pitch) / cp) * dt) + roll_pull[k]
        pitch = gain * (pitch + (cr * wy - sr * wz) * dt) + pitch_pull[k]
        yaw += turn / cp * dt
        out[k, 0], out[k, 1], out[k, 2] = roll, pitch, (yaw + math.pi) % math.tau - math.pi
    return out


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
