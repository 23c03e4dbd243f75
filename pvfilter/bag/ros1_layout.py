"""A ROS 1 bag's layout, read from its header and index section, and its messages read
chunk by chunk.

``pvfilter bag`` appends to a copy of the input (:mod:`pvfilter.bag.ros1_append`); this
module finds what that needs (the bag header's fields, where the index section starts,
the connection and chunk info records) and reads the few connections the filter uses
through the chunk infos and the index data records after each chunk, instead of building
an index entry for every message of the bag (what rosbags' reader does when it opens a
bag: about 1 µs and 150 bytes a message).

The layout is that of the ROS bag format 2.0: records of a header (fields
``uint32 length, name=value``) and data, each prefixed by its uint32 length;
little-endian; times as ``uint32 sec, uint32 nsec``.
"""

from __future__ import annotations

import dataclasses
import struct
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import BinaryIO

from pvfilter.bag.chunks import merged

MAGIC = b"#ROSBAG V2.0\n"
OP_MSGDATA, OP_BAGHEADER, OP_IDXDATA, OP_CHUNK, OP_CHUNK_INFO, OP_CONNECTION = range(2, 8)
U32, U64 = struct.Struct("<I"), struct.Struct("<Q")
# decompress(data, compression) -> the chunk's records
Decompress = Callable[[bytes, str], bytes]


def fields(header: bytes) -> list[tuple[str, bytes]]:
    """A record header's fields, in order."""
    found, at = [], 0
    while at < len(header):
        (size,) = U32.unpack_from(header, at)
        name, _, value = header[at + 4 : at + 4 + size].partition(b"=")
        found.append((name.decode("ascii"), value))
        at += 4 + size
    return found


def stamp_ns(time: bytes) -> int:
    """A ROS 1 time field's value, ns."""
    sec, nsec = struct.unpack("<II", time)
    return sec * 1_000_000_000 + nsec


def _walk(data: bytes, at: int, count: int) -> tuple[list[tuple[bytes, bytes, bytes]], int]:
    """``count`` records from ``at``: (the whole record, its header, its data), and the
    position after them."""
    records = []
    for _ in range(count):
        (size,) = U32.unpack_from(data, at)
        header = data[at + 4 : at + 4 + size]
        (length,) = U32.unpack_from(data, at + 4 + size)
        end = at + 8 + size + length
        records.append((data[at:end], header, data[end - length : end]))
        at = end
    return records, at


def _read(file: BinaryIO) -> tuple[bytes, bytes]:
    """The header and data of the record at ``file``'s position."""
    header = file.read(U32.unpack(file.read(4))[0])
    return header, file.read(U32.unpack(file.read(4))[0])


@dataclasses.dataclass(frozen=True)
class Ros1Connection:
    """A connection record: the whole record, its topic, its data's fields in order
    (``topic``, ``type``, ``md5sum``, ``message_definition``, maybe ``callerid``,
    ``latching``)."""

    record: bytes
    topic: str
    fields: list[tuple[str, bytes]]


@dataclasses.dataclass(frozen=True)
class Ros1Chunk:
    """A chunk info record: where the chunk is, when it starts, its messages by
    connection id."""

    pos: int
    start_ns: int
    counts: dict[int, int]


@dataclasses.dataclass
class Ros1Layout:
    """A ROS 1 bag's header and index section.

    Attributes:
        path: the bag.
        header: the bag header record's fields, in order.
        index_pos: where the index section starts (the chunks end).
        connections: the connection records by id.
        chunk_infos: the chunk info records, as bytes.
        chunks: what they say.
    """

    path: Path
    header: list[tuple[str, bytes]]
    index_pos: int
    connections: dict[int, Ros1Connection]
    chunk_infos: list[bytes]
    chunks: list[Ros1Chunk]

    @classmethod
    def read(cls, path: Path) -> Ros1Layout | None:
        """The layout of the bag at ``path``; None when it cannot be appended to (not
        format 2.0, not indexed, or encrypted)."""
        with path.open("rb") as file:
            start = file.read(len(MAGIC) + 4)
            if start[: len(MAGIC)] != MAGIC:
                return None
            header = fields(file.read(U32.unpack_from(start, len(MAGIC))[0]))
            values = dict(header)
            if values.get("op") != bytes([OP_BAGHEADER]) or values.get("encryptor"):
                return None
            (index_pos,) = U64.unpack(values["index_pos"])
            (conn_count,), (chunk_count,) = (
                U32.unpack(values["conn_count"]),
                U32.unpack(values["chunk_count"]),
            )
            if not index_pos:
                return None
            file.seek(index_pos)
            index = file.read()
        connections, at = _walk(index, 0, conn_count)
        chunk_infos, _ = _walk(index, at, chunk_count)
        found = {}
        for record, head, data in connections:
            values = dict(fields(head))
            topic = values["topic"].decode("utf-8")
            found[U32.unpack(values["conn"])[0]] = Ros1Connection(record, topic, fields(data))
        chunks = []
        for _, head, data in chunk_infos:
            values = dict(fields(head))
            counts = dict(struct.iter_unpack("<II", data))
            start = stamp_ns(values["start_time"])
            chunks.append(Ros1Chunk(U64.unpack(values["chunk_pos"])[0], start, counts))
        return cls(path, header, index_pos, found, [r for r, _, _ in chunk_infos], chunks)

    def message_counts(self) -> dict[int, int]:
        """Messages by connection id, from the chunk infos."""
        counts = dict.fromkeys(self.connections, 0)
        for chunk in self.chunks:
            for conn, count in chunk.counts.items():
                counts[conn] = counts.get(conn, 0) + count
        return counts

    def messages(
        self, conn_ids: set[int], decompress: Decompress
    ) -> Iterator[tuple[int, int, bytes]]:
        """``(connection id, bag time ns, data)`` of the connections' messages in time
        order (chunk order, then position in the chunk, between equal times)."""
        chunks = [c for c in self.chunks if conn_ids & c.counts.keys()]
        with self.path.open("rb") as file:
            yield from merged([_chunk_messages(file, c, conn_ids, decompress) for c in chunks])


def _chunk_messages(
    file: BinaryIO, chunk: Ros1Chunk, conn_ids: set[int], decompress: Decompress
) -> Iterator[tuple[int, int, int, bytes]]:
    """``(time ns, chunk position, connection, data)`` of a chunk's messages of those
    connections, in time order, found through the index data records after the chunk.

    A placeholder at the chunk's start time comes first (see :func:`merged`).
    """
    yield chunk.start_ns, -1, -1, b""
    file.seek(chunk.pos)
    header, data = _read(file)
    records = decompress(data, dict(fields(header))["compression"].decode("ascii"))
    found = []
    for _ in chunk.counts:  # one index data record per connection in the chunk
        header, entries = _read(file)
        (conn,) = U32.unpack(dict(fields(header))["conn"])
        if conn in conn_ids:
            for sec, nsec, offset in struct.iter_unpack("<III", entries):
                found.append((sec * 1_000_000_000 + nsec, offset, conn, _data_at(records, offset)))
    found.sort()
    for time_ns, _, conn, raw in found:
        yield time_ns, chunk.pos, conn, raw


def _data_at(records: bytes, at: int) -> bytes:
    """The data of the message data record at ``at`` (or after the connection records
    there, as rosbags allows)."""
    while True:
        (size,) = U32.unpack_from(records, at)
        (length,) = U32.unpack_from(records, at + 4 + size)
        start = at + 8 + size
        if dict(fields(records[at + 4 : at + 4 + size])).get("op") == bytes([OP_MSGDATA]):
            return bytes(records[start : start + length])
        at = start + length
