"""Throughput of the Pitch Variation Filter on 720-beam scans, single thread.

Input: a synthetic 10 Hz sequence of a sensor moving back and forth in an 8.5 m x 4 m
room (four walls, 1 cm range noise, the 120 degree sector on the right blocked), with a
floor line ahead or behind for three scans of every twenty (pvfilter.synthetic).

Prints scans/s of ``PitchVariationFilter.process`` (Table I parameters, and the modes;
nothing but the two-thread row starts a thread) and of the improved filter
(``ImprovedPitchVariationFilter``, defaults), the sequential ones run in turn for
``--repeats`` rounds, with the improved filter's time per scan over Table I's per round
(the goal: at most 2x), the two-thread one in whole runs, each paired with a sequential
run of Table I;
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
from in_turn import seconds_in_turn  # this folder's: the filters fed in turn

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
TABLE_ONE_ROW = "sequential, Table I"  # the two rows the goal compares
IMPROVED_ROW = "sequential, improved filter"
THREADED_ROW = "two threads, Table I"
ROW_ORDER = (
    TABLE_ONE_ROW,
    "sequential, detection only",
    "sequential, radius clustering",
    THREADED_ROW,
    IMPROVED_ROW,
)


def stream(scans: list, count: int) -> list:
    """``count`` scans cycling through ``scans``, restamped at 10 Hz (done before timing)."""
    return [dataclasses.replace(scans[i % len(scans)], stamp=0.1 * i) for i in range(count)]


def rates_in_turn(
    configurations: dict[str, FilterParams | ImprovedParams], batch: list, repeats: int
) -> dict[str, list[float]]:
    """Per sequential configuration, its scans/s in each of ``repeats`` rounds.

    Each round makes a fresh filter per configuration and feeds them the batch in turn, a
    few scans at a time (:func:`in_turn.seconds_in_turn`), so that the ratio of two
    configurations holds on a machine whose speed drifts. First one untimed pass over
    ``WARM_UP_SCANS`` scans (first calls pay for imports, caches and the KD-tree's set-up:
    with ``--repeats 1`` they would be the whole figure).
    """
    seconds_in_turn(
        {name: filter_for(params) for name, params in configurations.items()},
        batch[:WARM_UP_SCANS],
    )
    rates: dict[str, list[float]] = {name: [] for name in configurations}
    for _ in range(repeats):
        filters = {name: filter_for(params) for name, params in configurations.items()}
        for name, seconds in seconds_in_turn(filters, batch).items():
            rates[name].append(len(batch) / seconds)
    return rates


def threaded_rates(
    params: FilterParams, batch: list, repeats: int
) -> tuple[list[float], list[float]]:
    """The two-thread filter's scans/s in each of ``repeats`` whole runs of the batch (it
    takes the stream whole, ``process_stream``: it cannot be fed in turn), each run right
    after a whole sequential run with the same parameters, and that run's scans/s: the
    pair's ratio holds where a drifting machine moves both alike (after one warm-up run
    each)."""

    def threaded(scans: list) -> None:
        with ThreadedPitchVariationFilter(params) as pvf:
            for _ in pvf.process_stream(scans):
                pass

    def sequential(scans: list) -> None:
        pvf = filter_for(params)
        for scan in scans:
            pvf.process(scan)

    threaded(batch[:WARM_UP_SCANS])
    sequential(batch[:WARM_UP_SCANS])
    threads, alone = [], []
    for _ in range(repeats):
        for run, rates in ((sequential, alone), (threaded, threads)):
            start = time.perf_counter()
            run(batch)
            rates.append(len(batch) / (time.perf_counter() - start))
    return threads, alone


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
    in_turn_rows = {  # the sequential configurations, fed the stream in turn
        TABLE_ONE_ROW: table_one,
        "sequential, detection only": FilterParams(tracking=False),
        "sequential, radius clustering": FilterParams(clustering="radius"),
        IMPROVED_ROW: ImprovedParams(),
    }
    rates = rates_in_turn(in_turn_rows, batch, args.repeats)
    rates[THREADED_ROW], sequential_beside = threaded_rates(table_one, batch, args.repeats)
    print(f"{'configuration':32s} {'scans/s':>16s} {'us/scan':>8s}")
    for name in ROW_ORDER:
        runs = rates[name]
        median = statistics.median(runs)
        print(f"{name:32s} {median:8.0f} ({max(runs):5.0f}) {1e6 / median:8.1f}")
    # time per scan, improved over Table I, round by round (scans/s: the inverse ratio)
    ratios = [
        paper / improved
        for paper, improved in zip(rates[TABLE_ONE_ROW], rates[IMPROVED_ROW], strict=True)
    ]
    print(
        f"\nimproved / Table I time per scan, per round: median {statistics.median(ratios):.2f}x "
        f"({min(ratios):.2f}-{max(ratios):.2f}x)"
    )
    paired = [
        alone / threads
        for threads, alone in zip(rates[THREADED_ROW], sequential_beside, strict=True)
    ]
    print(
        f"two threads / sequential Table I time per scan, whole runs in pairs: median "
        f"{statistics.median(paired):.2f}x ({min(paired):.2f}-{max(paired):.2f}x)"
    )
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
