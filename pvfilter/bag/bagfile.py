"""Reading bags with ``rosbags``; writing them through it where no copy can be appended to.

``rosbags`` is pure Python and an optional extra of this package (``pip install
"pvfilter[bag]"``): it and its YAML library are imported here only, and
:func:`require_rosbags` says what to install when it is missing.

:class:`InputBag` is the input: its connections as rosbags gives them and, for a ROS 1
bag or a rosbag2 of one MCAP file, the file's layout, through which the filtered topic's
messages are read a chunk at a time (:mod:`pvfilter.bag.ros1_layout`,
:mod:`pvfilter.bag.mcap_layout`; a ROS 1 bag is then read without rosbags' reader) and
the output is written as a copy of the input with the new topics appended
(:mod:`pvfilter.bag.outputs`). Other bags (sqlite3 storage, split or compressed files)
are copied by :class:`CopiedBag`, message by message through rosbags' writers: the
output has the input's format and connections (message definitions, hashes, QoS,
latching), and messages are copied as bytes, never re-serialized.
"""

from __future__ import annotations

import io
import struct
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

from pvfilter.bag.input_bag import InputBag
from pvfilter.bag.mcap_layout import McapLayout
from pvfilter.bag.ros1_layout import Ros1Layout

NEWEST_ROSBAG2 = 9  # the newest rosbag2 metadata version rosbags reads
INSTALL_HINT = 'pvfilter bag needs rosbags: pip install "pvfilter[bag]" (or: pip install rosbags)'


def require_rosbags() -> None:
    """Raises ``ImportError`` with :data:`INSTALL_HINT` when rosbags is not installed."""
    try:
        import rosbags.highlevel  # noqa: F401
    except ImportError:
        raise ImportError(INSTALL_HINT) from None


def open_reader(path: Path) -> InputBag:
    """The bag at ``path``, opened: read through its file's layout where it has one,
    through rosbags' reader otherwise.

    Raises:
        ValueError: no bag at ``path``, or one rosbags cannot read.
    """
    from rosbags.rosbag1 import Reader as Reader1
    from rosbags.rosbag1 import ReaderError as Reader1Error
    from rosbags.rosbag2 import Reader as Reader2
    from rosbags.rosbag2 import ReaderError as Reader2Error

    if not path.exists():
        raise ValueError(f"{path}: no such bag (a rosbag2 folder or a ROS 1 .bag file)")
    if path.is_dir() and not (path / "metadata.yaml").is_file():
        raise ValueError(f"{path}: not a rosbag2 folder (it has no metadata.yaml)")
    is2 = path.suffix != ".bag"  # as rosbags' AnyReader tells them apart
    try:
        bag = _mcap_rosbag2(path) if is2 else _indexed_ros1(path)
    except (OSError, struct.error, KeyError, TypeError, ValueError, UnicodeDecodeError):
        bag = None  # rosbags' reader says what is wrong
    if bag is not None:
        return bag
    reader = Reader2(path) if is2 else Reader1(path)
    try:
        reader.open()
    except (Reader1Error, Reader2Error) as error:
        raise ValueError(f"{path}: not a bag rosbags can read: {error}") from None
    return InputBag(path, reader, reader.connections, is2=is2)


def _indexed_ros1(path: Path) -> InputBag | None:
    """A ROS 1 bag read through its index section, its connections as rosbags' reader
    gives them (which first indexes every message of the bag: about 1 µs and 150 bytes
    apiece); None for a bag that is not format 2.0, not indexed, or encrypted."""
    from rosbags.interfaces import (
        Connection,
        ConnectionExtRosbag1,
        MessageDefinition,
        MessageDefinitionFormat,
    )
    from rosbags.rosbag1.reader import decompressors, normalize
    from rosbags.typesys.msg import normalize_msgtype

    layout = Ros1Layout.read(path)
    if layout is None:
        return None
    counts, connections = layout.message_counts(), []
    for conn, record in layout.connections.items():
        values = {name: value.decode("utf-8") for name, value in record.fields}
        definition = MessageDefinition(MessageDefinitionFormat.MSG, values["message_definition"])
        latching = values.get("latching")
        ext = ConnectionExtRosbag1(values.get("callerid"), int(latching) if latching else None)
        msgtype = normalize_msgtype(values["type"])
        topic = normalize(record.topic)
        connections.append(
            Connection(conn, topic, msgtype, definition, values["md5sum"], counts[conn], ext, None)
        )

    def decompress(data: bytes, compression: str) -> bytes:
        if compression not in decompressors:
            raise ValueError(f"{path}: chunk compression {compression!r} is not supported")
        return decompressors[compression](data)

    return InputBag(path, None, connections, is2=False, layout=layout, decompress=decompress)


def _mcap_rosbag2(path: Path) -> InputBag | None:
    """A rosbag2 of one MCAP file read through the file's summary, its connections as
    rosbags' reader gives them; None for other storage, several files, a file compressed
    as a whole, an MCAP file without summary, a topic on two channels."""
    from rosbags.interfaces import (
        Connection,
        ConnectionExtRosbag2,
        MessageDefinition,
        MessageDefinitionFormat,
    )
    from rosbags.rosbag2.metadata import parse_qos
    from rosbags.rosbag2.storage_mcap import decompress

    metadata = load_yaml(path / "metadata.yaml")
    info = metadata["rosbag2_bagfile_information"]
    files = info["relative_file_paths"]
    mode = str(info.get("compression_mode") or "none").lower()
    if info["storage_identifier"] != "mcap" or len(files) != 1 or mode != "none":
        return None
    if info["version"] > 9:
        return None
    layout = McapLayout.read(path / Path(files[0]).name)
    if layout is None:
        return None
    by_topic = {c.topic: c for c in layout.channels.values()}
    formats = {"ros2msg": MessageDefinitionFormat.MSG, "ros2idl": MessageDefinitionFormat.IDL}
    formats |= {"omgidl": MessageDefinitionFormat.IDL}
    definitions = {}  # by type: the first schema that has one, as rosbags takes it
    for channel in layout.channels.values():
        name, encoding, data = layout.schemas[channel.schema_id]
        if encoding in formats:
            definitions.setdefault(name, MessageDefinition(formats[encoding], data))
    none = MessageDefinition(MessageDefinitionFormat.NONE, "")
    connections, keys = [], {}
    for index, entry in enumerate(info["topics_with_message_count"], start=1):
        topic = entry["topic_metadata"]
        if topic["serialization_format"] != "cdr" or topic["name"] not in by_topic:
            return None
        qos = parse_qos(topic.get("offered_qos_profiles", []))
        ext = ConnectionExtRosbag2(topic["serialization_format"], qos)
        digest = topic.get("type_description_hash", "")
        msgtype, count = topic["type"], entry["message_count"]
        definition = definitions.get(msgtype, none)
        connections.append(
            Connection(index, topic["name"], msgtype, definition, digest, count, ext, None)
        )
        keys[index] = by_topic[topic["name"]].id
    if len(by_topic) < len(layout.channels):
        return None  # a topic on two channels
    return InputBag(
        path, None, connections, is2=True, layout=layout, metadata=metadata, keys=keys,
        decompress=decompress,
    )  # fmt: skip


def load_yaml(path: Path) -> Any:
    """The YAML document in the file at ``path`` (safe types only).

    Raises:
        ValueError: the file is not YAML.
    """
    from ruamel.yaml import YAML
    from ruamel.yaml.error import YAMLError

    try:
        return YAML(typ="safe").load(path.read_text(encoding="utf-8"))
    except YAMLError as error:
        raise ValueError(f"{path}: not YAML ({error})") from None


def dump_yaml(data: Any) -> str:
    """``data`` as a block-style YAML document, as rosbag2 writes its metadata (no line
    folded, so that the document indented is the same one a level down)."""
    from ruamel.yaml import YAML

    yaml = YAML(typ="safe")
    yaml.default_flow_style = False
    yaml.width = 1 << 16  # characters
    text = io.StringIO()
    yaml.dump(data, text)
    return text.getvalue()


def _typestore(path: Path) -> Any:
    """The message types of the bag at ``path`` (those it stores, ROS 2 Humble's where it
    has none), from rosbags' ``AnyReader``: it parses every connection's message
    definition (50-200 ms), which only :class:`CopiedBag` needs."""
    from rosbags.highlevel import AnyReader, AnyReaderError
    from rosbags.typesys import Stores, get_typestore

    try:
        with AnyReader([path], default_typestore=get_typestore(Stores.ROS2_HUMBLE)) as typed:
            return typed.typestore
    except AnyReaderError as error:
        raise ValueError(f"{path}: not a bag rosbags can read: {error}") from None


def _storage_plugin(source: Path) -> Any:
    """The storage of the input bag, for the output to keep: MCAP for a folder of
    ``.mcap`` files or a bare ``.mcap`` file (rosbags reads one), else sqlite3."""
    from rosbags.rosbag2 import StoragePlugin

    mcap = source.suffix == ".mcap" if source.is_file() else any(source.glob("*.mcap"))
    return StoragePlugin.MCAP if mcap else StoragePlugin.SQLITE3


class CopiedBag:
    """The output bag written through rosbags: every input message copied, one by one.

    Args:
        bag: the input bag.
        path: where to write (a path that does not exist).
    """

    def __init__(self, bag: InputBag, path: Path) -> None:
        self.ros1 = not bag.is2
        self.typestore = _typestore(bag.path)
        if self.ros1:
            from rosbags.rosbag1 import Writer

            self._writer = Writer(path)
        else:
            from rosbags.rosbag2 import Writer

            self._writer = Writer(path, version=9, storage_plugin=_storage_plugin(bag.path))
        self._writer.open()
        self._copies = {c.id: self.add_topic(c, c.topic) for c in bag.connections}

    def add_topic(self, connection: Any, topic: str) -> Any:
        """An output connection like ``connection`` on ``topic``."""
        msgdef, digest = connection.msgdef.data or None, connection.digest or None
        if self.ros1:
            ext = connection.ext
            return self._writer.add_connection(
                topic, connection.msgtype, typestore=self.typestore, msgdef=msgdef,
                md5sum=digest, callerid=ext.callerid, latching=ext.latching,
            )  # fmt: skip
        return self._writer.add_connection(
            topic,
            connection.msgtype,
            typestore=self.typestore,
            msgdef=msgdef,
            rihs01=digest,
            serialization_format=connection.ext.serialization_format,
            offered_qos_profiles=connection.ext.offered_qos_profiles
            if topic == connection.topic
            else (),
        )

    def read_through(
        self, bag: InputBag, connections: Sequence[Any]
    ) -> Iterator[tuple[Any, int, bytes]]:
        """Copy every input message; yield those of ``connections`` on the way."""
        wanted = {c.id for c in connections}
        for connection, stamp_ns, raw in bag.messages():
            self._writer.write(self._copies[connection.id], stamp_ns, raw)
            if connection.id in wanted:
                yield connection, stamp_ns, raw

    def write(self, connection: Any, stamp_ns: int, raw: bytes) -> None:
        """Write one serialized message."""
        self._writer.write(connection, stamp_ns, raw)

    def close(self) -> None:
        """Finish the bag (indexes, metadata)."""
        self._writer.close()

    def abort(self) -> None:
        """Stop without finishing the bag (the caller removes it)."""
        self._writer.abort()
