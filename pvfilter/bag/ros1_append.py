"""Writing a ROS 1 bag as a copy of another with new connections appended.

As for MCAP (:mod:`pvfilter.bag.mcap_append`), the input is not rewritten message by
message: its chunks and their index records, everything before the index section, are
copied as one block of bytes; the new connections' messages follow in chunks of their
own (uncompressed), and the index section (connection records, chunk infos) is written
again with the new ones added; the bag header, padded to a fixed size, is rewritten in
place with the new index position and counts. Readers order messages by the index, so
chunks that overlap in time read as one time-ordered bag.

The records are those of the ROS bag format 2.0 (:mod:`pvfilter.bag.ros1_layout`).
"""

from __future__ import annotations

import struct
from pathlib import Path

from pvfilter.bag.chunks import OpenChunk, copy_prefix
from pvfilter.bag.ros1_layout import (
    MAGIC,
    OP_CHUNK,
    OP_CHUNK_INFO,
    OP_CONNECTION,
    OP_IDXDATA,
    OP_MSGDATA,
    U32,
    U64,
    Ros1Layout,
)


def _header(fields: list[tuple[str, bytes]]) -> bytes:
    return b"".join(U32.pack(len(n) + 1 + len(v)) + n.encode() + b"=" + v for n, v in fields)


def _record(fields: list[tuple[str, bytes]], data: bytes) -> bytes:
    header = _header(fields)
    return U32.pack(len(header)) + header + U32.pack(len(data)) + data


def _time(stamp_ns: int) -> bytes:
    return struct.pack("<II", *divmod(stamp_ns, 1_000_000_000))


def _op(code: int) -> tuple[str, bytes]:
    return "op", bytes([code])


class Ros1Appender:
    """A copy of a ROS 1 bag, new connections and their messages appended.

    Args:
        layout: the input bag's layout.
        path: the bag to write (it must not exist).
    """

    def __init__(self, layout: Ros1Layout, path: Path) -> None:
        self.layout = layout
        self._file = path.open("xb")
        copy_prefix(layout.path, self._file, layout.index_pos)
        self._next_id = max(layout.connections, default=-1) + 1
        self._connections: list[bytes] = []
        self._chunk_infos: list[bytes] = []
        self._heads: dict[int, bytes] = {}  # by connection: its message records' start
        self._chunk = OpenChunk()

    def add_connection(self, like: int, topic: str) -> int:
        """A new connection like connection ``like`` (type, definition, caller) on
        ``topic``; returns its id."""
        fields = [
            (n, topic.encode() if n == "topic" else v)
            for n, v in self.layout.connections[like].fields
        ]
        conn = self._next_id
        self._next_id += 1
        record = _record(
            [_op(OP_CONNECTION), ("conn", U32.pack(conn)), ("topic", topic.encode())],
            _header(fields),
        )
        self._connections.append(record)
        self._chunk.records += record  # a chunk holds a connection's record before its messages
        # its messages' records start alike, up to the time's value
        header = _header([_op(OP_MSGDATA), ("conn", U32.pack(conn)), ("time", bytes(8))])
        self._heads[conn] = U32.pack(len(header)) + header[:-8]
        return conn

    def write(self, conn: int, stamp_ns: int, data: bytes) -> None:
        """Add one message, stamped ``stamp_ns`` in the bag."""
        record = b"".join((self._heads[conn], _time(stamp_ns), U32.pack(len(data)), data))
        if self._chunk.add(conn, stamp_ns, record):
            self._write_chunk()

    def _write_chunk(self) -> None:
        """The open chunk, its index data records, and its chunk info for the index."""
        chunk = self._chunk
        if chunk.start_ns is None or chunk.end_ns is None:
            return  # no message (connection records alone are in the index section too)
        file, pos = self._file, self._file.tell()
        size = U32.pack(len(chunk.records))
        file.write(
            _record([_op(OP_CHUNK), ("compression", b"none"), ("size", size)], bytes(chunk.records))
        )
        counts = b""
        for conn, entries in chunk.index.items():
            fields = [
                _op(OP_IDXDATA),
                ("ver", U32.pack(1)),
                ("conn", U32.pack(conn)),
                ("count", U32.pack(len(entries))),
            ]
            file.write(_record(fields, b"".join(_time(t) + U32.pack(at) for t, at in entries)))
            counts += U32.pack(conn) + U32.pack(len(entries))
        fields = [_op(OP_CHUNK_INFO), ("ver", U32.pack(1)), ("chunk_pos", U64.pack(pos))]
        fields += [
            ("start_time", _time(chunk.start_ns)),
            ("end_time", _time(chunk.end_ns)),
            ("count", U32.pack(len(chunk.index))),
        ]
        self._chunk_infos.append(_record(fields, counts))
        self._chunk = OpenChunk()

    def close(self) -> None:
        """Finish the bag: the last chunk, the index section and the bag header."""
        self._write_chunk()
        file, layout = self._file, self.layout
        index_pos = file.tell()
        for connection in layout.connections.values():
            file.write(connection.record)
        file.write(b"".join(self._connections))
        file.write(b"".join(layout.chunk_infos + self._chunk_infos))
        values = {
            "index_pos": U64.pack(index_pos),
            "conn_count": U32.pack(len(layout.connections) + len(self._connections)),
            "chunk_count": U32.pack(len(layout.chunk_infos) + len(self._chunk_infos)),
        }
        file.seek(len(MAGIC) + 4)  # the header's fields: same names, same sizes
        file.write(_header([(n, values.get(n, v)) for n, v in layout.header]))
        file.close()

    def abort(self) -> None:
        """Close the file unfinished (the caller removes it)."""
        self._file.close()
