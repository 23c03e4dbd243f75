"""The input bag as the command reads it: its connections, and the layout of its file.

Built by :func:`pvfilter.bag.bagfile.open_reader`. Where the layout reads the messages
(:meth:`McapLayout.messages`, :meth:`Ros1Layout.messages`), only the topics asked for are
read, a chunk at a time; elsewhere rosbags' reader reads them.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any

from pvfilter.bag.mcap_layout import McapLayout
from pvfilter.bag.ros1_layout import Ros1Layout


class InputBag:
    """An opened input bag: its connections, and its file's layout or rosbags' reader.

    Args:
        path: the bag (a rosbag2 folder or a ROS 1 file).
        reader: rosbags' reader of it (``rosbag1.Reader`` or ``rosbag2.Reader``), open;
            None where the layout reads the messages.
        connections: the bag's connections (rosbags' ``Connection``).
        is2: True for a rosbag2.
        layout: a :class:`Ros1Layout` for a ROS 1 bag, a :class:`McapLayout` for a rosbag2
            of one MCAP file with a summary; None where rosbags' reader reads the bag.
        metadata: a rosbag2's ``metadata.yaml`` (where there is a layout).
        keys: a connection's id in the layout by its id in ``connections`` (MCAP channel
            ids; a ROS 1 bag's are the same).
        decompress: how the layout's chunks are decompressed.
    """

    def __init__(
        self,
        path: Path,
        reader: Any,
        connections: list[Any],
        *,
        is2: bool,
        layout: McapLayout | Ros1Layout | None = None,
        metadata: dict[str, Any] | None = None,
        keys: dict[int, int] | None = None,
        decompress: Callable[..., bytes] | None = None,
    ) -> None:
        self.path, self.reader, self.connections, self.is2 = path, reader, connections, is2
        self.layout, self.metadata = layout, metadata
        self._keys = keys
        self._decompress = decompress

    def channel_of(self, connection: Any) -> int:
        """A connection's id in the layout (its MCAP channel id)."""
        return self._keys[connection.id] if self._keys else connection.id

    def messages(self, connections: Sequence[Any] = ()) -> Iterator[tuple[Any, int, bytes]]:
        """``(connection, bag stamp ns, bytes)`` of ``connections``' messages (all when
        empty) in time order, as rosbags' reader gives them."""
        if self.layout is None or self._decompress is None:
            yield from self.reader.messages(connections=connections)
            return
        by_key = {self.channel_of(c): c for c in connections or self.connections}
        for key, stamp_ns, raw in self.layout.messages(set(by_key), self._decompress):
            yield by_key[key], stamp_ns, raw

    def close(self) -> None:
        """Close the reader."""
        if self.reader is not None:
            self.reader.close()
