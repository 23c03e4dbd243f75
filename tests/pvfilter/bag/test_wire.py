"""Fields read from message bytes agree with rosbags' full deserialization, in ROS 2 CDR
(both byte orders) and ROS 1, whatever the strings' lengths do to the alignment."""

from __future__ import annotations

import numpy as np
import pytest
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from pvfilter.bag.wire import read_transforms

FRAMES = [("odom", "base_footprint"), ("base_link", "laser_1")]  # lengths 4/14, 9/7


def _tf_message(store, ros1: bool):
    t = store.types
    transforms = []
    for i, (parent, child) in enumerate(FRAMES):
        stamp = t["builtin_interfaces/msg/Time"](sec=7 + i, nanosec=123 + i)
        seq = {"seq": i} if ros1 else {}  # ROS 1's header starts with a sequence number
        transforms.append(
            t["geometry_msgs/msg/TransformStamped"](
                header=t["std_msgs/msg/Header"](**seq, stamp=stamp, frame_id=parent),
                child_frame_id=child,
                transform=t["geometry_msgs/msg/Transform"](
                    translation=t["geometry_msgs/msg/Vector3"](x=0.1 + i, y=-0.2, z=0.3),
                    rotation=t["geometry_msgs/msg/Quaternion"](x=0.0, y=0.6, z=0.0, w=0.8),
                ),
            )
        )
    return t["tf2_msgs/msg/TFMessage"](transforms=transforms)


@pytest.mark.parametrize("encoding", ["cdr little-endian", "cdr big-endian", "ros1"])
def test_transforms_are_read_as_rosbags_deserializes_them(encoding):
    ros1 = encoding == "ros1"
    store = get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.ROS2_HUMBLE)
    if ros1:  # Noetic's store has no tf2_msgs
        definition = "geometry_msgs/TransformStamped[] transforms"
        store.register(get_types_from_msg(definition, "tf2_msgs/msg/TFMessage"))
    message = _tf_message(store, ros1)
    if ros1:
        raw = store.serialize_ros1(message, "tf2_msgs/msg/TFMessage")
    else:
        little = encoding == "cdr little-endian"
        raw = store.serialize_cdr(message, "tf2_msgs/msg/TFMessage", little_endian=little)
    read = read_transforms(bytes(raw), ros1)
    assert [(parent, child) for parent, child, _ in read] == FRAMES
    for (_, _, pose), expected in zip(read, message.transforms, strict=True):
        r, q = expected.transform.translation, expected.transform.rotation
        np.testing.assert_array_equal(pose, [r.x, r.y, r.z, q.w, q.x, q.y, q.z])
