"""Throughput of the Pitch Variation Filter on 720-beam scans, single thread.

Input: a synthetic 10 Hz sequence of a sensor moving back and forth in an 8.5 m x 4 m
room (four walls, 1 cm range noise, the 120 degree sector on the right blocked), with a
floor line ahead or behind for three scans of every twenty (pvfilter.synthetic).

Prints scans/s of ``PitchVariationFilter.process`` (Table I parameters, and the modes;
nothing but the two-thread row starts a thread) and of the improved filter
(``ImprovedPitchVariationFilter``, defaults) in the same run,
the split of one scan's time over the stages, and the per-beam precision and recall on the
sequence's ground truth, as a check that the measured filter does its job.

    python benchmarks/bench_pvfilter.py [--scans 5000] [--repeats 5]
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import platform
import statistics
import time

import numpy as np
import scipy

from pvfilter import (
    FilterParams,
    ImprovedParams,
    Tracker,
    cluster_scan,
    detect_clusters,
)
from pvfilter.paper.filter import remove_queued
from pvfilter.paper.threaded import ThreadedPitchVariationFilter
from pvfilter.registry import filter_for
from pvfilter.synthetic import room_sequence

SEQUENCE_LENGTH = 200  # scans, cycled; ten pitch events
WARM_UP_SCANS = 50  # scans run untimed before each configuration's timed runs


def stream(scans: list, count: int) -> list:
    """``count`` scans cycling through ``scans``, restamped at 10 Hz (done before timing)."""
    return [dataclasses.replace(scans[i % len(scans)], stamp=0.1 * i) for i in range(count)]


def rate(run, batch: list, repeats: int) -> tuple[float, float]:
    """Median and best scans/s of ``run(batch)`` over ``repeats`` runs, after one untimed
    run over the first ``WARM_UP_SCANS`` (first calls pay for imports, caches and the
    KD-tree's set-up: with ``--repeats 1`` they would be the whole figure)."""
    run(batch[:WARM_UP_SCANS])
    rates = []
    for _ in range(repeats):
        start = time.perf_counter()
        run(batch)
        rates.append(len(batch) / (time.perf_counter() - start))
    return statistics.median(rates), max(rates)


def sequential(params: FilterParams | ImprovedParams):
    def run(batch):
        pvf = filter_for(params)
        for scan in batch:
            pvf.process(scan)

    return run


def threaded(params: FilterParams):
    def run(batch):
        with ThreadedPitchVariationFilter(params) as pvf:
            for _ in pvf.process_stream(batch):
                pass

    return run


def stage_split(batch: list, params: FilterParams) -> dict[str, float]:
    """Mean microseconds per scan of each stage, run as PitchVariationFilter runs them."""
    totals = dict.fromkeys(("cluster + KD-tree", "detect", "track", "remove"), 0.0)
    tracker, previous_tree = Tracker(params), None
    for i, scan in enumerate(batch):
        t0 = time.perf_counter()
        clusters = cluster_scan(scan, params)
        t1 = time.perf_counter()
        detection = detect_clusters(clusters, previous_tree, params, new_sequence=i == 0)
        previous_tree = clusters.tree
        t2 = time.perf_counter()
        tracked = tracker.update(detection)
        t3 = time.perf_counter()
        remove_queued(detection, tracked)
        t4 = time.perf_counter()
        for key, seconds in zip(totals, (t1 - t0, t2 - t1, t3 - t2, t4 - t3), strict=True):
            totals[key] += seconds
    return {key: 1e6 * seconds / len(batch) for key, seconds in totals.items()}


def precision_recall(
    scans: list, truth: list, params: FilterParams | ImprovedParams
) -> tuple[float, float]:
    pvf = filter_for(params)
    removed = np.concatenate([pvf.process(scan).removed for scan in scans])
    positive = np.concatenate(truth)
    hits = int((removed & positive).sum())
    return hits / max(int(removed.sum()), 1), hits / max(int(positive.sum()), 1)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scans", type=int, default=5000, help="scans per timed run")
    parser.add_argument("--repeats", type=int, default=5, help="timed runs per row")
    args = parser.parse_args()
    sequence = room_sequence(SEQUENCE_LENGTH)
    scans = sequence.scans
    batch = stream(scans, args.scans)
    table_one = FilterParams()
    print(
        f"pvfilter benchmark: {len(scans[0])}-beam scans, {args.scans} scans per run, "
        f"median (best) of {args.repeats} runs"
    )
    print(
        f"python {platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}, "
        f"{platform.machine()}, {os.cpu_count()} cpus\n"
    )
    rows = [
        ("sequential, Table I", sequential(table_one)),
        ("sequential, detection only", sequential(FilterParams(tracking=False))),
        ("sequential, radius clustering", sequential(FilterParams(clustering="radius"))),
        ("two threads, Table I", threaded(table_one)),
        ("sequential, improved filter", sequential(ImprovedParams())),
    ]
    print(f"{'configuration':32s} {'scans/s':>16s} {'us/scan':>8s}")
    for name, run in rows:
        median, best = rate(run, batch, args.repeats)
        print(f"{name:32s} {median:8.0f} ({best:5.0f}) {1e6 / median:8.1f}")
    split = stage_split(batch, table_one)
    total = sum(split.values())
    print(f"\nper-stage split, Table I, sequential (sum {total:.1f} us/scan):")
    for stage, micros in split.items():
        print(f"  {stage:20s} {micros:7.1f} us  {100.0 * micros / total:5.1f} %")
    for name, params in (("Table I", table_one), ("improved", ImprovedParams())):
        precision, recall = precision_recall(scans, sequence.truth, params)
        print(f"\n{name}: per-beam precision {precision:.3f}, recall {recall:.3f} on the sequence")


if __name__ == "__main__":
    main()
