"""Wheel odometry as a robot computes it: encoder ticks, a calibration error, dead reckoning.

The encoders count the wheels' rotation relative to the body (as motor encoders do), in
whole ticks of ``2 pi / encoder_counts_per_rev``. The robot converts ticks to distance
with the wheel radius it *believes*, which is off by ``*_wheel_radius_error`` (a fraction
of the true radius: tyre wear, load, manufacturing). Slip needs no model of its own: the
wheels turn in the physics against the floor's friction (``robot.wheel_friction``), so
on a slippery floor a hard stop spins or locks them and the ticks no longer match the
ground travelled. On a TWSB robot the body's pitch swing also turns the wheels relative
to the body, and that leaks into the travelled distance as on the real thing.

The pose ``(x, y, yaw)`` of ``base_footprint`` in the ``odom`` frame (REP-105: fixed at
the robot's start, continuous, drifting) is integrated at ``rate_hz`` with the chord
rule for an arc (exact for constant curvature within a period); the twist is the
forward speed and yaw rate over the last period.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from twsb_sim.kernel import kernel
from twsb_sim.sensors.checks import within


@dataclass(frozen=True)
class OdometryConfig:
    """The encoders and the robot's odometry."""

    rate_hz: float = 50.0  # odometry updates per second (Hz)
    encoder_counts_per_rev: int = 1320  # ticks per wheel turn (11 ppr x4 x 30:1); 0 = exact
    left_wheel_radius_error: float = 0.005  # believed / true radius - 1
    right_wheel_radius_error: float = -0.003  # believed / true radius - 1

    def __post_init__(self) -> None:
        within("rate_hz", self.rate_hz, 1.0, 500.0, "Hz (at most the 500 Hz physics rate)")
        n = self.encoder_counts_per_rev
        if isinstance(n, bool) or not isinstance(n, int) or n < 0:
            raise ValueError(
                f"encoder_counts_per_rev: expected an integer >= 0 (0 = exact), got {n!r}"
            )
        within("left_wheel_radius_error", self.left_wheel_radius_error, -0.2, 0.2)
        within("right_wheel_radius_error", self.right_wheel_radius_error, -0.2, 0.2)

    @classmethod
    def ideal(cls, rate_hz: float = 50.0) -> OdometryConfig:
        """Exact encoders and a perfectly calibrated radius (slip remains: it is physics)."""
        return cls(
            rate_hz=rate_hz,
            encoder_counts_per_rev=0,
            left_wheel_radius_error=0.0,
            right_wheel_radius_error=0.0,
        )


class EncoderOdometry:
    """Dead reckoning from encoder readings, one odometry period at a time.

    Args:
        config: encoder resolution, calibration errors, rate.
        wheel_radius_m: the true wheel radius, m.
        track_width_m: distance between the wheels' contact points, m.
    """

    def __init__(self, config: OdometryConfig, wheel_radius_m: float, track_width_m: float) -> None:
        self.config = config
        self.track_width_m = track_width_m
        self.radii_m = wheel_radius_m * np.array(
            [1.0 + config.left_wheel_radius_error, 1.0 + config.right_wheel_radius_error]
        )  # what the robot believes
        cpr = config.encoder_counts_per_rev
        self.rad_per_tick = 2 * math.pi / cpr if cpr else 0.0
        self.dt_s = 1.0 / config.rate_hz
        self.reset(np.zeros(2))

    def reset(self, wheel_angles_rad: np.ndarray) -> None:
        """Start at the odom origin from the wheels' current angles (left, right)."""
        self._last_ticks = self.ticks(wheel_angles_rad)
        self.pose = np.zeros(3)  # x m, y m, yaw rad in odom
        self.twist = np.zeros(2)  # forward m/s, yaw rate rad/s

    def ticks(self, wheel_angles_rad: np.ndarray) -> np.ndarray:
        """Encoder counts (as floats) of wheel angles; the angles themselves when exact."""
        angles = np.asarray(wheel_angles_rad, dtype=np.float64)
        return np.floor(angles / self.rad_per_tick) if self.rad_per_tick else angles

    def update(self, wheel_angles_rad: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Integrate ``k`` consecutive encoder readings, one per odometry period.

        Args:
            wheel_angles_rad: ``(k, 2)`` left and right wheel angles relative to the body.

        Returns:
            ``(k, 3)`` poses (x m, y m, yaw rad in odom) and ``(k, 2)`` twists (m/s, rad/s).
        """
        angles = np.asarray(wheel_angles_rad, dtype=np.float64)
        if not len(angles):
            return np.empty((0, 3)), np.empty((0, 2))
        scale = (self.rad_per_tick or 1.0) * self.radii_m
        block, self._last_ticks = _dead_reckoning(
            angles, self._last_ticks, self.rad_per_tick, scale, *self.pose.tolist(), self.dt_s,
            self.track_width_m,
        )  # fmt: skip
        poses, twists = block[:, :3], block[:, 3:]
        self.pose, self.twist = block[-1, :3].copy(), block[-1, 3:].copy()
        return poses, twists


@kernel
def _dead_reckoning(
    angles: np.ndarray,
    last_ticks: np.ndarray,
    rad_per_tick: float,
    scale: np.ndarray,
    x: float,
    y: float,
    yaw: float,
    dt: float,
    track: float,
) -> tuple[np.ndarray, np.ndarray]:
    """Integrate ``(k, 2)`` wheel angles (rad, left and right) from the pose ``(x, y,
    yaw)``, the encoders having last counted ``last_ticks``: ``(k, 5)`` rows of x, y,
    yaw, forward speed, yaw rate, and the encoders' last counts. ``scale``: m per tick
    (per rad when exact) of each wheel."""
    out = np.empty((len(angles), 5))
    ticks = np.empty(2)
    previous = last_ticks.copy()
    for k in range(len(angles)):
        for wheel in range(2):
            angle = angles[k, wheel]
            ticks[wheel] = np.floor(angle / rad_per_tick) if rad_per_tick else angle
        left = (ticks[0] - previous[0]) * scale[0]
        right = (ticks[1] - previous[1]) * scale[1]
        previous[:] = ticks
        distance = 0.5 * (left + right)
        turn = (right - left) / track
        # the wheels drew an arc: its chord points at the mid heading and is shorter
        # than the arc by sin(turn / 2) / (turn / 2)
        heading, half = yaw + 0.5 * turn, 0.5 * turn
        chord = distance * (math.sin(half) / half if abs(half) > 1e-9 else 1.0)
        x += chord * math.cos(heading)
        y += chord * math.sin(heading)
        yaw = _remainder_tau(yaw + turn)
        out[k, 0], out[k, 1], out[k, 2] = x, y, yaw
        out[k, 3], out[k, 4] = distance / dt, turn / dt
    return out, previous


@kernel
def _remainder_tau(angle: float) -> float:
    """``math.remainder(angle, tau)``, the IEEE remainder (exact): ``angle`` minus the
    nearest multiple of 2 pi, ties to the even multiple."""
    modulus = np.fmod(abs(angle), math.tau)  # exact
    complement = math.tau - modulus  # exact wherever it decides the result
    if modulus < complement:
        rest = modulus
    elif modulus > complement:
        rest = -complement
    else:  # half-way: the even multiple
        rest = modulus - 2.0 * np.fmod(0.5 * (abs(angle) - modulus), math.tau)
    return math.copysign(1.0, angle) * rest
