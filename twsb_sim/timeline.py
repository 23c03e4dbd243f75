"""Scenario timelines: velocity / yaw-rate commands and shoves, sampled per physics step.

A timeline is written as a short list of command points (``t_s``, target velocity and yaw
rate, and how long the robot takes to ramp to them). The loop needs the command at every
physics step, so :func:`sample_commands` turns the list into one array per signal once,
before the run: the hot loop only indexes an array.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class CommandPoint:
    """From ``t_s`` on, ramp linearly to the targets over ``ramp_s``, then hold them.

    ``ramp_s = 0`` is a step: a hard stop when the velocity target is 0.
    """

    t_s: float  # s, time the ramp starts
    velocity_mps: float = 0.0  # m/s, forward velocity target
    yaw_rate_rad_s: float = 0.0  # rad/s, yaw-rate target (counter-clockwise positive)
    ramp_s: float = 0.0  # s, time to reach the targets from the values in force at t_s
    label: str = ""  # phase name shown in logs ("accelerate", "hard stop", ...)


@dataclass(frozen=True)
class Shove:
    """A push on the robot's body: a constant force over a short time.

    The force is given in the robot's heading frame at the moment the shove starts
    (x forward, y left, z up, yaw only: a push "from behind" stays horizontal even
    when the body pitches) and acts at ``point_m`` in the body frame.
    """

    t_s: float  # s, start
    force_n: tuple[float, float, float]  # N, in the heading frame at t_s
    duration_s: float = 0.2  # s
    point_m: tuple[float, float, float] = (0.0, 0.0, 0.35)  # m, body frame (origin at the axle)
    label: str = ""

    @property
    def end_s(self) -> float:
        return self.t_s + self.duration_s


@dataclass(frozen=True)
class CommandSamples:
    """Commands at every physics step ``k`` (time ``k * dt``)."""

    velocity_mps: np.ndarray  # float64[n_steps]
    yaw_rate_rad_s: np.ndarray  # float64[n_steps]


def sample_commands(points: tuple[CommandPoint, ...], dt_s: float, n_steps: int) -> CommandSamples:
    """Piecewise-linear command signals sampled at the physics rate.

    Before the first point, and with no points at all, the command is zero.

    Args:
        points: command points in time order, ramps not overlapping the next point.
        dt_s: physics step in s.
        n_steps: number of physics steps to sample.
    """
    times = np.arange(n_steps) * dt_s
    velocity = np.zeros(n_steps)
    yaw_rate = np.zeros(n_steps)
    held_v = held_w = 0.0  # the targets in force when the next point starts
    for point in points:
        # later points overwrite from their start on: the command is right-continuous
        started = times >= point.t_s - 1e-9 * dt_s
        if point.ramp_s > 0.0:
            fraction = np.clip((times[started] - point.t_s) / point.ramp_s, 0.0, 1.0)
        else:
            fraction = 1.0
        velocity[started] = held_v + (point.velocity_mps - held_v) * fraction
        yaw_rate[started] = held_w + (point.yaw_rate_rad_s - held_w) * fraction
        held_v, held_w = point.velocity_mps, point.yaw_rate_rad_s
    return CommandSamples(velocity_mps=velocity, yaw_rate_rad_s=yaw_rate)


def phase_at(points: tuple[CommandPoint, ...], t_s: float) -> str:
    """Label of the command point in force at ``t_s`` ("" before the first)."""
    label = ""
    for point in points:
        if point.t_s <= t_s + 1e-12:
            label = point.label or f"v={point.velocity_mps:g} m/s, w={point.yaw_rate_rad_s:g} rad/s"
    return label


def heading_force_to_world(force_n: tuple[float, float, float], yaw_rad: float) -> np.ndarray:
    """Rotate a heading-frame force into the world frame (rotation about z by yaw)."""
    c, s = math.cos(yaw_rad), math.sin(yaw_rad)
    fx, fy, fz = force_n
    return np.array([c * fx - s * fy, s * fx + c * fy, fz])
