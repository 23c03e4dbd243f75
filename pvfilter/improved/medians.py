"""Medians with ``np.median``'s very values, at a fraction of its cost.

``np.median`` works through several Python layers (the axis, a NaN check, the mean of the
middle elements): about 25 us for the 700 second differences of a scan or for a handful
of floats, where a partition or a sort in Python takes 3-6 us. The filter takes such
medians on every fourth scan (the range noise, :mod:`pvfilter.improved.noise`), on every
scan with a confident line (the roll, :mod:`pvfilter.improved.roll`), and for a seam's
jump (:func:`pvfilter.improved.claims.seam_claims`) and a held line's direction
(:meth:`pvfilter.improved.follow.FloorFollower.held`).

Both give what ``np.median`` gives: the middle element, or the two middle ones' sum
halved (``np.median`` takes their mean, the same float); only where 0.0 and -0.0 tie
for the middle may the zero's sign differ, which none of the filter's uses tells apart.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

import numpy as np


def median_of_few(values: Iterable[float]) -> float:
    """``np.median`` of a few floats (NaN if one of them is NaN, as ``np.median`` says).

    Raises:
        ValueError: no values.
    """
    ordered = sorted(values)
    if not ordered:
        raise ValueError("the median of no values")
    if any(value != value for value in ordered):  # NaN (sorted leaves it anywhere)
        return math.nan
    middle = len(ordered) // 2
    if len(ordered) % 2:
        return ordered[middle]
    return (ordered[middle - 1] + ordered[middle]) / 2.0


def median_in_place(values: np.ndarray) -> float:
    """``np.median`` of a 1-D float array without NaN, reordering ``values`` (a partition
    around the middle, as ``np.median`` makes on a copy).

    Raises:
        ValueError: an empty array.
    """
    size = values.size
    if size == 0:
        raise ValueError("the median of no values")
    middle = size // 2
    if size % 2:
        values.partition(middle)
        return float(values[middle])
    values.partition((middle - 1, middle))
    return (float(values[middle - 1]) + float(values[middle])) / 2.0
