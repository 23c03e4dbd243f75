"""Random disturbances of an episode: shoves on the body and injected hard stops.

Both arrive as Poisson processes at a mean rate per simulated second, decided once per
env step from the env's ``np_random`` (so a seed fixes them). A shove is a horizontal
push of random direction and magnitude at a point on the body; a hard stop forces the
velocity and yaw-rate targets (and, in the velocity variant, the commands) to zero for a
while, the manoeuvre that pitches a TWSB robot the most.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from typing import Any

import numpy as np


@dataclass(frozen=True)
class Disturbances:
    """Rates and sizes of the random disturbances (all off by default)."""

    shove_rate_hz: float = 0.0  # mean shoves per simulated second
    shove_force_n: tuple[float, float] = (20.0, 50.0)  # N, magnitude drawn uniformly
    shove_duration_s: float = 0.15  # s
    shove_height_m: float = 0.40  # m, point of application on the body z axis, above the axle
    hard_stop_rate_hz: float = 0.0  # mean hard stops per simulated second
    hard_stop_duration_s: float = 1.0  # s, how long the zero command is held

    def __post_init__(self) -> None:
        for f in fields(self):
            values = getattr(self, f.name)
            for value in values if isinstance(values, tuple) else (values,):
                if isinstance(value, bool) or not isinstance(value, int | float):
                    raise ValueError(f"{f.name}: expected numbers, got {values!r}")
                if not math.isfinite(value) or value < 0:
                    raise ValueError(f"{f.name}: expected finite values >= 0, got {values!r}")
        low, high = self.shove_force_n
        if len(self.shove_force_n) != 2 or low > high:
            raise ValueError(f"shove_force_n: expected (low, high), got {self.shove_force_n!r}")

    @classmethod
    def coerce(cls, value: Disturbances | dict[str, Any] | None) -> Disturbances:
        """Accept a ``Disturbances``, a dict of its fields (as from a config file), or None."""
        if value is None:
            return cls()
        if isinstance(value, cls):
            return value
        if isinstance(value, dict):
            unknown = set(value) - {f.name for f in fields(cls)}
            if unknown:
                raise ValueError(f"disturbances: unknown keys {sorted(unknown)}")
            return cls(**{k: tuple(v) if isinstance(v, list) else v for k, v in value.items()})
        raise ValueError(f"disturbances: expected Disturbances or a dict, got {value!r}")


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
    direction = rng.uniform(-math.pi, math.pi)
    return ShoveDraw(
        force_heading_n=(magnitude * math.cos(direction), magnitude * math.sin(direction), 0.0),
        point_body_m=(0.0, 0.0, config.shove_height_m),
        duration_s=config.shove_duration_s,
    )


def draw_hard_stop(config: Disturbances, rng: np.random.Generator, step_s: float) -> bool:
    """Whether a hard stop starts within a step of ``step_s``."""
    rate = config.hard_stop_rate_hz
    return rate > 0 and rng.random() < -math.expm1(-rate * step_s)
