"""Checks shared by the ranges of ``twsb generate``: ``[low, high]`` pairs and bounds."""

from __future__ import annotations

import dataclasses
from typing import Any

Range = tuple[float, float]


def normalize(config: Any) -> None:
    """Turn every scalar given for a range into ``(value, value)`` and check the order."""
    for f in dataclasses.fields(config):
        value = getattr(config, f.name)
        if "Range" not in str(f.type):
            continue
        if isinstance(value, int | float) and not isinstance(value, bool):
            value = (float(value), float(value))
            object.__setattr__(config, f.name, value)
        low, high = value
        if not low <= high:
            raise ValueError(f"{f.name}: expected [low, high] with low <= high, got {list(value)}")


def within(name: str, value: Range | float, low: float, high: float) -> None:
    """Raise ``ValueError("name: ...")`` unless every value lies in ``[low, high]``."""
    values = value if isinstance(value, tuple) else (value,)
    if not all(low <= v <= high for v in values):
        raise ValueError(f"{name}: expected values in [{low:g}, {high:g}], got {value}")
