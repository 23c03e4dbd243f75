"""An MCAP file's layout, read from its summary, and its messages read chunk by chunk.

``pvfilter bag`` appends to a copy of the input instead of rewriting every message (see
:mod:`pvfilter.bag.mcap_append`); this module finds what that needs: where the data
section ends, the summary's records (kept as bytes, to be written again unchanged), the
channels and the chunk indexes. Reading the few topics the filter uses walks the records
of the chunks that hold them with ``struct``, about 0.5 µs a record, where a generic
reader builds an object per message.

The layout is that of the MCAP specification (version 0): records of one opcode byte, a
uint64 length and their content, little-endian; strings and byte arrays prefixed by a
uint32 length; maps by their uint32 byte length.
"""

from __future__ import annotations

import dataclasses
import struct
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import BinaryIO

from pvfilter.bag.chunks import merged

MAGIC = b"\x89MCAP0\r\n"
OP_FOOTER, OP_SCHEMA, OP_CHANNEL, OP_MESSAGE, OP_CHUNK = 0x02, 0x03, 0x04, 0x05, 0x06
OP_CHUNK_INDEX, OP_ATTACHMENT_INDEX, OP_STATISTICS = 0x08, 0x0A, 0x0B
OP_METADATA, OP_METADATA_INDEX, OP_SUMMARY_OFFSET, OP_DATA_END = 0x0C, 0x0D, 0x0E, 0x0F
RECORD = struct.Struct("<BQ")  # opcode, content length
U32, U64 = struct.Struct("<I"), struct.Struct("<Q")
# a message record's opcode, length, channel id, sequence, log time and publish time
MESSAGE_HEAD_SIZE = RECORD.size + 22  # bytes
FOOTER_SIZE = RECORD.size + 20 + len(MAGIC)  # bytes
DATA_END_SIZE = RECORD.size + 4  # bytes: the data section's CRC
# decompress(data, compression, uncompressed size, uncompressed CRC) -> the chunk's records
Decompress = Callable[[bytes, str, int, int], bytes]


class _Fields:
    """Reads a record's content field by field."""

    def __init__(self, content: bytes) -> None:
        self.content, self.at = content, 0

    def unpack(self, code: str) -> tuple:
        values = struct.unpack_from(f"<{code}", self.content, self.at)
        self.at += struct.calcsize(f"<{code}")
        return values

    def bytes(self) -> bytes:
        (size,) = self.unpack("I")
        self.at += size
        return self.content[self.at - size : self.at]

    def string(self) -> str:
        return self.bytes().decode("utf-8")

    def string_map(self) -> dict[str, str]:
        (size,) = self.unpack("I")
        end, found = self.at + size, {}
        while self.at < end:
            key = self.string()
            found[key] = self.string()
        return found


@dataclasses.dataclass(frozen=True)
class Channel:
    """A channel record: ``id``, ``schema_id``, ``topic``, ``encoding``, ``metadata``."""

    id: int
    schema_id: int
    topic: str
    encoding: str
    metadata: dict[str, str]


@dataclasses.dataclass(frozen=True)
class ChunkIndex:
    """A chunk index record: where a chunk is, its time range and its channels."""

    start_ns: int
    end_ns: int
    offset: int  # of the chunk record, from the start of the file
    length: int  # of the chunk record, bytes
    message_indexes: dict[int, int]  # channel id -> offset of its message index record
    index_length: int  # of the message index records after the chunk, bytes

    @property
    def channels(self) -> set[int]:
        """The channels with messages in the chunk."""
        return set(self.message_indexes)


@dataclasses.dataclass
class McapLayout:
    """What an indexed MCAP file holds, from its summary section.

    Attributes:
        path: the file.
        data_end: where its data section's DataEnd record starts.
        summary: the summary's records by opcode, as bytes (opcode and length included).
        schemas: the schema records' ``(name, encoding, data)`` by id.
        channels: the channel records by id.
        chunks: the chunk index records, in file order.
        statistics: the statistics record's counts and times (see :func:`_statistics`).
        metadata: ``(name, offset, length)`` of each metadata record, from its index.
    """

    path: Path
    data_end: int
    summary: dict[int, list[bytes]]
    schemas: dict[int, tuple[str, str, str]]
    channels: dict[int, Channel]
    chunks: list[ChunkIndex]
    statistics: dict[str, object]
    metadata: list[tuple[str, int, int]]

    @classmethod
    def read(cls, path: Path) -> McapLayout | None:
        """The layout of the MCAP file at ``path``; None when it cannot be appended to
        (no summary, no chunk index or statistics, no DataEnd record before the summary)."""
        with path.open("rb") as file:
            head = file.read(len(MAGIC))
            file.seek(-FOOTER_SIZE, 2)
            footer = file.read(FOOTER_SIZE)
            if head != MAGIC or footer[-8:] != MAGIC or footer[0] != OP_FOOTER:
                return None
            summary_start, summary_offsets = struct.unpack_from("<QQ", footer, RECORD.size)
            end = summary_offsets or file.tell() - FOOTER_SIZE
            if summary_start < DATA_END_SIZE or end <= summary_start:
                return None
            file.seek(summary_start - DATA_END_SIZE)
            data_end = file.read(DATA_END_SIZE)
            records = file.read(end - summary_start)
        if data_end[0] != OP_DATA_END:
            return None
        summary: dict[int, list[bytes]] = {}
        at = 0
        while at < len(records):
            op, size = RECORD.unpack_from(records, at)
            summary.setdefault(op, []).append(records[at : at + RECORD.size + size])
            at += RECORD.size + size
        if not summary.get(OP_CHUNK_INDEX) or len(summary.get(OP_STATISTICS, ())) != 1:
            return None
        return cls(
            path,
            summary_start - DATA_END_SIZE,
            summary,
            dict(map(_schema, summary.get(OP_SCHEMA, []))),
            {c.id: c for c in map(_channel, summary.get(OP_CHANNEL, []))},
            [_chunk_index(r) for r in summary[OP_CHUNK_INDEX]],
            _statistics(summary[OP_STATISTICS][0]),
            [_metadata_index(r) for r in summary.get(OP_METADATA_INDEX, [])],
        )

    def messages(
        self, channel_ids: set[int], decompress: Decompress
    ) -> Iterator[tuple[int, int, bytes]]:
        """``(channel id, log time ns, data)`` of the channels' messages in log-time
        order (file order between equal times), as rosbags orders them."""
        chunks = [c for c in self.chunks if c.channels & channel_ids]
        with self.path.open("rb") as file:
            yield from merged([_chunk_messages(file, c, channel_ids, decompress) for c in chunks])


def _chunk_messages(
    file: BinaryIO, chunk: ChunkIndex, channel_ids: set[int], decompress: Decompress
) -> Iterator[tuple[int, int, int, bytes]]:
    """``(log time, chunk offset, channel, data)`` of a chunk's messages of those
    channels, in log-time order (file order between equal times), found through the
    chunk's message indexes.

    A placeholder at the chunk's start time comes first (see :func:`merged`).
    """
    yield chunk.start_ns, -1, -1, b""
    file.seek(chunk.offset)
    block = memoryview(file.read(chunk.length + chunk.index_length))
    at = RECORD.size
    _, _, uncompressed_size, crc, size = struct.unpack_from("<QQQII", block, at)
    compression = bytes(block[at + 32 : at + 32 + size]).decode("utf-8")
    (compressed_size,) = U64.unpack_from(block, at + 32 + size)
    data = block[at + 40 + size : at + 40 + size + compressed_size]
    records = (
        data if not compression else decompress(bytes(data), compression, uncompressed_size, crc)
    )
    found = []
    for channel in channel_ids & chunk.channels:
        at = chunk.message_indexes[channel] - chunk.offset + RECORD.size
        (size,) = U32.unpack_from(block, at + 2)  # after the channel id
        for log_time, offset in struct.iter_unpack("<QQ", block[at + 6 : at + 6 + size]):
            (length,) = U64.unpack_from(records, offset + 1)
            start = offset + MESSAGE_HEAD_SIZE
            found.append(
                (log_time, offset, channel, bytes(records[start : offset + RECORD.size + length]))
            )
    found.sort()
    for log_time, _, channel, raw in found:
        yield log_time, chunk.offset, channel, raw


def _schema(record: bytes) -> tuple[int, tuple[str, str, str]]:
    fields = _Fields(record[RECORD.size :])
    (schema_id,) = fields.unpack("H")
    return schema_id, (fields.string(), fields.string(), fields.string())


def _channel(record: bytes) -> Channel:
    fields = _Fields(record[RECORD.size :])
    channel_id, schema_id = fields.unpack("HH")
    topic, encoding = fields.string(), fields.string()
    return Channel(channel_id, schema_id, topic, encoding, fields.string_map())


def _chunk_index(record: bytes) -> ChunkIndex:
    fields = _Fields(record[RECORD.size :])
    start, end, offset, length = fields.unpack("QQQQ")
    indexes = dict(struct.iter_unpack("<HQ", fields.bytes()))
    (index_length,) = fields.unpack("Q")
    return ChunkIndex(start, end, offset, length, indexes, index_length)


def _statistics(record: bytes) -> dict[str, object]:
    """The statistics record's fields by name, ``channel_counts`` by channel id."""
    fields = _Fields(record[RECORD.size :])
    names = ("messages", "schemas", "channels", "attachments", "metadata", "chunks")
    values = dict(zip(names, fields.unpack("QHIIII"), strict=True))
    values["start_ns"], values["end_ns"] = fields.unpack("QQ")
    (size,) = fields.unpack("I")
    counts = struct.iter_unpack("<HQ", fields.content[fields.at : fields.at + size])
    values["channel_counts"] = dict(counts)
    return values


def _metadata_index(record: bytes) -> tuple[str, int, int]:
    fields = _Fields(record[RECORD.size :])
    offset, length = fields.unpack("QQ")
    return fields.string(), offset, length


def read_metadata_record(path: Path, offset: int, length: int) -> dict[str, str]:
    """The ``metadata`` map of the metadata record at ``offset``."""
    with path.open("rb") as file:
        file.seek(offset)
        record = file.read(length)
    fields = _Fields(record[RECORD.size :])
    fields.string()  # its name
    return fields.string_map()
