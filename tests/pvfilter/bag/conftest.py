"""Bags to filter: one episode of a small generated data set, exported as ``twsb
export-bag`` does (rosbag2 MCAP and ROS 1), and hand-made bags for the mistakes."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

rosbags = pytest.importorskip("rosbags")


@pytest.fixture(scope="session")
def exported(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path, Path]:
    """One short episode (25 scans) as a rosbag2 folder and a ROS 1 bag, and its data set."""
    pytest.importorskip("mujoco")
    from twsb_sim.dataset.generation import GenerationSettings, generate
    from twsb_sim.dataset.loader import open_dataset
    from twsb_sim.dataset.randomization import randomization_from_table
    from twsb_sim.dataset.rosbag import export_bag

    short = {"episode": {"duration_s": [2.5, 2.5]}, "shoves": {"probability": 1.0}}
    settings = GenerationSettings(seed=11, randomization=randomization_from_table(short))
    folder = tmp_path_factory.mktemp("exported")
    generate(folder / "data", 1, settings, workers=1, progress=False)
    ros2, ros1 = folder / "episode", folder / "episode.bag"
    export_bag(open_dataset(folder / "data"), 0, ros2, ros1_path=ros1)
    return ros2, ros1, folder / "data"


def write_scans(
    path: Path,
    stamps_s: list[float],
    topic: str = "/scan",
    storage: str = "MCAP",
    compressed: bool = False,
) -> Path:
    """A rosbag2 (``storage``: MCAP or SQLITE3) with one LaserScan per stamp (a wall 2 m
    ahead), in that order; ``compressed``: as the storage compresses (zstd MCAP chunks)."""
    from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    t = store.types
    writer = Writer(path, version=9, storage_plugin=StoragePlugin[storage])
    if compressed:
        writer.set_compression(CompressionMode.STORAGE, CompressionFormat.ZSTD)
    with writer:
        connection = writer.add_connection(topic, "sensor_msgs/msg/LaserScan", typestore=store)
        for i, stamp in enumerate(stamps_s):
            ns = round(stamp * 1e9)
            header = t["std_msgs/msg/Header"](
                stamp=t["builtin_interfaces/msg/Time"](sec=ns // 10**9, nanosec=ns % 10**9),
                frame_id="laser",
            )
            message = t["sensor_msgs/msg/LaserScan"](
                header=header, angle_min=-1.0, angle_max=1.0, angle_increment=0.01,
                time_increment=0.0, scan_time=0.1, range_min=0.1, range_max=10.0,
                ranges=np.full(201, 2.0, np.float32), intensities=np.zeros(0, np.float32),
            )  # fmt: skip
            writer.write(
                connection, 10**9 * (i + 1), store.serialize_cdr(message, message.__msgtype__)
            )
    return path
