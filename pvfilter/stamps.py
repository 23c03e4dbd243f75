"""The stamp check every stateful filter makes: scans out of order start a new sequence."""

from __future__ import annotations

import warnings


class StampWentBackWarning(UserWarning):
    """A scan's stamp was earlier than the previous scan's; the filter's history was reset."""


def stamp_went_back(stamp: float, previous: float | None, stacklevel: int) -> bool:
    """True (with a :class:`StampWentBackWarning`) when ``stamp`` is earlier than ``previous``.

    Filters reset their history then: scans out of order cannot be compared.

    Args:
        stamp: the new scan's stamp, s.
        previous: the previous scan's stamp, s, or None at the start of a sequence.
        stacklevel: how far up the warning points, counted from the caller.
    """
    if previous is None or stamp >= previous:
        return False
    warnings.warn(
        f"scan stamp {stamp} s is earlier than the previous {previous} s; "
        "the filter's history was reset",
        StampWentBackWarning,
        stacklevel=stacklevel + 1,
    )
    return True
