"""Reading and writing bags with ``rosbags``: rosbag2 (sqlite3 or MCAP) and ROS 1.

``rosbags`` is pure Python and an optional extra of this package (``pip install
"pvfilter[bag]"``): it is imported here only, and :func:`require_rosbags` says what to
install when it is missing. The output bag has the input's format (a rosbag2 folder with
the same storage, or a ROS 1 ``.bag`` file); its connections copy the input's (message
definitions, hashes, QoS, latching), and messages are copied as bytes, never re-serialized.
Outputs are written under a hidden ``.NAME.partial`` name beside the destination and
renamed when complete, so an interrupted run leaves no half-written bag.
"""

from __future__ import annotations

import os
import shutil
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

INSTALL_HINT = 'pvfilter bag needs rosbags: pip install "pvfilter[bag]" (or: pip install rosbags)'


def require_rosbags() -> None:
    """Raises ``ImportError`` with :data:`INSTALL_HINT` when rosbags is not installed."""
    try:
        import rosbags.highlevel  # noqa: F401
    except ImportError:
        raise ImportError(INSTALL_HINT) from None


def open_reader(path: Path) -> Any:
    """An opened ``rosbags.highlevel.AnyReader`` of the bag at ``path``.

    Raises:
        ValueError: no bag at ``path``, or one rosbags cannot read.
    """
    from rosbags.highlevel import AnyReader, AnyReaderError
    from rosbags.typesys import Stores, get_typestore

    if not path.exists():
        raise ValueError(f"{path}: no such bag (a rosbag2 folder or a ROS 1 .bag file)")
    if path.is_dir() and not (path / "metadata.yaml").is_file():
        raise ValueError(f"{path}: not a rosbag2 folder (it has no metadata.yaml)")
    # bags that do not store their message definitions (rosbag2 before Iron) are read
    # with the ROS 2 Humble types
    reader = AnyReader([path], default_typestore=get_typestore(Stores.ROS2_HUMBLE))
    try:
        reader.open()
    except AnyReaderError as error:
        raise ValueError(f"{path}: not a bag rosbags can read: {error}") from None
    return reader


def is_ros1(reader: Any) -> bool:
    """True for a ROS 1 bag, False for a rosbag2."""
    return not reader.is2


def _storage_plugin(source: Path) -> Any:
    from rosbags.rosbag2 import StoragePlugin

    return StoragePlugin.MCAP if any(source.glob("*.mcap")) else StoragePlugin.SQLITE3


class BagWriter:
    """The output bag: input connections copied, new LaserScan topics added.

    Args:
        reader: the input bag's reader (its format and connections).
        source: the input bag's path.
        path: where to write (a path that does not exist).
    """

    def __init__(self, reader: Any, source: Path, path: Path) -> None:
        self.ros1 = is_ros1(reader)
        self.reader = reader
        if self.ros1:
            from rosbags.rosbag1 import Writer

            self._writer = Writer(path)
        else:
            from rosbags.rosbag2 import Writer

            self._writer = Writer(path, version=9, storage_plugin=_storage_plugin(source))
        self._writer.open()
        self.copies: dict[int, Any] = {}  # input connection id -> output connection

    def copy_connection(self, connection: Any, topic: str | None = None) -> Any:
        """An output connection like ``connection`` (on ``topic``, when given)."""
        topic = connection.topic if topic is None else topic
        msgdef, digest = connection.msgdef.data or None, connection.digest or None
        if self.ros1:
            ext = connection.ext
            return self._writer.add_connection(
                topic, connection.msgtype, typestore=self.reader.typestore, msgdef=msgdef,
                md5sum=digest, callerid=ext.callerid, latching=ext.latching,
            )  # fmt: skip
        return self._writer.add_connection(
            topic,
            connection.msgtype,
            typestore=self.reader.typestore,
            msgdef=msgdef,
            rihs01=digest,
            serialization_format=connection.ext.serialization_format,
            offered_qos_profiles=connection.ext.offered_qos_profiles
            if topic == connection.topic
            else (),
        )

    def write(self, connection: Any, stamp_ns: int, raw: bytes) -> None:
        """Write one serialized message."""
        self._writer.write(connection, stamp_ns, raw)

    def close(self) -> None:
        """Finish the bag (indexes, metadata)."""
        self._writer.close()


def _remove(path: Path) -> None:
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path, ignore_errors=True)
    else:
        path.unlink(missing_ok=True)


@contextmanager
def staged_output(out: Path, replace: bool) -> Iterator[Path]:
    """Where to write the bag ``out``: moved into place when the block completes.

    The path yielded has ``out``'s name (rosbag2 names its files after its folder) inside
    a hidden ``.NAME.partial`` folder beside ``out``. With ``replace``, an existing
    ``out`` is replaced at the end; otherwise it is refused before any work.

    Raises:
        ValueError: ``out`` exists and ``replace`` is False.
    """
    if out.exists() and not replace:
        raise ValueError(f"{out}: exists; give --force to replace it")
    staging = out.with_name(f".{out.name}.partial")
    _remove(staging)  # what a killed run left
    staging.mkdir(parents=True)
    try:
        yield staging / out.name
        if out.exists():
            old = out.with_name(f".{out.name}.old")
            _remove(old)
            os.replace(out, old)
            os.replace(staging / out.name, out)
            _remove(old)
        else:
            os.replace(staging / out.name, out)
    finally:
        _remove(staging)
