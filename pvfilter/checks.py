"""Parameter checks every filter's parameters share: one error format for all of them.

Each check raises ``ValueError("<field>: <what was expected>, got <value>")``, so a
parameter file, a command-line flag and a Python call report a bad value alike.
"""

from __future__ import annotations

import math
import numbers


def check_number(
    name: str,
    value: object,
    *,
    lower: float,
    upper: float = math.inf,
    unit: str = "",
    closed: bool = False,
    infinite: bool = False,
    below: str = "",
) -> None:
    """Raise ``ValueError("name: ...")`` unless ``value`` is a real number in range.

    The lower bound is exclusive unless ``closed``; the upper bound is inclusive; ``inf``
    is accepted only where ``infinite`` (a check that can be switched off). ``below``
    names the field the lower bound comes from, if any.
    """
    unit = f" {unit}" if unit else ""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ValueError(f"{name}: must be a number, got {value!r}")
    if math.isnan(value) or (math.isinf(value) and not infinite):
        raise ValueError(f"{name}: must be finite, got {value}")
    if not (value >= lower if closed else value > lower):
        bound = f"{below} ({lower:g}{unit})" if below else f"{lower:g}{unit}"
        raise ValueError(f"{name}: must be {'>=' if closed else '>'} {bound}, got {value}")
    if value > upper:
        raise ValueError(f"{name}: must be <= {upper:g}{unit}, got {value}")


def check_integer(name: str, value: object, lowest: int) -> None:
    """Raise ``ValueError("name: ...")`` unless ``value`` is an integer ``>= lowest``."""
    integral = isinstance(value, numbers.Integral) and not isinstance(value, bool)
    if not integral or value < lowest:
        raise ValueError(f"{name}: must be an integer >= {lowest}, got {value!r}")


def check_flag(name: str, value: object) -> None:
    """Raise ``ValueError("name: ...")`` unless ``value`` is ``True`` or ``False``."""
    if not isinstance(value, bool):
        raise ValueError(f"{name}: must be true or false, got {value!r}")
