"""Writing an MCAP file as a copy of another with new channels appended.

Copying a bag message by message costs 10-20 µs a message in Python; a LiDAR bag has
about 35 messages a scan (IMU, odometry, tf), so the copy alone took longer than the
filter. Here the input's data section (its header, chunks and message indexes) is copied
as one block of bytes, so every input message keeps its bytes, its log time and its
place; the new channels' messages follow in chunks of their own (uncompressed), and a
new summary indexes old and new chunks together. Readers merge chunks by log time, as
they do for any MCAP file whose chunks overlap in time.
"""

from __future__ import annotations

import struct
import zlib
from pathlib import Path

from pvfilter.bag.chunks import OpenChunk, copy_prefix
from pvfilter.bag.mcap_layout import (
    MAGIC,
    OP_ATTACHMENT_INDEX,
    OP_CHANNEL,
    OP_CHUNK,
    OP_CHUNK_INDEX,
    OP_DATA_END,
    OP_FOOTER,
    OP_MESSAGE,
    OP_METADATA,
    OP_METADATA_INDEX,
    OP_SCHEMA,
    OP_STATISTICS,
    OP_SUMMARY_OFFSET,
    RECORD,
    McapLayout,
)

OP_MESSAGE_INDEX = 0x07
MESSAGE_HEAD = struct.Struct("<BQHIQQ")  # opcode, length, channel, sequence, log, publish time
# the summary's groups, in the order they are written
SUMMARY_ORDER = (OP_SCHEMA, OP_CHANNEL, OP_CHUNK_INDEX, OP_ATTACHMENT_INDEX, OP_METADATA_INDEX)


def _string(text: str | bytes) -> bytes:
    data = text.encode("utf-8") if isinstance(text, str) else text
    return struct.pack("<I", len(data)) + data


def _string_map(values: dict[str, str]) -> bytes:
    return _string(b"".join(_string(k) + _string(v) for k, v in values.items()))


def _record(op: int, content: bytes) -> bytes:
    return RECORD.pack(op, len(content)) + content


def _summary(groups: dict[int, list[bytes]], start: int) -> bytes:
    """The summary section from ``start``: the groups of records (by opcode; statistics
    last), their summary offsets, and the footer with the summary's CRC."""
    order = [*SUMMARY_ORDER, *sorted(set(groups) - set(SUMMARY_ORDER) - {OP_STATISTICS})]
    summary, offsets = bytearray(), bytearray()
    for op in [*order, OP_STATISTICS]:
        if groups.get(op):
            group = b"".join(groups[op])
            at = struct.pack("<BQQ", op, start + len(summary), len(group))
            offsets += _record(OP_SUMMARY_OFFSET, at)
            summary += group
    footer = RECORD.pack(OP_FOOTER, 20) + struct.pack("<QQ", start, start + len(summary))
    summary += offsets + footer
    return bytes(summary) + struct.pack("<I", zlib.crc32(summary)) + MAGIC


class McapAppender:
    """A copy of an MCAP file, new channels and their messages appended.

    Args:
        layout: the input file's layout.
        path: the file to write (it must not exist).
        replaced_metadata: the name of a metadata record that :meth:`close` writes anew;
            the input's record of that name is left out when it ends the data section
            (where writers put it), and its index is dropped in any case.
    """

    def __init__(self, layout: McapLayout, path: Path, replaced_metadata: str = "") -> None:
        self.layout = layout
        copy_end = layout.data_end
        for name, offset, length in layout.metadata:
            if name == replaced_metadata and offset + length == layout.data_end:
                copy_end = offset
        self._file = path.open("xb")
        copy_prefix(layout.path, self._file, copy_end)
        self._next_channel = max(layout.channels, default=0) + 1
        self._channels: list[bytes] = []
        self._chunk_indexes: list[bytes] = []
        self._counts: dict[int, int] = {}
        self._chunk = OpenChunk()

    def add_channel(self, like: int, topic: str, metadata: dict[str, str]) -> int:
        """A new channel like channel ``like`` (its schema and encoding) on ``topic``;
        returns its id."""
        channel, channel_id = self.layout.channels[like], self._next_channel
        self._next_channel += 1
        content = struct.pack("<HH", channel_id, channel.schema_id) + _string(topic)
        record = _record(OP_CHANNEL, content + _string(channel.encoding) + _string_map(metadata))
        self._file.write(record)  # before the chunks that use it, for streaming readers
        self._channels.append(record)
        self._counts[channel_id] = 0
        return channel_id

    def write(self, channel_id: int, log_time_ns: int, data: bytes) -> None:
        """Add one message (its publish time is its log time, as rosbags writes it)."""
        head = MESSAGE_HEAD.pack(
            OP_MESSAGE, 22 + len(data), channel_id, 0, log_time_ns, log_time_ns
        )
        self._counts[channel_id] += 1
        if self._chunk.add(channel_id, log_time_ns, head + data):
            self._write_chunk()

    def _write_chunk(self) -> None:
        """The open chunk, its message indexes, and its index for the summary."""
        chunk = self._chunk
        if chunk.start_ns is None or chunk.end_ns is None:
            return
        records, start, end = bytes(chunk.records), chunk.start_ns, chunk.end_ns
        file, offset = self._file, self._file.tell()
        head = struct.pack("<QQQI", start, end, len(records), zlib.crc32(records))
        file.write(
            _record(OP_CHUNK, head + _string("") + struct.pack("<Q", len(records)) + records)
        )
        length = file.tell() - offset
        index_offsets = b""
        for channel_id, entries in chunk.index.items():
            index_offsets += struct.pack("<HQ", channel_id, file.tell())
            pairs = b"".join(struct.pack("<QQ", t, at) for t, at in entries)
            file.write(_record(OP_MESSAGE_INDEX, struct.pack("<H", channel_id) + _string(pairs)))
        index_length = file.tell() - offset - length
        content = struct.pack("<QQQQ", start, end, offset, length) + _string(index_offsets)
        content += struct.pack("<Q", index_length) + _string("")
        self._chunk_indexes.append(
            _record(OP_CHUNK_INDEX, content + struct.pack("<QQ", len(records), len(records)))
        )
        self._chunk = OpenChunk()

    def close(self, metadata: dict[str, dict[str, str]]) -> None:
        """Finish the file: the last chunk, ``metadata`` records (name: key-value map),
        the data section's end, the summary and the footer."""
        self._write_chunk()
        file, layout = self._file, self.layout
        kept = zip(layout.summary.get(OP_METADATA_INDEX, []), layout.metadata, strict=True)
        indexes = [record for record, (name, _, _) in kept if name not in metadata]
        for name, values in metadata.items():
            offset = file.tell()
            file.write(_record(OP_METADATA, _string(name) + _string_map(values)))
            at = struct.pack("<QQ", offset, file.tell() - offset)
            indexes.append(_record(OP_METADATA_INDEX, at + _string(name)))
        file.write(_record(OP_DATA_END, struct.pack("<I", 0)))  # 0: no CRC of the data
        groups = dict(layout.summary)
        groups[OP_CHANNEL] = groups.get(OP_CHANNEL, []) + self._channels
        groups[OP_CHUNK_INDEX] = groups[OP_CHUNK_INDEX] + self._chunk_indexes
        groups[OP_METADATA_INDEX] = indexes
        groups[OP_STATISTICS] = [self._statistics(len(indexes))]
        groups.pop(OP_SUMMARY_OFFSET, None)  # written anew
        file.write(_summary(groups, file.tell()))
        file.close()

    def _statistics(self, metadata_count: int) -> bytes:
        """The statistics record, the new channels, chunks and messages counted."""
        old, new = self.layout.statistics, self._counts
        times = [struct.unpack_from("<QQ", r, RECORD.size) for r in self._chunk_indexes]
        if old["messages"]:
            times.append((old["start_ns"], old["end_ns"]))
        start, end = (min(t[0] for t in times), max(t[1] for t in times)) if times else (0, 0)
        counts = {**old["channel_counts"], **new}
        content = struct.pack(
            "<QHIIII",
            old["messages"] + sum(new.values()),
            old["schemas"],
            old["channels"] + len(new),
            old["attachments"],
            metadata_count,
            len(self.layout.chunks) + len(self._chunk_indexes),
        )
        content += struct.pack("<QQ", start, end)
        content += _string(b"".join(struct.pack("<HQ", c, n) for c, n in sorted(counts.items())))
        return _record(OP_STATISTICS, content)

    @property
    def counts(self) -> dict[int, int]:
        """Messages written so far, by new channel id."""
        return dict(self._counts)

    def abort(self) -> None:
        """Close the file unfinished (the caller removes it)."""
        self._file.close()
