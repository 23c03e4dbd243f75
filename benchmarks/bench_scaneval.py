"""Throughput of the scaneval baselines and scan matchers, measured in one run.

1. Filters, single thread, on the same synthetic 10 Hz stream of 720-beam scans that
   benchmarks/bench_pvfilter.py uses (a sensor moving back and forth in an 8.5 m x 4 m
   room, 1 cm range noise, the right 120 degree sector blocked, a floor line ahead or
   behind for three scans of every twenty): ``PitchVariationFilter`` (Table I) against
   ``DatmoLikeFilter`` (given the sensor's true world pose) and ``ImuHeightGate``, runs
   interleaved so that machine load hits all alike. Also the per-beam precision and
   recall of the filter and the tracker on the stream's ground truth (default
   thresholds); the stream has no pitch to give the gate, so it runs level, for timing.
2. Matchers: ICP, NDT and HSM on pairs of consecutive scans of a sensor moving through a
   cluttered room (0.3 m/s, 0.3 rad/s at 10 Hz, as between two frames of the paper's
   section IV-D), with the median pose error against the truth.

    python benchmarks/bench_scaneval.py [--scans 2000] [--pairs 50] [--repeats 5]
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import os
import platform
import statistics
import time

import numpy as np
import scipy

from pvfilter import PitchVariationFilter
from pvfilter.synthetic import room_sequence
from scaneval.baselines import DatmoLikeFilter, ImuHeightGate
from scaneval.geometry import compose, invert, scan_points, wrap_angle
from scaneval.matching import MATCHERS
from scaneval.metrics import precision_recall
from scaneval.synthetic import cluttered_room, scan_from_pose

SEQUENCE_LENGTH = 200  # scans, cycled
SPEED = 0.3  # m/s, sensor in the matcher pairs
TURN_RATE = 0.3  # rad/s


def sensor_x(k: int) -> float:
    """World x of the sensor in scan k of ``room_sequence`` (it moves along x only), m."""
    return 0.5 * math.sin(2.0 * math.pi * (k % SEQUENCE_LENGTH) / 100.0)


def filter_runs(batch: list) -> dict:
    """One closure per method: filter the whole batch, return the removed masks."""

    def pvf(scans):
        f = PitchVariationFilter()
        return [f.process(scan).removed for scan in scans]

    def datmo(scans):
        f = DatmoLikeFilter()
        return [
            f.process(scan, pose_sensor_in_odom=(sensor_x(k), 0.0, 0.0)).removed
            for k, scan in enumerate(scans)
        ]

    def imu_gate(scans):
        f = ImuHeightGate()
        return [f.process(scan, pitch_rad=0.0, roll_rad=0.0).removed for scan in scans]

    return {
        "PitchVariationFilter": pvf,
        "DatmoLikeFilter": datmo,
        "ImuHeightGate": imu_gate,
    }


def timed(run, batch: list) -> tuple[float, list]:
    start = time.perf_counter()
    masks = run(batch)
    return len(batch) / (time.perf_counter() - start), masks


def bench_filters(count: int, repeats: int) -> None:
    sequence = room_sequence(SEQUENCE_LENGTH)
    batch = [
        dataclasses.replace(sequence.scans[k % SEQUENCE_LENGTH], stamp=0.1 * k)
        for k in range(count)
    ]
    runs = filter_runs(batch)
    rates: dict[str, list[float]] = {name: [] for name in runs}
    masks = {}
    for _ in range(repeats):  # interleaved: PVF, DATMO, gate, PVF, ...
        for name, run in runs.items():
            rate, masks[name] = timed(run, batch)
            rates[name].append(rate)
    positive = np.concatenate([sequence.truth[k % SEQUENCE_LENGTH] for k in range(count)])
    finite = np.concatenate([np.isfinite(scan.ranges) for scan in batch])
    pvf_rate = statistics.median(rates["PitchVariationFilter"])
    print(
        f"{'filter':24s} {'scans/s':>16s} {'us/scan':>8s} {'PVF / this':>12s} {'P':>6s} {'R':>6s}"
    )
    for name, values in rates.items():
        median = statistics.median(values)
        scores = "     -      -"  # the gate has no pitch here: nothing to score
        if name != "ImuHeightGate":
            precision, recall = precision_recall(np.concatenate(masks[name]), positive, finite)
            scores = f"{precision:6.3f} {recall:6.3f}"
        print(
            f"{name:24s} {median:8.0f} ({max(values):5.0f}) {1e6 / median:8.1f} "
            f"{pvf_rate / median:11.2f}x {scores}"
        )


def matcher_pairs(count: int) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """(source, target, true pose of source in target) for consecutive scans at 10 Hz."""
    room, rng = cluttered_room(), np.random.default_rng(0)
    pairs = []
    for k in range(count):
        heading = 2.0 * math.pi * k / count
        before = np.array([0.8 * math.cos(heading), 0.6 * math.sin(heading), heading])
        motion = np.array([0.1 * SPEED, 0.0, 0.1 * TURN_RATE * (1 if k % 2 else -1)])
        after = compose(before, motion)
        target = scan_points(scan_from_pose(room, before, rng=rng))
        source = scan_points(scan_from_pose(room, after, rng=rng))
        pairs.append((source, target, compose(invert(before), after)))
    return pairs


def bench_matchers(count: int, repeats: int) -> None:
    pairs = matcher_pairs(count)
    print(f"{'matcher':8s} {'matches/s':>16s} {'ms/match':>9s} {'median error':>22s}")
    for name, matcher in MATCHERS.items():
        rates, errors = [], []
        for _ in range(repeats):
            start = time.perf_counter()
            poses = [matcher(source, target).pose for source, target, _ in pairs]
            rates.append(len(pairs) / (time.perf_counter() - start))
        for pose, (_, _, truth) in zip(poses, pairs, strict=True):
            errors.append((np.hypot(*(pose[:2] - truth[:2])), abs(wrap_angle(pose[2] - truth[2]))))
        translation, rotation = np.median(np.array(errors), axis=0)
        median = statistics.median(rates)
        print(
            f"{name:8s} {median:8.1f} ({max(rates):5.1f}) {1e3 / median:9.2f} "
            f"{1e3 * translation:8.2f} mm {math.degrees(rotation):7.3f} deg"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scans", type=int, default=2000, help="scans per timed filter run")
    parser.add_argument("--pairs", type=int, default=50, help="scan pairs per timed matcher run")
    parser.add_argument("--repeats", type=int, default=5, help="timed runs per row")
    args = parser.parse_args()
    print(
        f"scaneval benchmark: 720-beam scans, median (best) of {args.repeats} runs; "
        f"python {platform.python_version()}, numpy {np.__version__}, "
        f"scipy {scipy.__version__}, {platform.machine()}, {os.cpu_count()} cpus\n"
    )
    bench_filters(args.scans, args.repeats)
    print()
    bench_matchers(args.pairs, args.repeats)


if __name__ == "__main__":
    main()
