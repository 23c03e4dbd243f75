"""How fast ``twsb generate`` makes labeled scans: per core, and with 2 workers against 1.

Generates the same episodes (default ranges, seed 0) into fresh folders with 1 worker
(in-process) and with 2 worker processes, alternating, and reports labeled scans per
second of wall time for each: everything a user waits for is in it (house generation,
simulation at 500 Hz with the LQR, LiDAR ray casts at 10 Hz, Parquet encoding, atomic
writes, the pool's start-up). Timings on a shared machine are noisy: the best of
``--repeats`` is kept. Usage::

    python benchmarks/bench_dataset.py [--episodes 48] [--repeats 1]
"""

from __future__ import annotations

import argparse
import importlib
import os
import tempfile
from pathlib import Path

from twsb_sim.dataset.generation import GenerationSettings, generate


def scans_per_s(episodes: int, workers: int, settings: GenerationSettings) -> tuple[float, int]:
    """Labeled scans per wall second of one ``generate`` run into a fresh folder."""
    with tempfile.TemporaryDirectory() as folder:
        report = generate(Path(folder) / "data", episodes, settings, workers, progress=False)
    return report.scans_per_s, report.scans


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=48, help="episodes per run")
    parser.add_argument("--repeats", type=int, default=1, help="runs per worker count")
    args = parser.parse_args()
    settings = GenerationSettings(seed=0)
    # imports, first gains: not timed; the gain design library (about a second to import)
    # is imported only when an episode's robot needs LQR gains, which the warm-up's may not
    importlib.import_module("control")
    with tempfile.TemporaryDirectory() as folder:
        generate(Path(folder), 1, GenerationSettings(seed=1), workers=1, progress=False)
    best = {1: 0.0, 2: 0.0}
    scans = 0
    for _ in range(args.repeats):
        for workers in (1, 2):
            rate, scans = scans_per_s(args.episodes, workers, settings)
            best[workers] = max(best[workers], rate)
    print(f"cores available          {len(os.sched_getaffinity(0))}")
    print(f"episodes per run         {args.episodes} ({scans} labeled scans, default ranges)")
    print(f"1 worker                 {best[1]:7.0f} labeled scans/s  (target >= 500 per core)")
    print(f"2 workers                {best[2]:7.0f} labeled scans/s")
    print(f"speed-up                 {best[2] / best[1]:7.2f}x          (target >= 1.7x)")
    print(f"(best of {args.repeats}, each run in a fresh folder)")


if __name__ == "__main__":
    main()
