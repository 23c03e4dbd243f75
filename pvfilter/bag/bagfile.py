"""Reading bags with ``rosbags``; writing them through it where no copy can be appended to.

``rosbags`` is pure Python and an optional extra of this package (``pip install
"pvfilter[bag]"``): it and its YAML library are imported here only, and
:func:`require_rosbags` says what to install when it is missing.

:class:`InputBag` is the input: rosbags' reader (connections, message types) and,
for a ROS 1 bag or a rosbag2 of one MCAP file, the file's layout, through which the
filtered topic's messages are read a chunk at a time (:mod:`pvfilter.bag.mcap_layout`)
and the output is written as a copy of the input with the new topics appended
(:mod:`pvfilter.bag.outputs`). Other bags (sqlite3 storage, split or compressed files)
are copied by :class:`CopiedBag`, message by message through rosbags' writers: the
output has the input's format and connections (message definitions, hashes, QoS,
latching), and messages are copied as bytes, never re-serialized.
"""

from __future__ import annotations

import io
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

from pvfilter.bag.mcap_layout import Decompress, McapLayout
from pvfilter.bag.ros1_append import Ros1Layout

INSTALL_HINT = 'pvfilter bag needs rosbags: pip install "pvfilter[bag]" (or: pip install rosbags)'


def require_rosbags() -> None:
    """Raises ``ImportError`` with :data:`INSTALL_HINT` when rosbags is not installed."""
    try:
        import rosbags.highlevel  # noqa: F401
    except ImportError:
        raise ImportError(INSTALL_HINT) from None


def open_reader(path: Path) -> InputBag:
    """The bag at ``path``, opened.

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
    reader = Reader2(path) if is2 else Reader1(path)
    try:
        reader.open()
    except (Reader1Error, Reader2Error) as error:
        raise ValueError(f"{path}: not a bag rosbags can read: {error}") from None
    try:
        return InputBag(path, reader, is2)
    except BaseException:
        reader.close()
        raise


def load_yaml(path: Path) -> Any:
    """The YAML document in the file at ``path`` (safe types only)."""
    from ruamel.yaml import YAML

    return YAML(typ="safe").load(path.read_text(encoding="utf-8"))


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


def _mcap_decompress() -> Decompress | None:
    """rosbags' decompression of MCAP chunks (lz4, zstd); None where it has none."""
    try:
        from rosbags.rosbag2.storage_mcap import decompress
    except ImportError:
        return None
    return decompress


class InputBag:
    """An opened input bag: rosbags' reader, and its file's layout where there is one.

    The reader of message types (rosbags' ``AnyReader``, which parses every connection's
    message definition: 50-200 ms) is opened only when :attr:`typestore` is asked for.

    Args:
        path: the bag (a rosbag2 folder or a ROS 1 file).
        reader: rosbags' reader of it (``rosbag1.Reader`` or ``rosbag2.Reader``), open.
        is2: True for a rosbag2.

    Attributes:
        layout: a :class:`Ros1Layout` for a ROS 1 bag, a :class:`McapLayout` for a rosbag2
            of one MCAP file with a summary (its chunks compressed or not, the file not);
            None otherwise.
        metadata: a rosbag2's ``metadata.yaml`` (None for ROS 1).
    """

    def __init__(self, path: Path, reader: Any, is2: bool) -> None:
        self.path, self.reader, self.is2 = path, reader, is2
        self.connections = reader.connections
        self._typed: Any = None  # the AnyReader, once opened
        self.layout: McapLayout | Ros1Layout | None = None
        self.metadata: dict[str, Any] | None = None
        self._channels: dict[int, int] = {}  # connection id -> MCAP channel id
        self._decompress = _mcap_decompress()
        if not self.is2:
            self.layout = Ros1Layout.read(path)
            return
        self.metadata = load_yaml(path / "metadata.yaml")
        info = self.metadata["rosbag2_bagfile_information"]
        files = info.get("relative_file_paths", [])
        if (
            info.get("storage_identifier") != "mcap"
            or len(files) != 1
            or str(info.get("compression_mode") or "none").lower() != "none"
        ):
            return
        layout = McapLayout.read(path / Path(files[0]).name)
        topics = [c.topic for c in layout.channels.values()] if layout else []
        by_topic = {c.topic: c.id for c in layout.channels.values()} if layout else {}
        if (
            layout
            and len(set(topics)) == len(topics)
            and all(c.topic in by_topic for c in self.connections)
        ):
            self.layout = layout
            self._channels = {c.id: by_topic[c.topic] for c in self.connections}

    def channel_of(self, connection: Any) -> int:
        """The MCAP channel id of a connection of a rosbag2 with an MCAP layout."""
        return self._channels[connection.id]

    def messages(self, connections: Sequence[Any] = ()) -> Iterator[tuple[Any, int, bytes]]:
        """``(connection, bag stamp ns, bytes)`` of ``connections``' messages (all when
        empty) in time order, as rosbags' reader gives them."""
        if isinstance(self.layout, McapLayout) and connections and self._decompress:
            by_channel = {self._channels[c.id]: c for c in connections}
            for channel, stamp_ns, raw in self.layout.messages(set(by_channel), self._decompress):
                yield by_channel[channel], stamp_ns, raw
        else:
            yield from self.reader.messages(connections=connections)

    @property
    def typestore(self) -> Any:
        """The bag's message types (those it stores; ROS 2 Humble's where it has none)."""
        from rosbags.highlevel import AnyReader, AnyReaderError
        from rosbags.typesys import Stores, get_typestore

        if self._typed is None:
            typed = AnyReader([self.path], default_typestore=get_typestore(Stores.ROS2_HUMBLE))
            try:
                typed.open()
            except AnyReaderError as error:
                raise ValueError(f"{self.path}: not a bag rosbags can read: {error}") from None
            self._typed = typed
        return self._typed.typestore

    def close(self) -> None:
        """Close the readers."""
        self.reader.close()
        if self._typed is not None:
            self._typed.close()


def _storage_plugin(source: Path) -> Any:
    from rosbags.rosbag2 import StoragePlugin

    return StoragePlugin.MCAP if any(source.glob("*.mcap")) else StoragePlugin.SQLITE3


class CopiedBag:
    """The output bag written through rosbags: every input message copied, one by one.

    Args:
        bag: the input bag.
        path: where to write (a path that does not exist).
    """

    def __init__(self, bag: InputBag, path: Path) -> None:
        self.ros1 = not bag.is2
        self.bag = bag
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
                topic, connection.msgtype, typestore=self.bag.typestore, msgdef=msgdef,
                md5sum=digest, callerid=ext.callerid, latching=ext.latching,
            )  # fmt: skip
        return self._writer.add_connection(
            topic,
            connection.msgtype,
            typestore=self.bag.typestore,
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
