"""Throughput of the SLAM loop on the simulator's 720-beam scans, single thread.

Input: the frames of ``house1_single`` (441 scans at 10 Hz in house1: gentle drives and
turns, one hard stop), simulated once before timing.

Prints scans/s of the Hector-style SLAM (default parameters: 3 map levels, 5 cm finest
cells), the split of its time between scan matching and map updates, the PVF followed by
the SLAM (the whole pipeline a robot would run), and KISS-ICP on one thread when it is
installed; and the ATE of each run as a check that the measured loop does its job. The
loops run interleaved, ``--repeats`` rounds; median and best scans/s per loop.

    python benchmarks/bench_slam.py [--repeats 5]
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import time

import numpy as np

from pvfilter import PitchVariationFilter
from scaneval.slam import HectorSlam, score_trajectory
from twsb_sim.robot_inputs import sensor_pose_2d
from twsb_sim.slam.recording import record_frames
from twsb_sim.slam.sequences import shipped_sequence
from twsb_sim.slam.systems import available_systems, make_system


def slam_loop(system: str, scans: list, range_max_m: float, with_pvf: bool = False):
    def run() -> np.ndarray:
        slam = make_system(system, range_max_m)
        pvf = PitchVariationFilter() if with_pvf else None
        poses = []
        for scan in scans:
            removed = pvf.process(scan).removed if pvf is not None else None
            slam.process_scan(scan, removed)
            poses.append(slam.pose.copy())
        return np.array(poses)

    return run


def hector_split(scans: list) -> tuple[float, float, int]:
    """Mean ms per scan spent matching, mean ms per map update, and the updates made."""
    slam, match_s, update_s, updates = HectorSlam(), 0.0, 0.0, 0
    update_maps = slam._update_maps

    def timed_update(points: np.ndarray) -> None:
        nonlocal update_s, updates
        start = time.perf_counter()
        update_maps(points)
        update_s += time.perf_counter() - start
        updates += 1

    slam._update_maps = timed_update
    for scan in scans:
        start = time.perf_counter()
        slam.process_scan(scan)
        match_s += time.perf_counter() - start
    match_s -= update_s
    return 1e3 * match_s / len(scans), 1e3 * update_s / max(updates, 1), updates


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()

    frames, _ = record_frames(shipped_sequence("house1_single").scenario, seed=0)
    scans = [f.scan for f in frames]
    truth = np.array([sensor_pose_2d(f.truth) for f in frames])
    range_max = scans[0].range_max
    print(
        f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
        f"python {platform.python_version()}, numpy {np.__version__}"
    )
    print(f"house1_single: {len(scans)} scans of {len(scans[0])} beams\n")
    rows = [("Hector-style SLAM", "hector", False), ("PVF + Hector-style SLAM", "hector", True)]
    if "kiss_icp" in available_systems():
        rows += [("KISS-ICP (1 thread)", "kiss_icp", False), ("PVF + KISS-ICP", "kiss_icp", True)]
    # interleaved: every loop runs once per round, so all see the same machine load
    loops = [slam_loop(system, scans, range_max, with_pvf) for _, system, with_pvf in rows]
    seconds: list[list[float]] = [[] for _ in rows]
    poses: list[np.ndarray] = [np.zeros(0)] * len(rows)
    for _ in range(args.repeats):
        for k, run in enumerate(loops):
            start = time.perf_counter()
            poses[k] = run()
            seconds[k].append(time.perf_counter() - start)
    print(f"{'loop':<26}{'scans/s median':>16}{'best':>8}{'ATE m':>9}")
    for (title, _, _), times, estimate in zip(rows, seconds, poses, strict=True):
        ate = score_trajectory(estimate, truth).rmse_m
        median, best = statistics.median(times), min(times)
        print(f"{title:<26}{len(scans) / median:>16.0f}{len(scans) / best:>8.0f}{ate:>9.4f}")
    match_ms, update_ms, updates = hector_split(scans)
    print(
        f"\nHector-style SLAM: matching {match_ms:.2f} ms per scan (3 levels, coarse to fine); "
        f"map update {update_ms:.1f} ms each, {updates} of {len(scans)} scans updated the maps"
    )


if __name__ == "__main__":
    main()
