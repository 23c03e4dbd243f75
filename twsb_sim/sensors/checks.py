"""Value checks shared by the sensor configurations.

Each raises ``ValueError("field: what was expected, got X")``, the form the scenario
loader turns into a one-line error naming the file and the key.
"""

from __future__ import annotations

import math


def number(name: str, value: object) -> float:
    """``value`` as a float; raise when it is not a finite number (bools are not numbers)."""
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise ValueError(f"{name}: expected a finite number, got {value!r}")
    return float(value)


def within(name: str, value: object, low: float, high: float, unit: str = "") -> float:
    """``value`` as a float in ``[low, high]``; raise otherwise."""
    x = number(name, value)
    if not low <= x <= high:
        suffix = f" {unit}" if unit else ""
        raise ValueError(f"{name}: expected {low:g} to {high:g}{suffix}, got {x!r}")
    return x


def positive(name: str, value: object, unit: str = "") -> float:
    """``value`` as a float > 0; raise otherwise."""
    x = number(name, value)
    if x <= 0:
        raise ValueError(f"{name}: expected a value > 0{' ' + unit if unit else ''}, got {x!r}")
    return x


def non_negative(name: str, value: object, unit: str = "") -> float:
    """``value`` as a float >= 0; raise otherwise."""
    x = number(name, value)
    if x < 0:
        raise ValueError(f"{name}: expected a value >= 0{' ' + unit if unit else ''}, got {x!r}")
    return x
