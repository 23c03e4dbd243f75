"""The benchmarks' timing helper: filters fed in turn see the stream as they would alone."""

from __future__ import annotations

import importlib.util
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _in_turn():
    """``benchmarks/in_turn.py`` (the benchmarks are scripts, not a package)."""
    spec = importlib.util.spec_from_file_location("in_turn", ROOT / "benchmarks" / "in_turn.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


class _Recorder:
    """A stand-in filter that notes what it was given, and when, in a log shared by all."""

    def __init__(self, name: str, log: list) -> None:
        self.name, self.log, self.seen = name, log, []

    def process(self, item: int) -> None:
        self.seen.append(item)
        self.log.append(self.name)


def test_every_filter_sees_every_scan_once_in_order_taking_turns():
    in_turn = _in_turn()
    log: list[str] = []
    filters = {name: _Recorder(name, log) for name in ("a", "b", "c")}
    stream = list(range(23))  # the last chunk short: 23 = 2 x 10 + 3
    seconds = in_turn.seconds_in_turn(filters, stream, chunk_scans=10)
    assert all(f.seen == stream for f in filters.values())
    # ten scans each, in turn: a a ... b b ... c c ..., then the next chunk
    expected = [name for size in (10, 10, 3) for name in "abc" for _ in range(size)]
    assert log == expected
    assert set(seconds) == set(filters)
    assert all(s >= 0.0 for s in seconds.values())
