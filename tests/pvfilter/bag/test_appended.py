"""The output is a copy of the input with the new topics appended: the input's recorded
bytes are the output's, and the indexes, statistics and metadata count the new topics."""

from __future__ import annotations

from pathlib import Path

import pytest

from pvfilter.bag.bagfile import load_yaml, open_reader
from pvfilter.bag.mcap_layout import McapLayout, read_metadata_record
from pvfilter.bag.ros1_layout import Ros1Layout
from pvfilter.cli import main

from .conftest import write_scans
from .test_command import read_bag

NEW_TOPICS = ("/scan/filtered", "/scan/removed")


def _recorded(path: Path) -> tuple[Path, slice]:
    """The file that holds a bag's messages, and the span of it with every chunk."""
    if path.is_dir():
        layout = McapLayout.read(next(path.glob("*.mcap")))
        assert layout is not None
        end = max(c.offset + c.length + c.index_length for c in layout.chunks)
        return layout.path, slice(len(b"\x89MCAP0\r\n"), end)
    data = path.read_bytes()  # ROS 1: the chunks start after the padded bag header
    header = 13 + 4 + int.from_bytes(data[13:17], "little")
    start = header + 4 + int.from_bytes(data[header : header + 4], "little")
    layout = Ros1Layout.read(path)
    assert layout is not None
    return path, slice(start, layout.index_pos)


def _lz4(source: Path, path: Path) -> Path:
    """The ROS 1 bag ``source`` written again with lz4-compressed chunks."""
    from rosbags.rosbag1 import Reader, Writer

    writer = Writer(path)
    writer.set_compression(Writer.CompressionFormat.LZ4)
    with Reader(source) as reader, writer:
        copies = {
            c.id: writer.add_connection(
                c.topic,
                c.msgtype,
                msgdef=c.msgdef.data,
                md5sum=c.digest,
                callerid=c.ext.callerid,
                latching=c.ext.latching,
            )
            for c in reader.connections
        }
        for connection, stamp_ns, raw in reader.messages():
            writer.write(copies[connection.id], stamp_ns, raw)
    return path


def _input(which: str, exported: tuple[Path, Path, Path], tmp_path: Path) -> Path:
    if which == "rosbag2 zstd":
        return write_scans(tmp_path / "zstd", [1.0 + 0.1 * i for i in range(30)], compressed=True)
    if which == "ros1 lz4":
        return _lz4(exported[1], tmp_path / "lz4.bag")
    return exported[0] if which == "rosbag2" else exported[1]


@pytest.mark.parametrize("which", ["rosbag2", "rosbag2 zstd", "ros1", "ros1 lz4"])
def test_the_input_s_chunks_are_copied_as_bytes(exported, tmp_path, which):
    source = _input(which, exported, tmp_path)
    out = tmp_path / ("out.bag" if which.startswith("ros1") else "out")
    assert main(["bag", str(source), str(out), "--scan-topic", "/scan", "--quiet"]) == 0
    file, span = _recorded(source)
    out_file = out if which.startswith("ros1") else out / "out.mcap"
    assert out_file.read_bytes()[span] == file.read_bytes()[span]

    before, after = (
        {
            topic: [(t, raw) for t, raw, _ in messages]
            for topic, messages in read_bag(path)[0].items()
        }
        for path in (source, out)
    )
    assert {topic: v for topic, v in after.items() if topic not in NEW_TOPICS} == before
    assert len(after["/scan/filtered"]) == len(after["/scan/removed"]) == len(before["/scan"])
    bag = open_reader(out)
    try:  # the index section counts the new topics too
        counts = {c.topic: c.msgcount for c in bag.connections}
    finally:
        bag.close()
    assert counts == {topic: len(messages) for topic, messages in after.items()}


def test_the_rosbag2_metadata_lists_the_new_topics(exported, tmp_path):
    out = tmp_path / "out"
    assert main(["bag", str(exported[0]), str(out), "--scan-topic", "/scan", "--quiet"]) == 0
    info = load_yaml(out / "metadata.yaml")["rosbag2_bagfile_information"]
    before = load_yaml(exported[0] / "metadata.yaml")["rosbag2_bagfile_information"]
    counts = {
        t["topic_metadata"]["name"]: t["message_count"] for t in info["topics_with_message_count"]
    }
    scans = counts["/scan"]
    assert counts["/scan/filtered"] == counts["/scan/removed"] == scans
    assert info["message_count"] == before["message_count"] + 2 * scans == sum(counts.values())
    assert info["relative_file_paths"] == ["out.mcap"] and info["files"][0]["path"] == "out.mcap"
    # the copy inside the MCAP file (rosbag2's metadata record) says the same
    layout = McapLayout.read(out / "out.mcap")
    [(offset, length)] = [(o, n) for name, o, n in layout.metadata if name == "rosbag2"]
    serialized = read_metadata_record(layout.path, offset, length)["serialized_metadata"]
    assert (
        "/scan/filtered" in serialized and f"message_count: {info['message_count']}" in serialized
    )
