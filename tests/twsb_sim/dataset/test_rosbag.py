"""ROS export: read the bags back with rosbags and compare them with the data set."""

from __future__ import annotations

import numpy as np
import pytest
from rosbags.highlevel import AnyReader
from rosbags.typesys import Stores, get_typestore

from twsb_sim.cli import main
from twsb_sim.dataset.loader import DatasetFormatWarning, open_dataset
from twsb_sim.dataset.rosbag import export_bag

from .conftest import as_format_1

EPISODE = 2
OFFSET_S = 1.0


def read_bag(path):
    messages = {}
    with AnyReader([path], default_typestore=get_typestore(Stores.ROS2_HUMBLE)) as reader:
        types = {c.topic: c.msgtype for c in reader.connections}
        for connection, stamp_ns, raw in reader.messages():
            message = reader.deserialize(raw, connection.msgtype)
            messages.setdefault(connection.topic, []).append((stamp_ns, message))
    return types, messages


@pytest.fixture(scope="module")
def bags(reference, tmp_path_factory):
    folder = tmp_path_factory.mktemp("bags")
    ros2, ros1 = folder / "episode", folder / "episode.bag"
    argv = ["export-bag", str(reference), "--episode", str(EPISODE), "--out", str(ros2),
            "--ros1", str(ros1)]  # fmt: skip
    assert main(argv) == 0
    return ros2, ros1


@pytest.mark.parametrize("which", ["rosbag2", "ros1"])
def test_bag_holds_the_episode(reference, bags, which):
    path = bags[0] if which == "rosbag2" else bags[1]
    if which == "rosbag2":
        assert next(path.glob("*.mcap")).stat().st_size > 0
    types, messages = read_bag(path)
    assert types == {
        "/scan": "sensor_msgs/msg/LaserScan",
        "/scan/labels": "sensor_msgs/msg/LaserScan",
        "/imu": "sensor_msgs/msg/Imu",
        "/odom": "nav_msgs/msg/Odometry",
        "/tf": "tf2_msgs/msg/TFMessage",
        "/tf_static": "tf2_msgs/msg/TFMessage",
        "/ground_truth/odom": "nav_msgs/msg/Odometry",
    }
    episode = open_dataset(reference).episode(EPISODE)
    table = episode.table
    n = len(episode)
    flat = lambda name: table[name].combine_chunks().flatten().to_numpy()  # noqa: E731
    n_imu, n_odom = len(flat("imu_samples_stamp_s")), len(flat("odom_samples_stamp_s"))
    assert n_imu > 15 * n and n_odom > 4 * n  # 200 Hz and 50 Hz against 10 Hz scans
    assert {topic: len(v) for topic, v in messages.items()} == {
        "/scan": n, "/scan/labels": n, "/ground_truth/odom": n, "/tf_static": 1,
        "/imu": n_imu, "/odom": n_odom, "/tf": n_odom + n,
    }  # fmt: skip
    stamps = np.array([t for t, _ in messages["/scan"]])
    expected = np.round((episode.column("stamp_s") + OFFSET_S) * 1e9).astype(np.int64)
    np.testing.assert_array_equal(stamps, expected)
    scans = [m for _, m in messages["/scan"]]
    labels = [m for _, m in messages["/scan/labels"]]
    np.testing.assert_array_equal(np.stack([m.ranges for m in scans]), episode.ranges)
    np.testing.assert_array_equal(np.stack([m.intensities for m in labels]), episode.labels)
    assert scans[0].header.frame_id == "laser" and len(scans[0].intensities) == 0
    assert scans[0].angle_increment == pytest.approx(2 * np.pi / 720)
    assert scans[0].time_increment == pytest.approx(0.1 / 720)  # a rotating scanner

    # /odom is the encoders' odometry at its own rate, /imu every IMU sample as measured
    odom = [m for _, m in messages["/odom"]]
    np.testing.assert_allclose([m.pose.pose.position.x for m in odom], flat("odom_samples_x_m"))
    np.testing.assert_allclose(
        [m.twist.twist.linear.x for m in odom], flat("odom_samples_forward_velocity_mps"), rtol=1e-6
    )
    imu = [m for _, m in messages["/imu"]]
    np.testing.assert_allclose(
        [m.angular_velocity.y for m in imu], flat("imu_samples_gyro_y_rad_s")
    )
    imu_ns = np.round((flat("imu_samples_stamp_s") + OFFSET_S) * 1e9).astype(np.int64)
    np.testing.assert_array_equal([t for t, _ in messages["/imu"]], imu_ns)
    # the truth travels on its own topic
    truth = [m for _, m in messages["/ground_truth/odom"]]
    assert truth[0].header.frame_id == "world"
    np.testing.assert_allclose([m.pose.pose.position.x for m in truth], episode.column("base_x_m"))
    np.testing.assert_allclose([m.pose.pose.position.z for m in truth], episode.column("base_z_m"))

    # the tf tree: odom -> base_footprint per odometry update, base_footprint -> base_link
    # (axle height, the estimated pitch) per scan
    tilts = [
        tf.transforms[0]
        for _, tf in messages["/tf"]
        if tf.transforms[0].child_frame_id == "base_link"
    ]
    planars = [
        tf.transforms[0]
        for _, tf in messages["/tf"]
        if tf.transforms[0].child_frame_id == "base_footprint"
    ]
    assert len(tilts) == n and len(planars) == n_odom
    assert all(t.header.frame_id == "base_footprint" for t in tilts)
    assert all(t.header.frame_id == "odom" for t in planars)
    for tilt, z, pitch in zip(
        tilts, episode.column("base_z_m"), episode.column("est_pitch_rad"), strict=True
    ):
        q = tilt.transform.rotation
        assert tilt.transform.translation.z == pytest.approx(z)
        assert np.arcsin(2 * (q.w * q.y - q.x * q.z)) == pytest.approx(pitch, abs=1e-9)
    ((_, static),) = messages["/tf_static"]
    mounts = {t.child_frame_id: t.transform.translation.z for t in static.transforms}
    laser_height = episode.summary["scenario"]["robot"]["lidar_height_m"]
    wheel_radius = 0.08
    assert mounts["laser"] == pytest.approx(laser_height - wheel_radius, abs=1e-6)


def test_export_refuses_a_missing_episode(reference, tmp_path, capsys):
    argv = ["export-bag", str(reference), "--episode", "999", "--out", str(tmp_path / "b")]
    assert main(argv) == 2
    assert "no episode 999" in capsys.readouterr().err


def test_export_refuses_an_existing_ros1_bag_and_keeps_it(reference, tmp_path, capsys):
    taken = tmp_path / "episode.bag"
    taken.write_bytes(b"keep me")
    argv = ["export-bag", str(reference), "--out", str(tmp_path / "b"), "--ros1", str(taken)]
    assert main(argv) == 2
    error = capsys.readouterr().err
    assert "--ros1" in error and "exists" in error
    assert taken.read_bytes() == b"keep me" and not (tmp_path / "b").exists()
    dataset = open_dataset(reference)
    with pytest.raises(ValueError, match="exists"):  # the library refuses it too
        export_bag(dataset, dataset.episode_ids[0], tmp_path / "c", ros1_path=taken)
    assert taken.read_bytes() == b"keep me" and not (tmp_path / "c").exists()


def test_a_format_1_data_set_exports_its_truth(reference, tmp_path):
    old = tmp_path / "old"
    as_format_1(reference, old)
    with pytest.warns(DatasetFormatWarning):
        dataset = open_dataset(old)
    export_bag(dataset, EPISODE, tmp_path / "bag")
    _, messages = read_bag(tmp_path / "bag")
    n = len(dataset.episode(EPISODE))
    assert len(messages["/odom"]) == len(messages["/imu"]) == n
    odom = [m for _, m in messages["/odom"]]
    np.testing.assert_allclose(
        [m.pose.pose.position.x for m in odom], dataset.episode(EPISODE).column("base_x_m")
    )


def test_an_offset_that_leaves_stamps_before_zero_is_refused(reference, tmp_path):
    dataset = open_dataset(reference)
    with pytest.raises(ValueError, match=r"^time_offset_s: .*before 0"):
        export_bag(dataset, EPISODE, tmp_path / "bag", time_offset_s=0.0)
    assert not (tmp_path / "bag").exists()
