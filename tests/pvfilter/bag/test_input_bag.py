"""A bag read through its file's layout has the connections and messages rosbags' own
reader gives, and a bag the layout cannot read goes to rosbags' reader."""

from __future__ import annotations

import pytest
from rosbags.rosbag1 import Reader as Reader1
from rosbags.rosbag2 import Reader as Reader2

from pvfilter.bag.bagfile import open_reader

from .conftest import write_scans


@pytest.mark.parametrize("which", ["rosbag2", "ros1"])
def test_connections_and_messages_are_rosbags(exported, which):
    path = exported[0] if which == "rosbag2" else exported[1]
    bag = open_reader(path)
    try:
        assert bag.reader is None and bag.layout is not None  # read through the layout
        with (Reader2 if which == "rosbag2" else Reader1)(path) as reader:
            # all fields but the owner (the reader)
            assert [c[:-1] for c in bag.connections] == [c[:-1] for c in reader.connections]
            for topics in (["/scan"], ["/scan", "/imu", "/tf_static"]):
                ours = [c for c in bag.connections if c.topic in topics]
                theirs = [c for c in reader.connections if c.topic in topics]
                got = [(c.id, t, raw) for c, t, raw in bag.messages(ours)]
                assert got == [(c.id, t, bytes(raw)) for c, t, raw in reader.messages(theirs)]
    finally:
        bag.close()


def test_a_sqlite3_bag_is_read_by_rosbags(tmp_path):
    bag = open_reader(write_scans(tmp_path / "in", [1.0, 1.1], storage="SQLITE3"))
    try:
        assert bag.layout is None and bag.reader is not None
        assert [t for _, t, _ in bag.messages(bag.connections)] == [10**9, 2 * 10**9]
    finally:
        bag.close()
