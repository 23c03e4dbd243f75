"""A one-line progress report on stderr, without a progress-bar package.

On a terminal it rewrites one line (count, share, rate) at most every quarter second;
elsewhere (a log file, a pipe) it stays silent, so logs hold only the final summary.
"""

from __future__ import annotations

import sys
import time
from typing import TextIO

REFRESH_S = 0.25  # s between redraws


class Progress:
    """Counts work done and shows it.

    Args:
        total: the count at the end (0 when unknown).
        unit: what is counted (``"scans"``).
        quiet: show nothing.
        stream: where to write (stderr by default); shown only when it is a terminal.
    """

    def __init__(
        self, total: int, unit: str, quiet: bool = False, stream: TextIO | None = None
    ) -> None:
        self.stream = sys.stderr if stream is None else stream
        self.shown = not quiet and self.stream.isatty()
        self.total, self.unit, self.done = total, unit, 0
        self._start = self._drawn = time.perf_counter()

    def advance(self, count: int = 1) -> None:
        """Count ``count`` more done; redraw when the last draw is old enough."""
        self.done += count
        now = time.perf_counter()
        if self.shown and now - self._drawn >= REFRESH_S:
            self._drawn = now
            self._draw(now)

    def close(self) -> None:
        """Draw the final state and end the line."""
        if self.shown:
            self._draw(time.perf_counter())
            self.stream.write("\n")
            self.stream.flush()

    def _draw(self, now: float) -> None:
        rate = self.done / (now - self._start) if now > self._start else 0.0
        share = f" ({100 * self.done / self.total:3.0f} %)" if self.total else ""
        text = f"\r{self.done}/{self.total or '?'} {self.unit}{share}, {rate:.0f} {self.unit}/s"
        self.stream.write(text)
        self.stream.flush()
