"""ROS export: read the bags back with rosbags and compare them with the data set."""

from __future__ import annotations

import numpy as np
import pytest
from rosbags.highlevel import AnyReader
from rosbags.typesys import Stores, get_typestore

from twsb_sim.cli import main
from twsb_sim.dataset.loader import open_dataset

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
    }
    episode = open_dataset(reference).episode(EPISODE)
    n = len(episode)
    assert {topic: len(v) for topic, v in messages.items()} == {
        **dict.fromkeys(types, n),
        "/tf_static": 1,
    }
    stamps = np.array([t for t, _ in messages["/scan"]])
    expected = np.round((episode.column("stamp_s") + OFFSET_S) * 1e9).astype(np.int64)
    np.testing.assert_array_equal(stamps, expected)
    scans = [m for _, m in messages["/scan"]]
    labels = [m for _, m in messages["/scan/labels"]]
    np.testing.assert_array_equal(np.stack([m.ranges for m in scans]), episode.ranges)
    np.testing.assert_array_equal(np.stack([m.intensities for m in labels]), episode.labels)
    assert scans[0].header.frame_id == "laser" and len(scans[0].intensities) == 0
    assert scans[0].angle_increment == pytest.approx(2 * np.pi / 720)

    odom = [m for _, m in messages["/odom"]]
    np.testing.assert_allclose([m.pose.pose.position.x for m in odom], episode.column("base_x_m"))
    np.testing.assert_allclose(
        [m.twist.twist.linear.x for m in odom], episode.column("forward_velocity_mps")
    )
    imu = [m for _, m in messages["/imu"]]
    np.testing.assert_allclose(
        [m.angular_velocity.y for m in imu], episode.column("imu_gyro_y_rad_s")
    )

    # the tf chain odom -> base_footprint -> base_link gives the base's pose and pitch back
    for (_, tf), z, pitch in zip(
        messages["/tf"], episode.column("base_z_m"), episode.column("pitch_rad"), strict=True
    ):
        planar, tilt = tf.transforms
        assert (planar.header.frame_id, planar.child_frame_id) == ("odom", "base_footprint")
        assert (tilt.header.frame_id, tilt.child_frame_id) == ("base_footprint", "base_link")
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
