"""The output bag: a copy of the input with the new topics appended, where the format allows.

Every output gives ``add_topic``, ``read_through``, ``write``, ``close`` and ``abort``:
:func:`open_output` picks :class:`AppendedRosbag2` (a rosbag2 of one MCAP file) or
:class:`AppendedRos1` (a ROS 1 bag), which copy the input's recorded bytes in one block
and read only the filtered topic's messages; any other bag is copied message by message
through rosbags (:class:`pvfilter.bag.bagfile.CopiedBag`). Either way every input message
keeps its bytes and its bag stamp.
"""

from __future__ import annotations

import copy
import textwrap
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

from pvfilter.bag.bagfile import CopiedBag, dump_yaml
from pvfilter.bag.input_bag import InputBag
from pvfilter.bag.mcap_append import McapAppender
from pvfilter.bag.mcap_layout import McapLayout, read_metadata_record
from pvfilter.bag.ros1_append import Ros1Appender
from pvfilter.bag.ros1_layout import Ros1Layout

ROSBAG2_METADATA = "rosbag2"  # the MCAP metadata record rosbag2 keeps its metadata in
INFORMATION = "rosbag2_bagfile_information"  # metadata.yaml's one key


def open_output(bag: InputBag, path: Path) -> AppendedRosbag2 | AppendedRos1 | CopiedBag:
    """The output bag at ``path`` (which must not exist), in ``bag``'s format."""
    if isinstance(bag.layout, McapLayout):
        return AppendedRosbag2(bag, path)
    if isinstance(bag.layout, Ros1Layout):
        return AppendedRos1(bag, path)
    return CopiedBag(bag, path)


class _Appended:
    """What the appended outputs share: the input's messages are in the copy already."""

    _appender: McapAppender | Ros1Appender

    def read_through(
        self, bag: InputBag, connections: Sequence[Any]
    ) -> Iterator[tuple[Any, int, bytes]]:
        """``connections``' messages; the others are in the copy already."""
        return bag.messages(connections)

    def write(self, key: int, stamp_ns: int, raw: bytes) -> None:
        """Write one serialized message on a new topic (``key``: what add_topic gave)."""
        self._appender.write(key, stamp_ns, raw)

    def abort(self) -> None:
        """Stop without finishing the bag (the caller removes it)."""
        self._appender.abort()


class AppendedRos1(_Appended):
    """A ROS 1 bag: the input's bytes, the new connections appended.

    Args:
        bag: the input (a ROS 1 bag with a layout).
        path: the bag file to write.
    """

    def __init__(self, bag: InputBag, path: Path) -> None:
        assert isinstance(bag.layout, Ros1Layout)
        self._appender = Ros1Appender(bag.layout, path)

    def add_topic(self, connection: Any, topic: str) -> int:
        """A new connection like ``connection`` (type, definition, caller) on ``topic``."""
        return self._appender.add_connection(connection.id, topic)

    def close(self) -> None:
        """Finish the bag (index section, header)."""
        self._appender.close()


class AppendedRosbag2(_Appended):
    """A rosbag2 folder: its MCAP file the input's bytes with the new channels appended,
    its ``metadata.yaml`` the input's with the new topics and counts.

    Args:
        bag: the input (a rosbag2 with an MCAP layout).
        path: the folder to write; its file is named after it, as rosbag2 names it.
    """

    def __init__(self, bag: InputBag, path: Path) -> None:
        assert isinstance(bag.layout, McapLayout) and bag.metadata is not None
        self.bag, self.path = bag, path
        path.mkdir()
        self._file = path / f"{path.name}.mcap"
        self._appender = McapAppender(bag.layout, self._file, ROSBAG2_METADATA)
        self._topics: list[tuple[Any, str, int]] = []  # (like, topic, channel id)

    def add_topic(self, connection: Any, topic: str) -> int:
        """A new channel like ``connection``'s (schema, encoding) on ``topic``, no QoS."""
        like = self.bag.channel_of(connection)
        metadata = dict(self.bag.layout.channels[like].metadata)
        metadata["offered_qos_profiles"] = "[]"  # as rosbags writes an empty list
        channel = self._appender.add_channel(like, topic, metadata)
        self._topics.append((connection, topic, channel))
        return channel

    def close(self) -> None:
        """Finish the MCAP file (with rosbag2's metadata record, where the input had
        one) and write ``metadata.yaml``."""
        info = self._information()
        document = f"{INFORMATION}:\n" + textwrap.indent(info, "  ")  # one dump, not two
        records = {}
        for name, offset, length in self.bag.layout.metadata:
            if name == ROSBAG2_METADATA:
                values = read_metadata_record(self.bag.layout.path, offset, length)
                # as the input had it: metadata.yaml's content, or what is under its key
                wrapped = values.get("serialized_metadata", "").startswith(INFORMATION)
                values["serialized_metadata"] = (document if wrapped else info).strip()
                records[name] = values
        self._appender.close(records)
        (self.path / "metadata.yaml").write_text(document, encoding="utf-8")

    def _information(self) -> str:
        """The input's ``rosbag2_bagfile_information`` with the new topics, file name and
        message counts, as YAML."""
        info = copy.deepcopy(self.bag.metadata[INFORMATION])
        counts = self._appender.counts
        added = sum(counts.values())
        info["relative_file_paths"] = [self._file.name]
        info["message_count"] += added
        for entry in info.get("files") or []:
            entry["path"], entry["message_count"] = self._file.name, entry["message_count"] + added
        topics = info["topics_with_message_count"]
        for connection, topic, channel in self._topics:
            like = next(t for t in topics if t["topic_metadata"]["name"] == connection.topic)
            entry = copy.deepcopy(like)
            entry["message_count"] = counts[channel]
            entry["topic_metadata"]["name"] = topic
            qos = entry["topic_metadata"].get("offered_qos_profiles")
            entry["topic_metadata"]["offered_qos_profiles"] = [] if isinstance(qos, list) else ""
            topics.append(entry)
        return dump_yaml(info)
