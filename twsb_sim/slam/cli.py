"""``twsb slam``: the SLAM-in-the-loop experiment from the command line."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from twsb_sim.config_errors import ConfigError
from twsb_sim.output_paths import output_folder
from twsb_sim.staging import staged_folder


def add_slam_parser(commands: argparse._SubParsersAction) -> None:
    """Register ``twsb slam`` on the ``twsb`` command line."""
    slam = commands.add_parser(
        "slam",
        help="SLAM with and without the filter: ATE, maps, trajectories (paper Table II)",
        description="Simulate the House sequences and hard stops in random houses once per "
        "seed, run the Hector-style SLAM and KISS-ICP over the scans with no filter, the "
        "Pitch Variation Filter, the IMU height gate and the truth labels, and write "
        "report.md, results.json, maps and trajectories (PNG), TUM files and Rerun "
        "recordings.",
    )
    slam.add_argument("--out", type=Path, required=True, help="output folder")
    slam.add_argument(
        "--quick", action="store_true", help="smoke run: 2 sequences, 1 seed, 20 s each"
    )
    slam.add_argument("--seeds", type=int, nargs="+", default=None, help="run seeds (0 1 2)")
    slam.add_argument(
        "--random-houses", type=int, nargs="*", default=None, help="random house seeds (1 2 3 4)"
    )
    slam.add_argument("--no-rerun", action="store_true", help="write no Rerun recordings")
    slam.add_argument("--quiet", action="store_true", help="no progress bar")
    slam.set_defaults(handler=_run_slam)


def _run_slam(args: argparse.Namespace) -> int:
    import dataclasses

    from twsb_sim.slam.experiment import SlamConfig
    from twsb_sim.slam.pipeline import run_slam_experiment
    from twsb_sim.slam.systems import available_systems

    output_folder(args.out)
    config = SlamConfig.quick() if args.quick else SlamConfig()
    overrides = {}
    if args.seeds is not None:
        overrides["seeds"] = tuple(args.seeds)
    if args.random_houses is not None:
        overrides["random_houses"] = tuple(args.random_houses)
    try:
        config = dataclasses.replace(config, **overrides)
    except ValueError as error:
        raise ConfigError("twsb slam", "", str(error)) from None
    if "kiss_icp" not in available_systems():
        print(
            'twsb slam: KISS-ICP is not installed (pip install "twsb-pvfilter[slam]"): '
            "running the Hector-style SLAM only",
            file=sys.stderr,
        )
    command = "twsb slam " + " ".join(sys.argv[2:]) if sys.argv[1:2] == ["slam"] else "twsb slam"
    with staged_folder(args.out) as staging:  # the outputs appear whole or not at all
        outputs = run_slam_experiment(
            config, staging, progress=not args.quiet, rerun=not args.no_rerun, command=command
        )
    failures = sum(r.failed for r in outputs.results)
    print(
        f"{len(outputs.results)} SLAM runs, {failures} tracking failures; "
        f"report: {args.out / 'report.md'}, results: {args.out / 'results.json'}"
    )
    return 0
