"""``pvfilter bag IN OUT``: run any registered filter over the LaserScan topic of a ROS bag.

Reads a rosbag2 (sqlite3 or MCAP) folder or a ROS 1 ``.bag`` file and writes a bag of the
same format with every input message copied unchanged, plus two topics stamped like the
scans they come from:

- ``<scan topic>/filtered`` (``sensor_msgs/LaserScan``): the scan with the removed beams
  set to NaN, as ROS ``laser_filters`` does; every other field as in the input;
- ``<scan topic>/removed`` (``sensor_msgs/LaserScan``): the input scan with the removed
  mask as its intensities (1 removed, 0 kept), read by any ROS tool and paired with the
  scan by an exact-time synchronizer, as the simulator's ``/scan/labels`` is.

``--imu-topic`` (``sensor_msgs/Imu``) and ``--odom-topic`` (``nav_msgs/Odometry``) give
the filter its robot inputs (:mod:`pvfilter.bag.robot_inputs`); the LiDAR's mounting in
the odometry's child frame comes from ``/tf_static`` and ``/tf``, or ``--sensor-mount``.
Exit status: 0 done, 2 a user mistake (one line naming it), 130 interrupted.
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from pvfilter.bag.bagfile import open_reader, require_rosbags
from pvfilter.bag.input_bag import InputBag
from pvfilter.bag.inputs_pass import BagInputs, read_inputs
from pvfilter.bag.outputs import open_output
from pvfilter.bag.progress import Progress
from pvfilter.bag.staging import staged_output
from pvfilter.bag.wire import read_scan
from pvfilter.cli_options import (
    add_filter_options,
    chosen_filter,
    filter_notes,
)
from pvfilter.contract import ScanFilter
from pvfilter.exits import run_command
from pvfilter.scan import Scan


def build_parser() -> argparse.ArgumentParser:
    """The command's arguments."""
    parser = argparse.ArgumentParser(
        prog="pvfilter bag",
        description="Filter the LaserScan topic of a ROS bag (rosbag2 sqlite3/MCAP or ROS 1): "
        "every topic is copied, the filtered scan and the removed mask are added.",
    )
    parser.add_argument("input", help="the bag: a rosbag2 folder or a ROS 1 .bag file")
    parser.add_argument("output", help="the bag to write (same format as the input)")
    parser.add_argument("--scan-topic", metavar="TOPIC", help="(default: the one LaserScan topic)")
    parser.add_argument("--imu-topic", metavar="TOPIC", help="sensor_msgs/Imu: pitch and roll")
    parser.add_argument("--odom-topic", metavar="TOPIC", help="nav_msgs/Odometry: the pose")
    parser.add_argument(
        "--sensor-mount",
        nargs=3,
        type=float,
        metavar=("X", "Y", "YAW"),
        help="the LiDAR in the odometry's child frame (m, m, rad; default: from /tf_static)",
    )
    parser.add_argument("--filtered-topic", metavar="TOPIC", help="(default: SCAN/filtered)")
    parser.add_argument("--removed-topic", metavar="TOPIC", help="(default: SCAN/removed)")
    add_filter_options(parser)
    parser.add_argument("--force", action="store_true", help="replace an existing output")
    parser.add_argument("--quiet", action="store_true", help="no progress line")
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command; returns the exit status."""
    args = build_parser().parse_args(argv)

    def work() -> int:
        require_rosbags()
        return filter_bag(args)

    return run_command(
        "pvfilter bag", work, "interrupted; the output was not written",
        mistakes=(ImportError, OSError, ValueError),  # ImportError: rosbags is missing
    )  # fmt: skip


def filter_bag(args: argparse.Namespace) -> int:
    """Filter the bag the options name and write the output bag (see the module docstring)."""
    entry, params = chosen_filter(args)
    scan_filter = entry.make(params)  # (a bag states no robot geometry: the options may)
    source, out = Path(args.input), Path(args.output)
    if out.exists() and source.exists() and out.resolve() == source.resolve():
        raise ValueError(f"{out}: is the input bag; write the output elsewhere")
    if out.exists() and not args.force:
        raise ValueError(f"{out}: exists; give --force to replace it")
    start = time.perf_counter()  # the rate counts the reading and writing too
    bag = open_reader(source)
    try:
        inputs = read_inputs(bag, args)  # checks topics and stamps before writing
        missing = [name for name in entry.needs if name not in inputs.provides]
        if missing:
            raise ValueError(
                f"filter {entry.name!r} needs {', '.join(missing)}: give "
                + ("--imu-topic" if "pitch_rad" in missing else "--odom-topic")
            )
        with staged_output(out, replace=args.force) as path:
            removed, valid = _write(bag, path, inputs, scan_filter, args)
        elapsed = time.perf_counter() - start
    finally:
        bag.close()
    count = len(inputs.scan_stamps_ns)
    rate = count / elapsed if elapsed > 0 else float("inf")
    share = 100.0 * removed / valid if valid else 0.0
    used = f" with {', '.join(inputs.provides)}" if inputs.provides else ""
    print(
        f"pvfilter bag: {entry.name} filter on {inputs.scan_topic}, {count} scans{used}, "
        f"removed {removed} of {valid} valid beams ({share:.2f} %), {rate:.0f} scans/s"
    )
    for note in filter_notes("pvfilter bag", args, params, {}):
        print(note)
    print(f"pvfilter bag: wrote {out} (+ {inputs.filtered_topic}, {inputs.removed_topic})")
    return 0


def _write(
    bag: InputBag, path: Path, inputs: BagInputs, scan_filter: ScanFilter, args: argparse.Namespace
) -> tuple[int, int]:
    """Copy every message, filter the scans; returns removed and valid beam counts."""
    writer = open_output(bag, path)
    first = inputs.scan_connections[0]
    filtered_out = writer.add_topic(first, inputs.filtered_topic)
    removed_out = writer.add_topic(first, inputs.removed_topic)
    progress = Progress(len(inputs.scan_stamps_ns), "scans", quiet=args.quiet)
    removed_total = valid_total = 0
    ros1 = not bag.is2
    try:
        for _, stamp_ns, raw in writer.read_through(bag, inputs.scan_connections):
            message = read_scan(raw, ros1)
            scan, reversed_beams = scan_of(message, inputs.scan_topic, progress.done)
            result = scan_filter.process(scan, **inputs.at(message.stamp_ns))
            removed = np.asarray(result.removed, dtype=bool)
            if reversed_beams:  # back to the message's (clockwise) order
                removed = removed[::-1]
            filtered = np.where(removed, np.float32(np.nan), message.ranges)
            writer.write(filtered_out, stamp_ns, message.with_ranges(filtered))
            writer.write(removed_out, stamp_ns, message.with_intensities(removed))
            removed_total += int(np.count_nonzero(removed))
            valid_total += int(np.count_nonzero(scan.valid_mask()))
            progress.advance()
    except BaseException:
        writer.abort()
        raise
    else:
        writer.close()
    finally:
        progress.close()
    return removed_total, valid_total


def scan_of(message: object, topic: str, index: int) -> tuple[Scan, bool]:
    """The filter's scan of a LaserScan message (the filters use no intensities), and
    whether its beams are the message's reversed (a clockwise message, negative
    ``angle_increment``: :meth:`Scan.counter_clockwise`)."""
    fields = message.intrinsics
    try:
        return Scan.counter_clockwise(
            ranges=message.ranges,
            angle_min=fields["angle_min"],
            angle_increment=fields["angle_increment"],
            range_min=fields["range_min"],
            range_max=fields["range_max"],
            stamp=message.stamp_ns * 1e-9,
            time_increment=fields["time_increment"],
            scan_time=fields["scan_time"],
        )
    except ValueError as error:
        raise ValueError(f"{topic}: scan {index}: {error}") from None
