"""Random disturbances of an episode: shoves on the body and injected hard stops.

Both arrive as Poisson processes at a mean rate per simulated second, decided once per
env step from the env's ``np_random`` (so a seed fixes them). A shove is a horizontal
push of random magnitude at a point on the body, from behind or from the front within a
spread of directions; a hard stop forces the
velocity and yaw-rate targets (and, in the velocity variant, the commands) to zero for a
while, the manoeuvre that pitches a TWSB robot the most.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from twsb_sim.envs.options import check_non_negative


@dataclass(frozen=True)
class Disturbances:
    """Rates and sizes of the random disturbances (all off by default)."""

    shove_rate_hz: float = 0.0  # mean shoves per simulated second
    shove_force_n: tuple[float, float] = (20.0, 40.0)  # N, magnitude drawn uniformly
    shove_duration_s: float = 0.15  # s
    shove_height_m: float = 0.40  # m, point of application on the body z axis, above the axle
    # deg, spread of the push direction around straight from behind or from the front (each
    # half of the shoves): the robot cannot balance sideways, and 90 deg tips it over often
    shove_spread_deg: float = 15.0
    hard_stop_rate_hz: float = 0.0  # mean hard stops per simulated second
    hard_stop_duration_s: float = 1.0  # s, how long the zero command is held

    def __post_init__(self) -> None:
        check_non_negative(self)
        low, high = self.shove_force_n
        if len(self.shove_force_n) != 2 or low > high:
            raise ValueError(f"shove_force_n: expected (low, high), got {self.shove_force_n!r}")


@dataclass(frozen=True)
class ShoveDraw:
    """One shove as drawn: a force in the heading frame and how long it lasts."""

    force_heading_n: tuple[float, float, float]  # N, heading frame (x forward, y left)
    point_body_m: tuple[float, float, float]  # m, body frame
    duration_s: float


def draw_shove(config: Disturbances, rng: np.random.Generator, step_s: float) -> ShoveDraw | None:
    """Whether a shove starts within a step of ``step_s``, and which one."""
    if config.shove_rate_hz <= 0 or rng.random() >= -math.expm1(-config.shove_rate_hz * step_s):
        return None
    magnitude = rng.uniform(*config.shove_force_n)
    spread = math.radians(min(config.shove_spread_deg, 180.0))
    direction = (math.pi if rng.random() < 0.5 else 0.0) + rng.uniform(-spread, spread)
    return ShoveDraw(
        force_heading_n=(magnitude * math.cos(direction), magnitude * math.sin(direction), 0.0),
        point_body_m=(0.0, 0.0, config.shove_height_m),
        duration_s=config.shove_duration_s,
    )


def draw_hard_stop(config: Disturbances, rng: np.random.Generator, step_s: float) -> bool:
    """Whether a hard stop starts within a step of ``step_s``."""
    rate = config.hard_stop_rate_hz
    return rate > 0 and rng.random() < -math.expm1(-rate * step_s)
