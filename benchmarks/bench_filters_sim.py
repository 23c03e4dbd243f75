"""Throughput of the paper's and the improved filter on the simulator's scans, single thread.

Input: the evaluation's two sequences (``normal_sequence``, ``disturb_sequence``, seed 0)
in ``house1`` and in random houses 11 and 12, simulated once before timing (about 2,200
frames of 720 beams at 10 Hz: drives, turns, hard stops and shoves). The benchmark room of
``bench_pvfilter.py`` is simpler: a house gives more segments, and more bent ones.

Prints scans/s of the paper's filter (Table I) and of the improved filter (defaults, the
robot's LiDAR and axle heights, scans alone; and once more without re-anchoring the level
view, to show what that stage costs), fed each run's frames in turn a few at a time
(``in_turn.py``), ``--repeats`` rounds; the median and best of each, and the improved
filter's time per scan over the paper's, per round (the goal: at most 2x); then, from
one pass under cProfile, where the improved filter's time goes. The filters run as
``twsb eval`` runs them.

    python benchmarks/bench_filters_sim.py [--repeats 5] [--houses 3]
"""

from __future__ import annotations

import argparse
import cProfile
import os
import platform
import pstats
import statistics
from pathlib import Path

import numpy as np
import scipy
from in_turn import CHUNK_SCANS, seconds_in_turn  # this folder's: the filters fed in turn

from pvfilter import ImprovedParams
from twsb_sim.evaluation.improved import improved_filter
from twsb_sim.evaluation.recording import record, sequence_in_house
from twsb_sim.frame_filter import frame_filter

SEQUENCES = ("normal_sequence", "disturb_sequence")
HOUSES = (("house1", None), (None, 11), (None, 12))  # (named layout, random house seed)
WARM_UP_FRAMES = 50  # frames each filter takes untimed before the timed rounds
NO_REANCHOR = ImprovedParams(reanchor_view=False)  # what the level view's re-anchoring costs
STAGES = (  # (label, (module, function)): the improved filter's stages, and parts of them
    ("line detection", ("detection.py", "detect_lines")),
    ("  scoring", ("scoring.py", "score_segments")),
    ("  corners", ("corners.py", "split_at_corners")),
    ("  claims", ("claims.py", "best_claims")),
    ("level view moved and compared", ("filter.py", "_evidence")),
    ("  re-anchoring", ("filter.py", "_reanchor")),
    ("scan preparation", ("filter.py", "_prepare")),
    ("  segmentation", ("segmentation.py", "segment_scan")),
    ("ego-motion match", ("filter.py", "_match")),
    ("teaching the level view", ("filter.py", "_remember")),
)


def recordings(houses: int) -> list:
    """The sequences in the first ``houses`` houses, each simulated once (seed 0)."""
    runs = []
    for sequence in SEQUENCES:
        for name, seed in HOUSES[:houses]:
            scenario, house = sequence_in_house(sequence, name, seed, None)
            runs.append(record(scenario, house, 0))
    return runs


def seconds_per_scan_in_turn(makers: dict, runs: list) -> dict[str, float]:
    """Per filter, mean seconds per frame over ``runs``: for each run a fresh filter each
    from ``make(recording)``, fed the run's frames in turn, a few at a time
    (:func:`in_turn.seconds_in_turn`: their ratio holds on a machine whose speed drifts)."""
    elapsed = dict.fromkeys(makers, 0.0)
    frames = 0
    for run in runs:
        filters = {name: make(run) for name, make in makers.items()}
        for scan_filter in filters.values():
            scan_filter.reset()
        for name, seconds in seconds_in_turn(filters, run.frames).items():
            elapsed[name] += seconds
        frames += len(run.frames)
    return {name: seconds / frames for name, seconds in elapsed.items()}


def where_the_time_goes(runs: list) -> tuple[dict[str, float], float]:
    """The share of the improved filter's time in each of ``STAGES`` (cumulative, from one
    pass under cProfile, whose overhead weighs on the many small calls: the shares, not
    the times, are the point), and the share of frames whose lines were fitted (new
    returns on a segment across the travel: scored, cut at corners and claimed)."""
    profile = cProfile.Profile()
    fitted = frames = 0
    for run in runs:
        scan_filter = improved_filter(run, inputs=())
        scan_filter.reset()
        for frame in run.frames:
            profile.enable()
            result = scan_filter.process(frame)
            profile.disable()
            fitted += bool(np.isfinite(result.lines.segment_scores.tilt_rad).any())
            frames += 1
    cumulative: dict[tuple[str, str], float] = {}
    for (path, _, name), (_, _, _, seconds, _) in pstats.Stats(profile).stats.items():
        if "improved" in Path(path).parts:
            key = (Path(path).name, name)
            cumulative[key] = cumulative.get(key, 0.0) + seconds
    total = cumulative[("filter.py", "process")]
    shares = {label: cumulative.get(key, 0.0) / total for label, key in STAGES}
    return shares, fitted / frames


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=5, help="rounds of the filters in turn")
    parser.add_argument("--houses", type=int, default=3, choices=(1, 2, 3), help="houses")
    args = parser.parse_args()
    runs = recordings(args.houses)
    frames = sum(len(run.frames) for run in runs)
    print(
        f"filters on the simulator's scans: {frames} frames of {len(runs)} runs, "
        f"{args.repeats} rounds, the filters in turn {CHUNK_SCANS} frames at a time"
    )
    print(
        f"python {platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}, "
        f"{platform.machine()}, {os.cpu_count()} cpus\n"
    )
    filters = {
        "paper (Table I)": lambda run: frame_filter("paper", "paper", None, run.geometry, ()),
        "improved (defaults)": lambda run: improved_filter(run, inputs=()),
        "improved, no re-anchor": lambda run: improved_filter(run, NO_REANCHOR, inputs=()),
    }
    # one untimed pass first: the first calls pay for imports and caches, and the filter
    # whose turn comes first would pay them alone
    seconds_in_turn(
        {name: make(runs[0]) for name, make in filters.items()}, runs[0].frames[:WARM_UP_FRAMES]
    )
    times: dict[str, list[float]] = {name: [] for name in filters}
    for _ in range(args.repeats):
        for name, seconds in seconds_per_scan_in_turn(filters, runs).items():
            times[name].append(seconds)
    print(f"{'filter':24s} {'scans/s':>16s} {'us/scan':>8s}")
    for name, seconds in times.items():
        median = statistics.median(seconds)
        print(f"{name:24s} {1.0 / median:8.0f} ({1.0 / min(seconds):5.0f}) {1e6 * median:8.1f}")
    ratios = [
        i / p for i, p in zip(times["improved (defaults)"], times["paper (Table I)"], strict=True)
    ]
    print(
        f"\nimproved / paper time per scan, per round: median {statistics.median(ratios):.2f}x "
        f"({min(ratios):.2f}-{max(ratios):.2f}x)"
    )
    shares, fitted = where_the_time_goes(runs)
    print(
        f"\nwhere the improved filter's time goes (cProfile, cumulative, its overhead "
        f"included; lines fitted in {100.0 * fitted:.0f} % of the frames):"
    )
    for label, share in shares.items():
        print(f"  {label:32s} {100.0 * share:5.1f} %")


if __name__ == "__main__":
    main()
