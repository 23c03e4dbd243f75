"""``pvfilter bag``: a twsb bag round-trips, SLAM reads the output, mistakes get one line."""

from __future__ import annotations

import sys

import numpy as np
import pytest
from rosbags.highlevel import AnyReader
from rosbags.typesys import Stores, get_typestore

from pvfilter import Scan, make_filter
from pvfilter.cli import main

from .conftest import write_scans

INPUT_TOPICS = {"/scan", "/scan/labels", "/imu", "/odom", "/tf", "/tf_static", "/ground_truth/odom"}


def read_bag(path):
    """``{topic: [(bag stamp ns, raw bytes, message)]}`` and ``{topic: type}``."""
    topics, types = {}, {}
    with AnyReader([path], default_typestore=get_typestore(Stores.ROS2_HUMBLE)) as reader:
        for connection, stamp_ns, raw in reader.messages():
            message = reader.deserialize(raw, connection.msgtype)
            topics.setdefault(connection.topic, []).append((stamp_ns, bytes(raw), message))
            types[connection.topic] = connection.msgtype
    return topics, types


def as_scan(message) -> Scan:
    stamp = message.header.stamp.sec + 1e-9 * message.header.stamp.nanosec
    return Scan(
        ranges=message.ranges, angle_min=message.angle_min,
        angle_increment=message.angle_increment, range_min=message.range_min,
        range_max=message.range_max, stamp=stamp, time_increment=message.time_increment,
        scan_time=message.scan_time,
    )  # fmt: skip


@pytest.mark.parametrize("which", ["rosbag2", "ros1"])
def test_a_twsb_bag_round_trips(exported, tmp_path, which, capsys):
    source = exported[0] if which == "rosbag2" else exported[1]
    out = tmp_path / ("out" if which == "rosbag2" else "out.bag")
    argv = ["bag", str(source), str(out), "--scan-topic", "/scan", "--improved"]
    argv += ["--imu-topic", "/imu", "--odom-topic", "/odom", "--quiet"]
    assert main(argv) == 0
    assert "improved filter on /scan" in capsys.readouterr().out
    before, _ = read_bag(source)
    after, types = read_bag(out)
    assert set(after) == INPUT_TOPICS | {"/scan/filtered", "/scan/removed"}
    for topic in INPUT_TOPICS:  # copied as they were: bytes and bag stamps
        assert [(t, raw) for t, raw, _ in after[topic]] == [(t, raw) for t, raw, _ in before[topic]]
    assert types["/scan/filtered"] == types["/scan/removed"] == "sensor_msgs/msg/LaserScan"

    for (t, _, scan_msg), (t_f, _, filtered), (t_r, _, mask) in zip(
        before["/scan"], after["/scan/filtered"], after["/scan/removed"], strict=True
    ):
        assert t == t_f == t_r
        for message in (filtered, mask):
            assert message.header.stamp.nanosec == scan_msg.header.stamp.nanosec
            assert message.header.frame_id == scan_msg.header.frame_id
        removed = np.asarray(mask.intensities) == 1.0
        assert set(np.unique(mask.intensities)) <= {0.0, 1.0}
        np.testing.assert_array_equal(
            np.isnan(filtered.ranges), removed | np.isnan(scan_msg.ranges)
        )
        np.testing.assert_array_equal(filtered.ranges[~removed], scan_msg.ranges[~removed])
        np.testing.assert_array_equal(mask.ranges, scan_msg.ranges)
        assert filtered.range_max == scan_msg.range_max and len(filtered.intensities) == 0


@pytest.mark.parametrize("name", ["paper", "improved"])
def test_the_filtered_scans_are_the_filter_s(exported, tmp_path, name):
    """The filter run here on the same scans removes what the bag says was removed."""
    out = tmp_path / "out"
    argv = ["bag", str(exported[0]), str(out), "--scan-topic", "/scan", "--filter", name]
    assert main([*argv, "--quiet"]) == 0
    before, _ = read_bag(exported[0])
    after, _ = read_bag(out)
    reference = make_filter(name)
    removed_any = 0
    for (_, _, scan_msg), (_, _, filtered), (_, _, mask) in zip(
        before["/scan"], after["/scan/filtered"], after["/scan/removed"], strict=True
    ):
        expected = reference.process(as_scan(scan_msg)).removed
        np.testing.assert_array_equal(np.asarray(mask.intensities) == 1.0, expected)
        np.testing.assert_array_equal(
            np.isnan(filtered.ranges), expected | np.isnan(scan_msg.ranges)
        )
        removed_any += int(expected.sum())
    # the episode's shove tips the scan plane into the floor: the improved filter acts
    assert removed_any > 0 or name == "paper"


def test_robot_inputs_are_what_the_simulator_gave_its_filter(exported):
    """Attitude and LiDAR pose read from the bag match the data set's, scan by scan."""
    from pvfilter.bag.bagfile import open_reader
    from pvfilter.bag.command import build_parser
    from pvfilter.bag.inputs_pass import read_inputs
    from twsb_sim.dataset.loader import open_dataset

    args = build_parser().parse_args(
        [str(exported[0]), "unused", "--scan-topic", "/scan", "--imu-topic", "/imu",
         "--odom-topic", "/odom"]
    )  # fmt: skip
    reader = open_reader(exported[0])
    try:
        inputs = read_inputs(reader, args)
    finally:
        reader.close()
    table = open_dataset(exported[2]).episode(0).table
    column = lambda name: table[name].to_numpy()  # noqa: E731
    given = [inputs.at(stamp) for stamp in inputs.scan_stamps_ns]
    assert len(given) == table.num_rows
    # a scan stamped before the first IMU sample gets no attitude (the simulator's
    # estimator reads level then)
    early = [i for i, g in enumerate(given) if "pitch_rad" not in g]
    assert early == list(range(len(early))) and len(early) <= 3
    assert all(column("est_pitch_rad")[early] == 0.0)
    given, table = given[len(early) :], table.slice(len(early))
    np.testing.assert_allclose([g["pitch_rad"] for g in given], column("est_pitch_rad"), atol=1e-9)
    np.testing.assert_allclose([g["roll_rad"] for g in given], column("est_roll_rad"), atol=1e-9)
    poses = np.array([g["pose_sensor_in_odom"] for g in given])
    lidar = np.column_stack([column(f"lidar_odom_{c}") for c in ("x_m", "y_m", "yaw_rad")])
    np.testing.assert_allclose(poses[:, 2], lidar[:, 2], atol=1e-9)
    # the mounting is taken from the tf tree at the first scan, the simulator's at rest
    np.testing.assert_allclose(poses[:, :2], lidar[:, :2], atol=5e-3)


def test_kiss_icp_reads_the_filtered_topic(exported, tmp_path):
    pytest.importorskip("kiss_icp")
    from scaneval.slam import KissIcp2D

    out = tmp_path / "out"
    assert main(["bag", str(exported[0]), str(out), "--scan-topic", "/scan", "--quiet"]) == 0
    after, _ = read_bag(out)
    kiss = KissIcp2D(max_range_m=12.0)
    poses = np.array([kiss.process_scan(as_scan(m)) for _, _, m in after["/scan/filtered"]])
    truth = np.array(
        [
            [m.pose.pose.position.x, m.pose.pose.position.y]
            for _, _, m in after["/ground_truth/odom"]
        ]
    )
    assert not kiss.lost and np.isfinite(poses).all()
    travelled = np.linalg.norm(truth[-1] - truth[0])
    assert abs(np.linalg.norm(poses[-1, :2]) - travelled) < 0.1 + 0.2 * travelled


def test_an_interrupted_run_leaves_nothing(exported, tmp_path, monkeypatch, capsys):
    out = tmp_path / "out"
    calls = []

    def interrupt(self, scan, **inputs):
        calls.append(scan)
        if len(calls) == 5:
            raise KeyboardInterrupt
        return original(self, scan, **inputs)

    from pvfilter.paper import PitchVariationFilter

    original = PitchVariationFilter.process
    monkeypatch.setattr(PitchVariationFilter, "process", interrupt)
    assert main(["bag", str(exported[0]), str(out), "--scan-topic", "/scan", "--quiet"]) == 130
    assert "interrupted" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []  # no output, no partial folder


def test_an_existing_output_is_replaced_only_with_force(exported, tmp_path, capsys):
    out = tmp_path / "out"
    out.mkdir()
    (out / "keep").write_text("mine")
    argv = ["bag", str(exported[0]), str(out), "--scan-topic", "/scan", "--quiet"]
    assert main(argv) == 2
    assert (
        capsys.readouterr().err.strip()
        == f"pvfilter bag: error: {out}: exists; give --force to replace it"
    )
    assert (out / "keep").exists()
    assert main([*argv, "--force"]) == 0
    assert not (out / "keep").exists() and (out / "metadata.yaml").exists()


MISTAKES = {  # options: the error
    "": "--scan-topic: the bag has 2 LaserScan topics (/scan, /scan/labels); name one",
    "--scan-topic /lidar": "--scan-topic /lidar: not in the bag "
    "(its LaserScan topics: /scan, /scan/labels)",
    "--scan-topic /scan --imu-topic /odom": "--imu-topic /odom: is nav_msgs/msg/Odometry, "
    "not sensor_msgs/msg/Imu",
    "--scan-topic /imu": "--scan-topic /imu: is sensor_msgs/msg/Imu, not sensor_msgs/msg/LaserScan",
    "--scan-topic /scan --filter imu_gate": "filter 'imu_gate' needs pitch_rad, roll_rad: "
    "give --imu-topic",
    "--scan-topic /scan --filtered-topic /odom": "--filtered-topic /odom: the input bag has "
    "this topic already",
}


@pytest.mark.parametrize(("extra", "message"), MISTAKES.items(), ids=list(MISTAKES))
def test_mistakes_get_one_line_and_no_output(exported, tmp_path, capsys, extra, message):
    out = tmp_path / "out"
    assert main(["bag", str(exported[0]), str(out), "--quiet", *extra.split()]) == 2
    err = capsys.readouterr().err
    assert err == f"pvfilter bag: error: {message}\n"
    assert not out.exists() and list(tmp_path.iterdir()) == []


def test_a_missing_bag_and_stamps_out_of_order_are_named(tmp_path, capsys):
    assert main(["bag", str(tmp_path / "nothing"), str(tmp_path / "out")]) == 2
    assert "nothing: no such bag" in capsys.readouterr().err
    source = write_scans(tmp_path / "shuffled", [1.0, 1.1, 1.05, 1.2])
    assert main(["bag", str(source), str(tmp_path / "out"), "--quiet"]) == 2
    assert capsys.readouterr().err == (
        "pvfilter bag: error: /scan: scan 2 is stamped 1.050000000 s, before scan 1's "
        "1.100000000 s (stamps out of order)\n"
    )
    assert not (tmp_path / "out").exists()


def test_the_none_filter_passes_a_bag_through(tmp_path, capsys):
    source = write_scans(tmp_path / "in", [1.0, 1.1, 1.2])
    assert main(["bag", str(source), str(tmp_path / "out"), "--filter", "none"]) == 0
    assert "none filter on /scan, 3 scans, removed 0 of 603 valid beams" in capsys.readouterr().out
    after, _ = read_bag(tmp_path / "out")
    assert [raw for _, raw, _ in after["/scan/filtered"]] == [raw for _, raw, _ in after["/scan"]]


def test_a_sqlite3_bag_is_filtered_into_a_sqlite3_bag(tmp_path, capsys):
    source = write_scans(tmp_path / "in", [1.0, 1.1, 1.2, 1.3], storage="SQLITE3")
    assert [f.suffix for f in source.iterdir() if f.suffix in (".db3", ".mcap")] == [".db3"]
    assert main(["bag", str(source), str(tmp_path / "out"), "--quiet"]) == 0
    printed = capsys.readouterr().out
    assert "paper filter on /scan, 4 scans" in printed
    assert "pvfilter bag: the paper's filter ran, the default" in printed
    out = tmp_path / "out"
    assert [f.suffix for f in out.iterdir() if f.suffix in (".db3", ".mcap")] == [".db3"]
    after, types = read_bag(out)
    assert [raw for _, raw, _ in after["/scan"]] == [
        raw for _, raw, _ in read_bag(source)[0]["/scan"]
    ]
    assert len(after["/scan/filtered"]) == len(after["/scan/removed"]) == 4
    assert types["/scan/filtered"] == "sensor_msgs/msg/LaserScan"


def test_a_bare_mcap_file_is_filtered_into_an_mcap_bag(tmp_path, capsys):
    source = write_scans(tmp_path / "in", [1.0, 1.1, 1.2, 1.3], storage="MCAP")
    (bare,) = source.glob("*.mcap")  # the file alone, as rosbags reads it
    assert main(["bag", str(bare), str(tmp_path / "out"), "--quiet"]) == 0
    assert "paper filter on /scan, 4 scans" in capsys.readouterr().out
    out = tmp_path / "out"
    assert [f.suffix for f in out.iterdir() if f.suffix in (".db3", ".mcap")] == [".mcap"]
    assert len(read_bag(out)[0]["/scan/filtered"]) == 4


def test_without_rosbags_the_error_names_the_extra(tmp_path, monkeypatch, capsys):
    for name in [m for m in sys.modules if m == "rosbags" or m.startswith("rosbags.")]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, "rosbags", None)
    assert main(["bag", str(tmp_path / "in"), str(tmp_path / "out")]) == 2
    assert 'pip install "pvfilter[bag]"' in capsys.readouterr().err


def _write_laser_scans(path, messages, clockwise: bool):
    """A rosbag2 of ``messages`` (LaserScan) on /scan, as they are or with their beams
    clockwise: reversed, negative increments, the header stamp the time of the first
    beam in the new order (the same physical scan)."""
    from rosbags.rosbag2 import Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    t = store.types
    with Writer(path, version=9) as writer:
        connection = writer.add_connection("/scan", "sensor_msgs/msg/LaserScan", typestore=store)
        for bag_ns, _, m in messages:
            stamp_ns = m.header.stamp.sec * 10**9 + m.header.stamp.nanosec
            fields = dict(angle_min=m.angle_min, angle_max=m.angle_max,
                          angle_increment=m.angle_increment, time_increment=m.time_increment,
                          ranges=np.asarray(m.ranges, np.float32))  # fmt: skip
            if clockwise:
                last = len(m.ranges) - 1
                stamp_ns += round(last * m.time_increment * 1e9)
                fields = dict(angle_min=m.angle_max, angle_max=m.angle_min,
                              angle_increment=-m.angle_increment,
                              time_increment=-m.time_increment,
                              ranges=np.asarray(m.ranges, np.float32)[::-1].copy())  # fmt: skip
            sec, nanosec = divmod(stamp_ns, 10**9)
            header = t["std_msgs/msg/Header"](
                stamp=t["builtin_interfaces/msg/Time"](sec=sec, nanosec=nanosec),
                frame_id=m.header.frame_id,
            )
            message = t["sensor_msgs/msg/LaserScan"](
                header=header, scan_time=m.scan_time, range_min=m.range_min,
                range_max=m.range_max, intensities=np.zeros(0, np.float32), **fields,
            )  # fmt: skip
            writer.write(connection, bag_ns, store.serialize_cdr(message, message.__msgtype__))
    return path


def test_a_clockwise_scan_topic_is_filtered_in_its_own_beam_order(exported, tmp_path):
    # ROS allows a negative angle_increment; the same scans written clockwise lose the
    # same beams, in the message's order
    scans = read_bag(exported[0])[0]["/scan"]
    masks = {}
    for clockwise in (False, True):
        source = _write_laser_scans(tmp_path / f"in{clockwise}", scans, clockwise)
        out = tmp_path / f"out{clockwise}"
        assert main(["bag", str(source), str(out), "--improved", "--quiet"]) == 0
        masks[clockwise] = [
            np.asarray(m.intensities) == 1.0 for _, _, m in read_bag(out)[0]["/scan/removed"]
        ]
    assert sum(int(m.sum()) for m in masks[False]) > 0
    for counter, clockwise in zip(masks[False], masks[True], strict=True):
        np.testing.assert_array_equal(clockwise[::-1], counter)
