"""Checks and conversions of the environments' options."""

from __future__ import annotations

import math
from dataclasses import fields
from typing import Any, TypeVar

from pvfilter import ScanFilter
from pvfilter.registry import entry_for_params
from twsb_sim.frame_filter import FrameFilter, as_frame_filter, frame_filter

T = TypeVar("T")


def check_non_negative(config: object) -> None:
    """Raise ``ValueError`` naming the field when a number (or a tuple's) is not finite >= 0."""
    for f in fields(config):
        values = getattr(config, f.name)
        for value in values if isinstance(values, tuple) else (values,):
            if isinstance(value, bool) or not isinstance(value, int | float):
                raise ValueError(f"{f.name}: expected numbers, got {values!r}")
            if not math.isfinite(value) or value < 0:
                raise ValueError(f"{f.name}: expected finite values >= 0, got {values!r}")


def coerce(cls: type[T], value: T | dict[str, Any] | None, name: str) -> T:
    """Accept an instance of the dataclass ``cls``, a dict of its fields (lists become
    tuples, as from a config file) or None (the defaults)."""
    if value is None:
        return cls()
    if isinstance(value, cls):
        return value
    if isinstance(value, dict):
        unknown = set(value) - {f.name for f in fields(cls)}
        if unknown:
            raise ValueError(f"{name}: unknown keys {sorted(unknown)}")
        return cls(**{k: tuple(v) if isinstance(v, list) else v for k, v in value.items()})
    raise ValueError(f"{name}: expected {cls.__name__} or a dict, got {value!r}")


Range = float | tuple[float, float]


def value_range(name: str, value: Range, limit: float) -> tuple[float, float]:
    """Check a value or a (low, high) range against ±``limit``; return it as (low, high)."""
    low, high = (value, value) if isinstance(value, int | float) else tuple(value)
    if not -limit <= low <= high <= limit:
        raise ValueError(
            f"{name}: expected a value or (low, high) within ±{limit:g}, got {value!r}"
        )
    return float(low), float(high)


def make_scan_filter(scan_filter: Any) -> FrameFilter | None:
    """The filter an env runs on every scan (see ``TwsbEnv``'s ``scan_filter``), or None.

    Raises:
        ValueError: an unknown filter name, or parameters no registered filter takes.
    """
    if scan_filter is None or scan_filter is False:
        return None
    if scan_filter is True:
        return frame_filter("paper", "PitchVariationFilter")
    if isinstance(scan_filter, str):
        return frame_filter(scan_filter, scan_filter)
    if isinstance(scan_filter, FrameFilter | ScanFilter):
        return as_frame_filter(scan_filter)
    entry = entry_for_params(scan_filter)  # the parameters of a registered filter
    return frame_filter(entry.name, entry.name, scan_filter)
