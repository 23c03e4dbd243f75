"""What the two bag formats share here: chunks' messages merged in time order, the
input's bytes copied in one piece, and the chunk being filled with the new messages."""

from __future__ import annotations

import heapq
from collections.abc import Iterator
from pathlib import Path
from typing import BinaryIO

BLOCK = 1 << 20  # bytes read at a time: 1 MiB
CHUNK_SIZE = 1 << 20  # bytes of records a new chunk holds, as rosbags writes them: 1 MiB


def merged(
    sources: list[Iterator[tuple[int, int, int, bytes]]],
) -> Iterator[tuple[int, int, bytes]]:
    """``(id, time ns, data)`` of the chunks' messages in time order (chunk order between
    equal times).

    Args:
        sources: one a chunk, each yielding ``(time ns, chunk position, id, data)`` in time
            order, after a placeholder at the chunk's start time with position -1, so
            that the merge reads each chunk only when its time comes, not all of them
            at its start (as rosbags does).
    """
    for time_ns, position, key, data in heapq.merge(*sources):
        if position >= 0:  # not a chunk's placeholder
            yield key, time_ns, data


def copy_prefix(source: Path, destination: BinaryIO, length: int) -> None:
    """Write the first ``length`` bytes of ``source`` to ``destination``.

    Raises:
        ValueError: ``source`` is shorter than ``length``.
    """
    with source.open("rb") as file:
        remaining = length
        while remaining:
            block = file.read(min(remaining, BLOCK))
            if not block:
                raise ValueError(f"{source}: ends {remaining} bytes early (truncated?)")
            destination.write(block)
            remaining -= len(block)


class OpenChunk:
    """The records of a chunk being filled, and what its index needs.

    Attributes:
        records: the chunk's records so far (uncompressed).
        index: ``(stamp ns, offset of its record in records)`` of each message, by
            channel or connection id.
        start_ns: the earliest message stamp (None while there is none).
        end_ns: the latest.
    """

    def __init__(self) -> None:
        self.records = bytearray()
        self.index: dict[int, list[tuple[int, int]]] = {}
        self.start_ns: int | None = None
        self.end_ns: int | None = None

    def add(self, key: int, stamp_ns: int, record: bytes) -> bool:
        """Append a message's record (``key``: its channel or connection); True when the
        chunk is full."""
        self.index.setdefault(key, []).append((stamp_ns, len(self.records)))
        self.records += record
        if self.start_ns is None or self.end_ns is None:
            self.start_ns = self.end_ns = stamp_ns
        else:
            self.start_ns, self.end_ns = min(self.start_ns, stamp_ns), max(self.end_ns, stamp_ns)
        return len(self.records) >= CHUNK_SIZE
