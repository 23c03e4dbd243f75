"""Export one episode as a ROS bag (rosbag2 with MCAP storage; optionally ROS 1), no ROS needed.

Topics (frame ids in brackets), one message per scan unless said:

=================  ===========================  ==========================================
topic              type                         content
=================  ===========================  ==========================================
``/scan``          sensor_msgs/LaserScan        [laser] the ranges (REP-117), no intensities
``/scan/labels``   sensor_msgs/LaserScan        [laser] the same scan, with the ground-truth
                                                label code of each beam as its intensity
``/imu``           sensor_msgs/Imu              [imu_link] orientation, rates, specific force
``/odom``          nav_msgs/Odometry            [odom -> base_footprint] true planar pose,
                                                forward velocity and yaw rate
``/tf``            tf2_msgs/TFMessage           odom -> base_footprint (x, y, yaw) and
                                                base_footprint -> base_link (height, pitch,
                                                roll)
``/tf_static``     tf2_msgs/TFMessage           base_link -> laser, base_link -> imu_link;
                                                once, latched (transient local)
=================  ===========================  ==========================================

Labels travel as a ``LaserScan`` because it is a standard type every ROS tool reads,
its header carries the same stamp and frame as ``/scan`` (so an exact-time synchronizer
pairs them), and RViz colours it by label. Codes are those of the label table (0
NO_RETURN ... 6 OCCLUDED). The tree follows REP-105/120: ``base_footprint`` is the
robot's projection on the floor, ``base_link`` the body (origin at the wheel axle),
which pitches. Odometry is the simulator's ground truth, noise-free; covariances are a
nominal 1e-6. Stamps are the scan stamps plus ``time_offset_s``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from rosbags.interfaces import (
    Qos,
    QosDurability,
    QosHistory,
    QosLiveliness,
    QosReliability,
    QosTime,
)
from rosbags.rosbag1 import Writer as Ros1Writer
from rosbags.rosbag2 import StoragePlugin
from rosbags.rosbag2 import Writer as Ros2Writer
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from twsb_sim.dataset.loader import ScanDataset
from twsb_sim.staging import staged_file, staged_new_folder

ODOM, FOOTPRINT, BASE, LASER, IMU = "odom", "base_footprint", "base_link", "laser", "imu_link"
SCAN, LABELS = "/scan", "/scan/labels"
TOPICS = {  # topic: message type
    SCAN: "sensor_msgs/msg/LaserScan",
    LABELS: "sensor_msgs/msg/LaserScan",
    "/imu": "sensor_msgs/msg/Imu",
    "/odom": "nav_msgs/msg/Odometry",
    "/tf": "tf2_msgs/msg/TFMessage",
    "/tf_static": "tf2_msgs/msg/TFMessage",
}
NOMINAL_VARIANCE = 1e-6
_TF_MESSAGE = "geometry_msgs/TransformStamped[] transforms"  # for the ROS 1 typestore
_LATCHED = Qos(
    QosHistory.KEEP_LAST, 1, QosReliability.RELIABLE, QosDurability.TRANSIENT_LOCAL,
    QosTime(0, 0), QosTime(0, 0), QosLiveliness.AUTOMATIC, QosTime(0, 0), False,
)  # fmt: skip


def _quat_multiply(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton product of (w, x, y, z) quaternions, row by row."""
    aw, ax, ay, az = a.T
    bw, bx, by, bz = b.T
    return np.stack(
        (
            aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
        ),
        axis=-1,
    )


class _Messages:
    """Builds the messages of one typestore (ROS 2 CDR, or ROS 1 with header sequence)."""

    def __init__(self, ros1: bool) -> None:
        self.ros1 = ros1
        self.store = get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.ROS2_HUMBLE)
        if ros1 and "tf2_msgs/msg/TFMessage" not in self.store.types:
            self.store.register(get_types_from_msg(_TF_MESSAGE, "tf2_msgs/msg/TFMessage"))
        self.types = self.store.types
        self.serialize: Callable[[Any, str], bytes] = (
            self.store.serialize_ros1 if ros1 else self.store.serialize_cdr
        )
        self._seq = 0

    def header(self, stamp_ns: int, frame_id: str) -> Any:
        stamp = self.types["builtin_interfaces/msg/Time"](
            sec=stamp_ns // 1_000_000_000, nanosec=stamp_ns % 1_000_000_000
        )
        if self.ros1:
            self._seq += 1
            return self.types["std_msgs/msg/Header"](seq=self._seq, stamp=stamp, frame_id=frame_id)
        return self.types["std_msgs/msg/Header"](stamp=stamp, frame_id=frame_id)

    def vector(self, xyz: Any) -> Any:
        x, y, z = (float(v) for v in xyz)
        return self.types["geometry_msgs/msg/Vector3"](x=x, y=y, z=z)

    def quaternion(self, wxyz: Any) -> Any:
        w, x, y, z = (float(v) for v in wxyz)
        return self.types["geometry_msgs/msg/Quaternion"](x=x, y=y, z=z, w=w)

    def transform(self, stamp_ns: int, parent: str, child: str, pose: Any) -> Any:
        t = self.types
        return t["geometry_msgs/msg/TransformStamped"](
            header=self.header(stamp_ns, parent),
            child_frame_id=child,
            transform=t["geometry_msgs/msg/Transform"](
                translation=self.vector(pose[:3]), rotation=self.quaternion(pose[3:])
            ),
        )

    def tf(self, transforms: list[Any]) -> Any:
        return self.types["tf2_msgs/msg/TFMessage"](transforms=transforms)

    def scan(
        self, stamp_ns: int, ranges: np.ndarray, intensities: np.ndarray, i: dict[str, float]
    ) -> Any:
        return self.types["sensor_msgs/msg/LaserScan"](
            header=self.header(stamp_ns, LASER),
            angle_min=i["angle_min"],
            angle_max=i["angle_max"],
            angle_increment=i["angle_increment"],
            time_increment=i["time_increment"],
            scan_time=i["scan_time"],
            range_min=i["range_min"],
            range_max=i["range_max"],
            ranges=np.asarray(ranges, np.float32),
            intensities=np.asarray(intensities, np.float32),
        )

    def imu(self, stamp_ns: int, row: dict[str, float]) -> Any:
        covariance = np.diag(np.full(3, NOMINAL_VARIANCE)).reshape(-1)
        return self.types["sensor_msgs/msg/Imu"](
            header=self.header(stamp_ns, IMU),
            orientation=self.quaternion([row[f"imu_q{c}"] for c in "wxyz"]),
            orientation_covariance=covariance,
            angular_velocity=self.vector([row[f"imu_gyro_{c}_rad_s"] for c in "xyz"]),
            angular_velocity_covariance=covariance,
            linear_acceleration=self.vector([row[f"imu_accel_{c}_mps2"] for c in "xyz"]),
            linear_acceleration_covariance=covariance,
        )

    def odometry(self, stamp_ns: int, planar: np.ndarray, row: dict[str, float]) -> Any:
        t = self.types
        covariance = np.diag(np.full(6, NOMINAL_VARIANCE)).reshape(-1)
        return t["nav_msgs/msg/Odometry"](
            header=self.header(stamp_ns, ODOM),
            child_frame_id=FOOTPRINT,
            pose=t["geometry_msgs/msg/PoseWithCovariance"](
                pose=t["geometry_msgs/msg/Pose"](
                    position=t["geometry_msgs/msg/Point"](
                        x=float(planar[0]), y=float(planar[1]), z=0.0
                    ),
                    orientation=self.quaternion(planar[3:]),
                ),
                covariance=covariance,
            ),
            twist=t["geometry_msgs/msg/TwistWithCovariance"](
                twist=t["geometry_msgs/msg/Twist"](
                    linear=self.vector([row["forward_velocity_mps"], 0.0, 0.0]),
                    angular=self.vector([0.0, 0.0, row["yaw_rate_rad_s"]]),
                ),
                covariance=covariance,
            ),
        )


def _poses(table: Any) -> tuple[np.ndarray, np.ndarray]:
    """Per scan: odom -> base_footprint and base_footprint -> base_link, as
    ``[x, y, z, qw, qx, qy, qz]`` rows."""
    col = lambda name: table[name].to_numpy()  # noqa: E731
    n = table.num_rows
    base_q = np.column_stack([col("base_qw"), col("base_qx"), col("base_qy"), col("base_qz")])
    half = 0.5 * col("yaw_rad")
    yaw_q = np.column_stack([np.cos(half), np.zeros(n), np.zeros(n), np.sin(half)])
    planar = np.column_stack([col("base_x_m"), col("base_y_m"), np.zeros(n), yaw_q])
    tilt_q = _quat_multiply(yaw_q * np.array([1, -1, -1, -1]), base_q)  # yaw undone
    tilt = np.column_stack([np.zeros(n), np.zeros(n), col("base_z_m"), tilt_q])
    return planar, tilt


def episode_messages(
    dataset: ScanDataset, episode: int, messages: _Messages, time_offset_s: float
) -> list[tuple[str, int, Any]]:
    """Every message of an episode as ``(topic, stamp in ns, message)``, in time order."""
    record = dataset.episode(episode)
    table, intrinsics = record.table, dataset.intrinsics
    stamps_ns = np.round((table["stamp_s"].to_numpy() + time_offset_s) * 1e9).astype(np.int64)
    ranges, labels = record.ranges, record.labels
    rows = table.drop_columns(["ranges", "labels"]).to_pylist()
    planar, tilt = _poses(table)
    mounts = record.summary["mounts"]
    out: list[tuple[str, int, Any]] = []
    if len(rows):
        first = int(stamps_ns[0])
        static = [
            messages.transform(first, BASE, LASER, mounts["laser"]),
            messages.transform(first, BASE, IMU, mounts["imu"]),
        ]
        out.append(("/tf_static", first, messages.tf(static)))
    no_intensities = np.zeros(0, np.float32)
    for i, row in enumerate(rows):
        t = int(stamps_ns[i])
        dynamic = [
            messages.transform(t, ODOM, FOOTPRINT, planar[i]),
            messages.transform(t, FOOTPRINT, BASE, tilt[i]),
        ]
        out.append(("/tf", t, messages.tf(dynamic)))
        out.append(("/odom", t, messages.odometry(t, planar[i], row)))
        out.append(("/imu", t, messages.imu(t, row)))
        out.append((SCAN, t, messages.scan(t, ranges[i], no_intensities, intrinsics)))
        out.append((LABELS, t, messages.scan(t, ranges[i], labels[i], intrinsics)))
    return out


def export_bag(
    dataset: ScanDataset,
    episode: int,
    out: str | Path,
    ros1_path: str | Path | None = None,
    time_offset_s: float = 1.0,
) -> dict[str, int]:
    """Write episode ``episode`` as a rosbag2 folder ``out`` (MCAP), and a ROS 1 bag.

    Args:
        dataset: the data set.
        episode: which episode.
        out: the rosbag2 folder to create (must not exist).
        ros1_path: also write a ROS 1 ``.bag`` file here.
        time_offset_s: added to every stamp (s); ROS reads a zero stamp as "latest".

    Returns:
        Messages written per topic.
    """
    if not math.isfinite(time_offset_s) or time_offset_s < 0:
        raise ValueError(f"time_offset_s: expected a finite value >= 0, got {time_offset_s}")
    if Path(out).exists():
        raise ValueError(f"out: {out} exists; a rosbag2 export writes a new folder")
    ros2 = _Messages(ros1=False)
    counts = dict.fromkeys(TOPICS, 0)
    # both bags are written under hidden names and renamed when complete (the folder
    # last): an interrupted export leaves no half bag that a re-run would refuse
    with staged_new_folder(Path(out)) as folder:
        with Ros2Writer(folder, version=9, storage_plugin=StoragePlugin.MCAP) as writer:
            connections = {
                topic: writer.add_connection(
                    topic,
                    msgtype,
                    typestore=ros2.store,
                    offered_qos_profiles=[_LATCHED] if topic == "/tf_static" else [],
                )
                for topic, msgtype in TOPICS.items()
            }
            for topic, stamp_ns, message in episode_messages(dataset, episode, ros2, time_offset_s):
                writer.write(connections[topic], stamp_ns, ros2.serialize(message, TOPICS[topic]))
                counts[topic] += 1
        if ros1_path is not None:
            _write_ros1(dataset, episode, Path(ros1_path), time_offset_s)
    return counts


def _write_ros1(dataset: ScanDataset, episode: int, path: Path, time_offset_s: float) -> None:
    """The same messages as a ROS 1 ``.bag`` file (replacing ``path`` when it exists)."""
    ros1 = _Messages(ros1=True)
    with staged_file(path) as file, Ros1Writer(file) as writer:
        connections = {
            topic: writer.add_connection(
                topic,
                msgtype,
                typestore=ros1.store,
                latching=1 if topic == "/tf_static" else None,
            )
            for topic, msgtype in TOPICS.items()
        }
        for topic, stamp_ns, message in episode_messages(dataset, episode, ros1, time_offset_s):
            writer.write(connections[topic], stamp_ns, ros1.serialize(message, TOPICS[topic]))
