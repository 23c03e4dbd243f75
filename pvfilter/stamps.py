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


class ScansApartWarning(UserWarning):
    """Scan after scan came too long after the one before to be compared: the filter
    removes nothing. A log recorded that slowly, or stamps not in seconds."""


GAPS_BEFORE_WARNING = 5  # scans in a row too far apart: one is a pause, five a pattern
UNLIKELY_GAP_S = 60.0  # s: scans this far apart, one after another, are stamps in another
# unit (milliseconds read as seconds put 10 Hz scans 100 s apart), not a slow log


class GapWatch:
    """Counts scans in a row that came more than ``max_gap_s`` after the one before, and
    warns once (:class:`ScansApartWarning`) when ``GAPS_BEFORE_WARNING`` have: a filter
    that compares no two scans removes nothing, silently, and stamps in milliseconds or
    nanoseconds (ROS hands out nanoseconds) look exactly so."""

    def __init__(self) -> None:
        self.in_a_row = 0
        self.warned = False

    def reset(self) -> None:
        """A new sequence: count afresh, and warn again."""
        self.in_a_row, self.warned = 0, False

    def scan(self, gap_s: float, max_gap_s: float, stacklevel: int) -> None:
        """Take a scan ``gap_s`` after the one before (s)."""
        if gap_s <= max_gap_s:
            self.in_a_row = 0
            return
        self.in_a_row += 1
        if self.in_a_row < GAPS_BEFORE_WARNING or self.warned:
            return
        self.warned = True
        why = (
            "Are the stamps in seconds?"
            if gap_s > UNLIKELY_GAP_S
            else "A log recorded this slowly is left as it is (see max_gap_s)."
        )
        warnings.warn(
            f"the last {self.in_a_row} scans each came more than max_gap_s ({max_gap_s:g} s) "
            f"after the one before (the last {gap_s:.4g} s): the filter compares no two of "
            f"them and removes nothing. {why}",
            ScansApartWarning,
            stacklevel=stacklevel + 1,
        )
