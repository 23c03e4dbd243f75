"""The few fields ``pvfilter bag`` needs, read straight from serialized ROS messages.

Deserializing a whole message with a generic reader costs 20-80 µs in Python (and
building the reader's types from the bag's definitions 50-200 ms); an IMU at 200 Hz
beside a 10 Hz LiDAR would take more time than the filter. The fields needed here
sit at offsets that only the header's ``frame_id`` shifts, so they are read with
``struct`` and numpy in a few µs, in both wire formats:

- ROS 2 (CDR, XCDR1): a 4-byte encapsulation header (byte 1: 1 little-endian, 0
  big-endian), then the fields, each aligned to its size from the end of that header;
  ``std_msgs/Header`` is ``int32 sec, uint32 nanosec, string frame_id``;
- ROS 1: little-endian, unaligned; ``std_msgs/Header`` is ``uint32 seq, uint32 sec,
  uint32 nsec, string frame_id``; strings carry no terminating NUL.

A filtered scan is the input's bytes with its ranges replaced, so every other field
(header, intrinsics, intensities) is carried over bit for bit.
"""

from __future__ import annotations

import dataclasses
import functools
import struct

import numpy as np

LASER_SCAN = "sensor_msgs/msg/LaserScan"
IMU = "sensor_msgs/msg/Imu"
ODOMETRY = "nav_msgs/msg/Odometry"


@functools.cache
def _struct(layout: str) -> struct.Struct:
    """A compiled ``struct`` layout (compiling one costs more than unpacking it)."""
    return struct.Struct(layout)


class _Cursor:
    """Reads fields in order, aligning them as the wire format does."""

    def __init__(self, raw: bytes | memoryview, ros1: bool) -> None:
        self.raw, self.ros1 = raw, ros1
        if ros1:
            self.start, self.endian = 0, "<"
        else:
            if len(raw) < 4 or raw[1] not in (0, 1):
                raise ValueError("not a CDR message (unknown encapsulation header)")
            self.start, self.endian = 4, "<" if raw[1] == 1 else ">"
        self.at = self.start

    def align(self, size: int) -> None:
        if not self.ros1:
            self.at += -(self.at - self.start) % size

    def take(self, code: str, count: int = 1) -> tuple:
        layout = _struct(f"{self.endian}{count}{code}")
        self.align(layout.size // count)
        values = layout.unpack_from(self.raw, self.at)
        self.at += layout.size
        return values

    def string(self) -> str:
        (length,) = self.take("I")
        text = bytes(self.raw[self.at : self.at + length])
        self.at += length
        return text.rstrip(b"\0").decode("utf-8", errors="replace")

    def stamp_ns(self) -> int:
        """Reads a ``std_msgs/Header``'s stamp (and skips its frame id)."""
        if self.ros1:
            _, sec, nsec = self.take("I", 3)
        else:
            sec, nsec = self.take("i")[0], self.take("I")[0]
        return sec * 1_000_000_000 + nsec

    def float32_array(self) -> tuple[int, np.ndarray]:
        """A ``float32[]``: its data's byte offset and its values (a read-only view)."""
        (count,) = self.take("I")
        data = np.frombuffer(self.raw, dtype=f"{self.endian}f4", count=count, offset=self.at)
        offset = self.at
        self.at += 4 * count
        return offset, data


def header_stamp_ns(raw: bytes | memoryview, ros1: bool) -> int:
    """The ``header.stamp`` of any message that starts with a ``std_msgs/Header``, ns."""
    return _Cursor(raw, ros1).stamp_ns()


@dataclasses.dataclass(frozen=True)
class RawScan:
    """A serialized ``sensor_msgs/LaserScan``, its fields read in place.

    Attributes:
        raw: the message's bytes.
        stamp_ns: ``header.stamp``, ns.
        frame_id: ``header.frame_id``.
        intrinsics: ``angle_min`` ... ``range_max`` (the seven float32 fields) by name.
        ranges: the ranges, float32, read-only, in the message's byte order.
        ranges_offset: byte offset of the ranges' data.
        intensities_at: byte offset of the intensities' length field.
        endian: ``"<"`` or ``">"``.
    """

    raw: bytes
    stamp_ns: int
    frame_id: str
    intrinsics: dict[str, float]
    ranges: np.ndarray
    ranges_offset: int
    intensities_at: int
    endian: str

    def with_ranges(self, ranges: np.ndarray) -> bytes:
        """The same message with other ranges (same count): a filtered scan."""
        data = np.asarray(ranges, dtype=f"{self.endian}f4").tobytes()
        end = self.ranges_offset + len(data)
        return self.raw[: self.ranges_offset] + data + self.raw[end:]

    def with_intensities(self, intensities: np.ndarray) -> bytes:
        """The same message with other intensities (any count)."""
        values = np.asarray(intensities, dtype=f"{self.endian}f4")
        count = struct.pack(f"{self.endian}I", values.size)
        return self.raw[: self.intensities_at] + count + values.tobytes()


SCAN_FIELDS = ("angle_min", "angle_max", "angle_increment", "time_increment", "scan_time")
SCAN_FIELDS += ("range_min", "range_max")


def read_scan(raw: bytes, ros1: bool) -> RawScan:
    """The fields of a serialized ``sensor_msgs/LaserScan``.

    Raises:
        ValueError: bytes too short for a LaserScan.
    """
    try:
        cursor = _Cursor(raw, ros1)
        stamp_ns = cursor.stamp_ns()
        frame_id = cursor.string()
        intrinsics = dict(zip(SCAN_FIELDS, cursor.take("f", 7), strict=True))
        offset, ranges = cursor.float32_array()
        cursor.align(4)
        intensities_at = cursor.at
    except (struct.error, ValueError) as error:
        raise ValueError(f"not a LaserScan message ({error})") from None
    return RawScan(
        bytes(raw), stamp_ns, frame_id, intrinsics, ranges, offset, intensities_at, cursor.endian
    )


def read_orientation(raw: bytes | memoryview, ros1: bool) -> tuple[int, np.ndarray]:
    """``header.stamp`` (ns) and ``orientation`` ``(w, x, y, z)`` of a ``sensor_msgs/Imu``."""
    cursor = _Cursor(raw, ros1)
    stamp_ns = cursor.stamp_ns()
    cursor.string()
    x, y, z, w = cursor.take("d", 4)
    return stamp_ns, np.array([w, x, y, z])


def read_odometry(raw: bytes | memoryview, ros1: bool) -> tuple[int, str, str, np.ndarray]:
    """``header.stamp`` (ns), ``header.frame_id``, ``child_frame_id`` and the pose
    ``(x, y, z, qw, qx, qy, qz)`` of a ``nav_msgs/Odometry``."""
    cursor = _Cursor(raw, ros1)
    stamp_ns = cursor.stamp_ns()
    frame_id = cursor.string()
    child = cursor.string()
    x, y, z, qx, qy, qz, qw = cursor.take("d", 7)
    return stamp_ns, frame_id, child, np.array([x, y, z, qw, qx, qy, qz])


def read_transforms(raw: bytes | memoryview, ros1: bool) -> list[tuple[str, str, np.ndarray]]:
    """``(header.frame_id, child_frame_id, (x, y, z, qw, qx, qy, qz))`` of each transform
    of a ``tf2_msgs/TFMessage`` (ROS 1: ``tf/tfMessage``): the child frame in the parent."""
    cursor = _Cursor(raw, ros1)
    (count,) = cursor.take("I")
    transforms = []
    for _ in range(count):
        cursor.stamp_ns()
        parent, child = cursor.string(), cursor.string()
        x, y, z, qx, qy, qz, qw = cursor.take("d", 7)
        transforms.append((parent, child, np.array([x, y, z, qw, qx, qy, qz])))
    return transforms
