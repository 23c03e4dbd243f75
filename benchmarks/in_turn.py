"""Timing several filters on one stream in turn, a few scans at a time.

On a shared machine the speed drifts within seconds: timed one after the other, whole
run against whole run, the improved filter's time per scan over the paper filter's read
anywhere from 1.8x to 3.7x within one call of ``bench_pvfilter.py`` or
``bench_filters_sim.py`` on one busy day. Fed the same stream in turn, ``CHUNK_SCANS``
scans each before the next filter takes its turn, every filter sees the same drift, and
the ratio of their times holds.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import Any

CHUNK_SCANS = 50  # scans (5 s of a 10 Hz stream) each filter takes before the next's turn


def seconds_in_turn(
    filters: dict[str, Any],
    stream: Sequence[Any],
    chunk_scans: int = CHUNK_SCANS,
) -> dict[str, float]:
    """Seconds each of ``filters`` (name -> an object with ``process(item)``) spent on the
    whole ``stream``, fed to them in turn ``chunk_scans`` items at a time (each filter
    sees every item once, in order: a filter that keeps state between scans runs as it
    would on the stream alone).
    """
    elapsed = dict.fromkeys(filters, 0.0)
    for start in range(0, len(stream), chunk_scans):
        chunk = stream[start : start + chunk_scans]
        for name, scan_filter in filters.items():
            process = scan_filter.process
            began = time.perf_counter()
            for item in chunk:
                process(item)
            elapsed[name] += time.perf_counter() - began
    return elapsed
