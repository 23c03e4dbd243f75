"""Export one episode as a ROS bag (rosbag2 with MCAP storage; optionally ROS 1), no ROS needed.

Topics (frame ids in brackets), what a robot with these sensors would record:

=======================  ===========================  ====================================
topic                    type                         content
=======================  ===========================  ====================================
``/scan``                sensor_msgs/LaserScan        [laser] one per scan: the ranges
                                                      (REP-117), no intensities
``/scan/labels``         sensor_msgs/LaserScan        [laser] the same scan, with the
                                                      ground-truth label code of each beam
                                                      as its intensity
``/imu``                 sensor_msgs/Imu              [imu_link] every IMU sample, stamped
                                                      on arrival: measured rates and
                                                      specific force, the attitude
                                                      estimate as orientation
``/odom``                nav_msgs/Odometry            [odom -> base_footprint] every
                                                      encoder-odometry update: pose, twist
``/tf``                  tf2_msgs/TFMessage           odom -> base_footprint per odometry
                                                      update; base_footprint -> base_link
                                                      (axle height, estimated pitch and
                                                      roll) per scan
``/tf_static``           tf2_msgs/TFMessage           base_link -> laser, base_link ->
                                                      imu_link; once, latched
``/ground_truth/odom``   nav_msgs/Odometry            [world -> base_link] one per scan:
                                                      the true pose (3-D) and twist
=======================  ===========================  ====================================

Labels travel as a ``LaserScan`` because it is a standard type every ROS tool reads,
its header carries the same stamp and frame as ``/scan`` (so an exact-time synchronizer
pairs them), and RViz colours it by label. Codes are those of the label table (0
NO_RETURN ... 6 OCCLUDED). The tree follows REP-105/120: ``base_footprint`` is the
robot's projection on the floor, ``base_link`` the body (origin at the wheel axle),
which pitches. Covariances are a nominal 1e-6. Stamps are the data set's plus
``time_offset_s``; a scan's stamp is its beam 0's time. A data set of format 1 holds no
sensor readings: its ``/odom``, ``/imu`` and ``/tf`` are the truth at the scans' stamps,
as that format's export wrote them.
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
    "/ground_truth/odom": "nav_msgs/msg/Odometry",
}
WORLD = "world"
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

    def imu(self, stamp_ns: int, quat_wxyz: Any, gyro: Any, accel: Any) -> Any:
        covariance = np.diag(np.full(3, NOMINAL_VARIANCE)).reshape(-1)
        return self.types["sensor_msgs/msg/Imu"](
            header=self.header(stamp_ns, IMU),
            orientation=self.quaternion(quat_wxyz),
            orientation_covariance=covariance,
            angular_velocity=self.vector(gyro),
            angular_velocity_covariance=covariance,
            linear_acceleration=self.vector(accel),
            linear_acceleration_covariance=covariance,
        )

    def odometry(
        self, stamp_ns: int, frames: tuple[str, str], pose: Any, twist: tuple[float, float]
    ) -> Any:
        """``pose`` is ``[x, y, z, qw, qx, qy, qz]``; ``twist`` forward m/s, yaw rate rad/s."""
        t = self.types
        covariance = np.diag(np.full(6, NOMINAL_VARIANCE)).reshape(-1)
        return t["nav_msgs/msg/Odometry"](
            header=self.header(stamp_ns, frames[0]),
            child_frame_id=frames[1],
            pose=t["geometry_msgs/msg/PoseWithCovariance"](
                pose=t["geometry_msgs/msg/Pose"](
                    position=t["geometry_msgs/msg/Point"](
                        x=float(pose[0]), y=float(pose[1]), z=float(pose[2])
                    ),
                    orientation=self.quaternion(pose[3:]),
                ),
                covariance=covariance,
            ),
            twist=t["geometry_msgs/msg/TwistWithCovariance"](
                twist=t["geometry_msgs/msg/Twist"](
                    linear=self.vector([twist[0], 0.0, 0.0]),
                    angular=self.vector([0.0, 0.0, twist[1]]),
                ),
                covariance=covariance,
            ),
        )


def _yaw_quats(yaw: np.ndarray) -> np.ndarray:
    half = 0.5 * np.asarray(yaw, dtype=np.float64)
    return np.column_stack([np.cos(half), np.zeros_like(half), np.zeros_like(half), np.sin(half)])


def _rpy_quats(roll: np.ndarray, pitch: np.ndarray, yaw: np.ndarray) -> np.ndarray:
    """Unit quaternions (w, x, y, z) of Z-Y-X angles, row by row."""
    cr, sr = np.cos(roll / 2), np.sin(roll / 2)
    cp, sp = np.cos(pitch / 2), np.sin(pitch / 2)
    cy, sy = np.cos(yaw / 2), np.sin(yaw / 2)
    return np.column_stack(
        (cy * cp * cr + sy * sp * sr, cy * cp * sr - sy * sp * cr,
         cy * sp * cr + sy * cp * sr, sy * cp * cr - cy * sp * sr)
    )  # fmt: skip


def _truth_poses(table: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per scan, from the truth: world -> base_link, odom -> base_footprint (the world's
    planar part) and base_footprint -> base_link, as ``[x, y, z, qw, qx, qy, qz]`` rows."""
    col = lambda name: table[name].to_numpy()  # noqa: E731
    n = table.num_rows
    base_q = np.column_stack([col("base_qw"), col("base_qx"), col("base_qy"), col("base_qz")])
    yaw_q = _yaw_quats(col("yaw_rad"))
    world = np.column_stack([col("base_x_m"), col("base_y_m"), col("base_z_m"), base_q])
    planar = np.column_stack([col("base_x_m"), col("base_y_m"), np.zeros(n), yaw_q])
    tilt_q = _quat_multiply(yaw_q * np.array([1, -1, -1, -1]), base_q)  # yaw undone
    tilt = np.column_stack([np.zeros(n), np.zeros(n), col("base_z_m"), tilt_q])
    return world, planar, tilt


def _flat(table: Any, name: str) -> np.ndarray:
    """The values of a list column, all rows one after the other."""
    return table[name].combine_chunks().flatten().to_numpy(zero_copy_only=False)


def _sensor_messages(
    table: Any, messages: _Messages, to_ns: Callable[[np.ndarray], np.ndarray], tilt_z: np.ndarray
) -> list[tuple[str, int, Any]]:
    """``/imu``, ``/odom`` and ``/tf`` from the robot's own sensors (format 2 on)."""
    out: list[tuple[str, int, Any]] = []
    imu_ns = to_ns(_flat(table, "imu_samples_stamp_s"))
    gyro = np.column_stack([_flat(table, f"imu_samples_gyro_{c}_rad_s") for c in "xyz"])
    accel = np.column_stack([_flat(table, f"imu_samples_accel_{c}_mps2") for c in "xyz"])
    rpy = [_flat(table, f"imu_samples_{a}_rad") for a in ("roll", "pitch", "yaw")]
    quats = _rpy_quats(*(np.asarray(a, np.float64) for a in rpy))
    for i, t in enumerate(imu_ns.tolist()):
        out.append(("/imu", t, messages.imu(t, quats[i], gyro[i], accel[i])))
    odom_ns = to_ns(_flat(table, "odom_samples_stamp_s"))
    x, y, yaw = (_flat(table, f"odom_samples_{c}") for c in ("x_m", "y_m", "yaw_rad"))
    v, w = (_flat(table, f"odom_samples_{c}") for c in ("forward_velocity_mps", "yaw_rate_rad_s"))
    planar = np.column_stack([x, y, np.zeros_like(x), _yaw_quats(yaw)])
    for i, t in enumerate(odom_ns.tolist()):
        out.append(("/odom", t, messages.odometry(t, (ODOM, FOOTPRINT), planar[i], (v[i], w[i]))))
        out.append(("/tf", t, messages.tf([messages.transform(t, ODOM, FOOTPRINT, planar[i])])))
    col = lambda name: table[name].to_numpy()  # noqa: E731
    n = table.num_rows
    tilt_q = _rpy_quats(col("est_roll_rad"), col("est_pitch_rad"), np.zeros(n))
    tilt = np.column_stack([np.zeros(n), np.zeros(n), tilt_z, tilt_q])
    for t, pose in zip(to_ns(table["stamp_s"].to_numpy()).tolist(), tilt, strict=True):
        out.append(("/tf", t, messages.tf([messages.transform(t, FOOTPRINT, BASE, pose)])))
    return out


def episode_messages(
    dataset: ScanDataset, episode: int, messages: _Messages, time_offset_s: float
) -> list[tuple[str, int, Any]]:
    """Every message of an episode as ``(topic, stamp in ns, message)``, in time order."""
    record = dataset.episode(episode)
    table, intrinsics = record.table, dataset.intrinsics

    def to_ns(stamps_s: np.ndarray) -> np.ndarray:
        stamps_ns = np.round((np.asarray(stamps_s) + time_offset_s) * 1e9).astype(np.int64)
        if len(stamps_ns) and stamps_ns.min() < 0:
            raise ValueError(
                f"time_offset_s: {time_offset_s} s leaves stamps before 0 (the first scan is "
                f"stamped at {float(np.min(stamps_s)):g} s); give a larger offset"
            )
        return stamps_ns

    stamps_ns = to_ns(table["stamp_s"].to_numpy())
    ranges, labels = record.ranges, record.labels
    world, planar, tilt = _truth_poses(table)
    truth_twist = np.column_stack(
        [table["forward_velocity_mps"].to_numpy(), table["yaw_rate_rad_s"].to_numpy()]
    )
    mounts = record.summary["mounts"]
    out: list[tuple[str, int, Any]] = []
    if len(stamps_ns):
        first = int(stamps_ns[0])
        static = [
            messages.transform(first, BASE, LASER, mounts["laser"]),
            messages.transform(first, BASE, IMU, mounts["imu"]),
        ]
        out.append(("/tf_static", first, messages.tf(static)))
    no_intensities = np.zeros(0, np.float32)
    for i, t in enumerate(stamps_ns.tolist()):
        truth_odom = messages.odometry(t, (WORLD, BASE), world[i], truth_twist[i])
        out.append(("/ground_truth/odom", t, truth_odom))
        out.append((SCAN, t, messages.scan(t, ranges[i], no_intensities, intrinsics)))
        out.append((LABELS, t, messages.scan(t, ranges[i], labels[i], intrinsics)))
    if not dataset.missing_columns:
        out += _sensor_messages(table, messages, to_ns, tilt[:, 2])
    else:  # format 1: the truth at the scans' stamps, as that format's export wrote it
        imu_q = [table[f"imu_q{c}"].to_numpy() for c in "wxyz"]
        gyro = [table[f"imu_gyro_{c}_rad_s"].to_numpy() for c in "xyz"]
        accel = [table[f"imu_accel_{c}_mps2"].to_numpy() for c in "xyz"]
        for i, t in enumerate(stamps_ns.tolist()):
            dynamic = [
                messages.transform(t, ODOM, FOOTPRINT, planar[i]),
                messages.transform(t, FOOTPRINT, BASE, tilt[i]),
            ]
            out.append(("/tf", t, messages.tf(dynamic)))
            out.append(
                ("/odom", t, messages.odometry(t, (ODOM, FOOTPRINT), planar[i], truth_twist[i]))
            )
            out.append(("/imu", t, messages.imu(t, [q[i] for q in imu_q], [g[i] for g in gyro],
                                                 [a[i] for a in accel])))  # fmt: skip
    order = {topic: k for k, topic in enumerate(TOPICS)}
    out.sort(key=lambda item: (item[1], order[item[0]]))
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
        ros1_path: also write a ROS 1 ``.bag`` file here (must not exist).
        time_offset_s: added to every stamp (s); ROS reads a zero stamp as "latest".

    Returns:
        Messages written per topic.
    """
    if not math.isfinite(time_offset_s) or time_offset_s < 0:
        raise ValueError(f"time_offset_s: expected a finite value >= 0, got {time_offset_s}")
    if Path(out).exists():
        raise ValueError(f"out: {out} exists; a rosbag2 export writes a new folder")
    if ros1_path is not None and Path(ros1_path).exists():  # (as the folder: nothing lost)
        raise ValueError(f"ros1: {ros1_path} exists; the export writes a new .bag file")
    ros2 = _Messages(ros1=False)
    counts = dict.fromkeys(TOPICS, 0)
    items = episode_messages(dataset, episode, ros2, time_offset_s)  # checks before writing
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
            for topic, stamp_ns, message in items:
                writer.write(connections[topic], stamp_ns, ros2.serialize(message, TOPICS[topic]))
                counts[topic] += 1
        if ros1_path is not None:
            _write_ros1(dataset, episode, Path(ros1_path), time_offset_s)
    return counts


def _write_ros1(dataset: ScanDataset, episode: int, path: Path, time_offset_s: float) -> None:
    """The same messages as a ROS 1 ``.bag`` file (``path``, written whole or not at all)."""
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
