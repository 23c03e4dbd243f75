"""The first pass over a bag: check the topics and the scans' stamps, gather robot inputs.

Everything that can be wrong with the request is found here, before an output is
written: a topic that is missing or of the wrong type, scans stamped out of order, a
mounting that no ``tf`` chain gives. The IMU, odometry and tf samples are read field by
field from their bytes (:mod:`pvfilter.bag.wire`), a few µs each.
"""

from __future__ import annotations

import argparse
import dataclasses
from typing import Any

import numpy as np

from pvfilter.bag.robot_inputs import AttitudeTrack, PoseTrack, mount_in_base, yaw_of
from pvfilter.bag.wire import (
    IMU,
    LASER_SCAN,
    ODOMETRY,
    header_stamp_ns,
    read_odometry,
    read_orientation,
    read_scan,
    read_transforms,
)

TF_TYPES = ("tf2_msgs/msg/TFMessage", "tf/msg/tfMessage")


@dataclasses.dataclass
class BagInputs:
    """What the first pass found.

    Attributes:
        scan_topic: the LaserScan topic filtered.
        scan_connections: its connections.
        filtered_topic: where the filtered scans go.
        removed_topic: where the removed masks go.
        scan_stamps_ns: every scan's ``header.stamp``, ns, in bag order.
        tracks: the robot-input streams (attitude, pose) the options asked for.
    """

    scan_topic: str
    scan_connections: list[Any]
    filtered_topic: str
    removed_topic: str
    scan_stamps_ns: list[int] = dataclasses.field(default_factory=list)
    tracks: list[AttitudeTrack | PoseTrack] = dataclasses.field(default_factory=list)

    @property
    def provides(self) -> tuple[str, ...]:
        """The robot inputs the filter gets."""
        names: tuple[str, ...] = ()
        for track in self.tracks:
            names += ("pitch_rad", "roll_rad") if isinstance(track, AttitudeTrack) else ()
            names += ("pose_sensor_in_odom",) if isinstance(track, PoseTrack) else ()
        return names

    def at(self, stamp_ns: int) -> dict[str, Any]:
        """The robot inputs at a scan's stamp (keyword arguments of ``process``)."""
        inputs: dict[str, Any] = {}
        for track in self.tracks:
            inputs.update(track.at(stamp_ns))
        return inputs


def _topic(connections: list[Any], option: str, topic: str, msgtype: str) -> list[Any]:
    """The connections of ``topic``, which must have type ``msgtype``."""
    found = [c for c in connections if c.topic == topic]
    if not found:
        same = sorted({c.topic for c in connections if c.msgtype == msgtype})
        kind = msgtype.split("/")[-1]
        listed = ", ".join(same) if same else "none"
        raise ValueError(f"{option} {topic}: not in the bag (its {kind} topics: {listed})")
    wrong = [c.msgtype for c in found if c.msgtype != msgtype]
    if wrong:
        raise ValueError(f"{option} {topic}: is {wrong[0]}, not {msgtype}")
    return found


def _scan_topic(connections: list[Any], topic: str | None) -> str:
    if topic is not None:
        return topic
    scans = sorted({c.topic for c in connections if c.msgtype == LASER_SCAN})
    if len(scans) != 1:
        listed = ", ".join(scans) if scans else "none"
        raise ValueError(
            f"--scan-topic: the bag has {len(scans)} LaserScan topics ({listed}); name one"
        )
    return scans[0]


def read_inputs(reader: Any, args: argparse.Namespace) -> BagInputs:
    """Check the options against the bag and read the robot inputs they name.

    Raises:
        ValueError: one line naming the topic, scan or frame that is wrong.
    """
    connections = list(reader.connections)
    scan_topic = _scan_topic(connections, args.scan_topic)
    inputs = BagInputs(
        scan_topic,
        _topic(connections, "--scan-topic", scan_topic, LASER_SCAN),
        args.filtered_topic or f"{scan_topic.rstrip('/')}/filtered",
        args.removed_topic or f"{scan_topic.rstrip('/')}/removed",
    )
    for option, topic in (("--filtered-topic", inputs.filtered_topic),
                          ("--removed-topic", inputs.removed_topic)):  # fmt: skip
        if any(c.topic == topic for c in connections):
            raise ValueError(f"{option} {topic}: the input bag has this topic already")
    if inputs.filtered_topic == inputs.removed_topic:
        raise ValueError(f"--removed-topic {inputs.removed_topic}: is the filtered topic")
    imu = _topic(connections, "--imu-topic", args.imu_topic, IMU) if args.imu_topic else []
    odom = _topic(connections, "--odom-topic", args.odom_topic, ODOMETRY) if args.odom_topic else []
    need_tf = bool(odom) and args.sensor_mount is None
    tf = [c for c in connections if c.msgtype in TF_TYPES] if need_tf else []
    ros1 = not reader.is2
    scan_ids, imu_ids, odom_ids = (
        {c.id for c in group} for group in (inputs.scan_connections, imu, odom)
    )
    imu_rows: list[tuple[int, np.ndarray]] = []
    odom_rows: list[tuple[int, float, float, float]] = []
    frames: dict[str, str] = {}
    transforms: dict[tuple[str, str], np.ndarray] = {}
    mount = None if need_tf else np.asarray(args.sensor_mount or (0.0, 0.0, 0.0), dtype=float)
    stamps = inputs.scan_stamps_ns
    for connection, _, raw in reader.messages(
        connections=inputs.scan_connections + imu + odom + tf
    ):
        if connection.id in scan_ids:
            stamp = header_stamp_ns(raw, ros1)
            if stamps and stamp < stamps[-1]:
                raise ValueError(
                    f"{scan_topic}: scan {len(stamps)} is stamped {stamp * 1e-9:.9f} s, before "
                    f"scan {len(stamps) - 1}'s {stamps[-1] * 1e-9:.9f} s (stamps out of order)"
                )
            if not stamps:
                frames["sensor"] = read_scan(raw, ros1).frame_id
            stamps.append(stamp)
        elif connection.id in imu_ids:
            imu_rows.append(read_orientation(raw, ros1))
        elif connection.id in odom_ids:
            stamp, _, child, pose = read_odometry(raw, ros1)
            frames.setdefault("base", child)
            odom_rows.append((stamp, float(pose[0]), float(pose[1]), yaw_of(pose[3:])))
        elif mount is None:
            for parent, child, transform in read_transforms(raw, ros1):
                transforms.setdefault((parent.lstrip("/"), child.lstrip("/")), transform)
            if len(frames) == 2:
                mount = mount_in_base(transforms, frames["base"], frames["sensor"])
    if odom:
        if mount is None and len(frames) == 2:
            mount = mount_in_base(transforms, frames["base"], frames["sensor"])
        if mount is None:
            base, sensor = frames.get("base", "?"), frames.get("sensor", "?")
            raise ValueError(
                f"--odom-topic {args.odom_topic}: no tf chain from {base} to {sensor} in the "
                "bag's /tf_static and /tf; give the LiDAR's mounting: --sensor-mount X Y YAW"
            )
    if imu:
        imu_stamps = np.array([s for s, _ in imu_rows], dtype=np.int64)
        inputs.tracks.append(AttitudeTrack(imu_stamps, np.array([q for _, q in imu_rows])))
    if odom:
        rows = np.array(odom_rows, dtype=np.float64).reshape(-1, 4)
        odom_stamps = np.array([r[0] for r in odom_rows], dtype=np.int64)
        inputs.tracks.append(PoseTrack(odom_stamps, rows[:, 1:], mount))
    return inputs
