"""Throughput of ``pvfilter bag`` on a bag that ``twsb export-bag`` wrote, I/O included.

Input: one generated episode (``--duration`` s of a random episode, 10 Hz scans, the
robot's 200 Hz IMU, 50 Hz odometry, tf and ground truth: about 34 messages per scan),
exported as a rosbag2 (MCAP) and a ROS 1 bag.

Prints, per bag format, the scans/s of the whole command run in this process (open,
first pass, copying every message, filtering, writing the filtered and removed topics,
closing; the registry's plug-ins loaded beforehand) and of the filter alone on the same
scans, measured in the same run, and their ratio. The default filter is the command's
(``paper``); ``--filter NAME`` measures another.

    python benchmarks/bench_bag.py [--duration 60] [--repeats 3] [--filter paper]
"""

from __future__ import annotations

import argparse
import io
import statistics
import tempfile
import time
from contextlib import redirect_stdout
from pathlib import Path

from pvfilter import make_filter
from pvfilter.bag.bagfile import open_reader
from pvfilter.bag.command import scan_of
from pvfilter.bag.wire import read_scan
from pvfilter.cli import main as pvfilter_main
from pvfilter.registry import filter_names
from twsb_sim.dataset.generation import GenerationSettings, generate
from twsb_sim.dataset.loader import open_dataset
from twsb_sim.dataset.randomization import randomization_from_table
from twsb_sim.dataset.rosbag import export_bag


def exported_bags(folder: Path, duration_s: float) -> tuple[Path, Path]:
    """One episode of ``duration_s`` seconds as a rosbag2 folder and a ROS 1 bag."""
    table = {"episode": {"duration_s": [duration_s, duration_s]}}
    settings = GenerationSettings(seed=5, randomization=randomization_from_table(table))
    generate(folder / "data", 1, settings, workers=1, progress=False)
    ros2, ros1 = folder / "episode", folder / "episode.bag"
    export_bag(open_dataset(folder / "data"), 0, ros2, ros1_path=ros1)
    return ros2, ros1


def bag_rate(source: Path, out: Path, name: str, repeats: int) -> tuple[float, int]:
    """Median scans/s of ``pvfilter bag`` over ``repeats`` runs, and the scan count."""
    rates, count = [], 0
    for _ in range(repeats):
        argv = ["bag", str(source), str(out), "--scan-topic", "/scan", "--filter", name]
        start = time.perf_counter()
        with redirect_stdout(io.StringIO()) as printed:
            assert pvfilter_main([*argv, "--quiet", "--force"]) == 0
        elapsed = time.perf_counter() - start
        count = int(printed.getvalue().split(" scans")[0].rsplit(" ", 1)[1])
        rates.append(count / elapsed)
    return statistics.median(rates), count


def filter_rate(source: Path, name: str, repeats: int) -> float:
    """Median scans/s of the filter alone on the bag's scans (read beforehand)."""
    reader = open_reader(source)
    try:
        scans = [
            scan_of(read_scan(raw, not reader.is2), "/scan", i)[0]
            for i, (_, _, raw) in enumerate(
                reader.messages(connections=[c for c in reader.connections if c.topic == "/scan"])
            )
        ]
    finally:
        reader.close()
    rates = []
    for _ in range(repeats):
        scan_filter = make_filter(name)
        start = time.perf_counter()
        for scan in scans:
            scan_filter.process(scan)
        rates.append(len(scans) / (time.perf_counter() - start))
    return statistics.median(rates)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--duration", type=float, default=60.0, help="episode length, s")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--filter", default="paper")
    args = parser.parse_args()
    filter_names()  # the registry's plug-ins, loaded once per process, are not the bag's cost
    with tempfile.TemporaryDirectory() as tmp:
        ros2, ros1 = exported_bags(Path(tmp), args.duration)
        print(f"pvfilter bag, {args.filter} filter, median of {args.repeats} runs")
        print(f"{'bag':18s} {'scans':>6s} {'bag scans/s':>12s} {'filter alone':>13s} {'ratio':>6s}")
        for label, source, out in (
            ("rosbag2 (MCAP)", ros2, Path(tmp) / "out"),
            ("ROS 1", ros1, Path(tmp) / "out.bag"),
        ):
            rate, count = bag_rate(source, out, args.filter, args.repeats)
            alone = filter_rate(source, args.filter, args.repeats)
            print(f"{label:18s} {count:6d} {rate:12.0f} {alone:13.0f} {rate / alone:6.2f}")


if __name__ == "__main__":
    main()
