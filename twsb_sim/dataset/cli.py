"""``twsb generate`` and ``twsb export-bag``: the data-set commands of the ``twsb`` CLI."""

from __future__ import annotations

import argparse
from pathlib import Path

from twsb_sim.config_errors import ConfigError
from twsb_sim.output_paths import output_file, output_folder
from twsb_sim.stopping import print_stop, stop_within


def add_dataset_commands(commands: argparse._SubParsersAction) -> None:
    """Register ``generate`` and ``export-bag`` on the ``twsb`` command line."""
    generate = commands.add_parser(
        "generate",
        help="generate a labeled data set (Parquet shards) of random episodes",
        description="Simulate random episodes (house, start, robot, commands, shoves) in "
        "parallel and write one Parquet shard per episode. Running the same command again "
        "resumes an interrupted run; more --episodes extends the data set.",
    )
    generate.add_argument("--out", type=Path, help="the data set's folder")
    generate.add_argument("--episodes", type=int, default=10, help="episodes (default 10)")
    generate.add_argument("--seed", type=int, default=0, help="data-set seed (default 0)")
    generate.add_argument(
        "--workers", type=int, default=None, help="local worker processes (default: one per core)"
    )
    generate.add_argument(
        "--scheduler",
        default=None,
        metavar="ADDRESS",
        help="run on a Dask distributed cluster (e.g. tcp://10.0.0.5:8786) instead",
    )
    generate.add_argument(
        "--ranges", type=Path, default=None, help="TOML file overriding randomization ranges"
    )
    generate.add_argument(
        "--show-ranges", action="store_true", help="print the ranges in effect as TOML and exit"
    )
    generate.add_argument("--quiet", action="store_true", help="no progress bar")
    generate.set_defaults(handler=_generate)

    export = commands.add_parser(
        "export-bag",
        help="write one episode of a data set as a rosbag2 (MCAP) and optionally a ROS 1 bag",
        description="Export an episode to a rosbag2 folder (MCAP storage) with /scan, "
        "/scan/labels, /imu, /odom, /tf and /tf_static, readable without ROS.",
    )
    export.add_argument("dataset", type=Path, help="the data set's folder")
    export.add_argument("--episode", type=int, default=0, help="episode number (default 0)")
    export.add_argument("--out", type=Path, required=True, help="rosbag2 folder to create")
    export.add_argument("--ros1", type=Path, default=None, help="also write this ROS 1 .bag file")
    export.add_argument(
        "--time-offset",
        type=float,
        default=1.0,
        help="s added to every stamp (default 1.0: ROS reads time 0 as 'latest')",
    )
    export.set_defaults(handler=_export_bag)


def _generate(args: argparse.Namespace) -> int:
    from twsb_sim.dataset.generation import GenerationSettings, generate
    from twsb_sim.dataset.randomization import load_randomization
    from twsb_sim.dataset.store import DatasetMismatchError

    ranges = load_randomization(args.ranges)
    if args.show_ranges:
        print(ranges.to_toml(), end="")
        return 0
    if args.out is None:
        raise ConfigError("--out", "", "missing: the data set's folder")
    output_folder(args.out)
    for flag, value, low in (("--episodes", args.episodes, 0), ("--seed", args.seed, 0)):
        if value < low:
            raise ConfigError(flag, "", f"expected an integer >= {low}, got {value}")
    if args.workers is not None and args.workers < 1:
        raise ConfigError("--workers", "", f"expected an integer >= 1, got {args.workers}")
    settings = GenerationSettings(seed=args.seed, randomization=ranges)
    try:
        report = generate(
            args.out,
            args.episodes,
            settings,
            workers=args.workers,
            scheduler=args.scheduler,
            progress=not args.quiet,
        )
    except DatasetMismatchError as error:
        raise ConfigError(error.root, "", error.reason) from None
    except BaseException as error:
        if stop_within(error) is None:  # a Ctrl-C or SIGTERM, perhaps wrapped
            raise
        print_stop(
            f"twsb: interrupted; finished episodes are kept in {args.out}: run the same "
            "command again to resume"
        )
        return 130
    print(
        f"{_count(report.episodes, 'episode')} in {args.out} ({report.generated} new, "
        f"{report.skipped} already there); {_count(report.scans, 'scan')} in "
        f"{report.wall_s:.1f} s ({report.scans_per_s:.0f} scans/s); of the new, "
        f"{report.fallen} ended in a fall"
    )
    return 0


def _count(number: int, noun: str) -> str:
    """``number`` and ``noun``, plural unless one: "1 episode", "3 episodes"."""
    return f"{number} {noun}" if number == 1 else f"{number} {noun}s"


def _export_bag(args: argparse.Namespace) -> int:
    from twsb_sim.dataset.loader import open_dataset
    from twsb_sim.dataset.rosbag import export_bag
    from twsb_sim.dataset.store import DatasetMismatchError

    try:
        dataset = open_dataset(args.dataset)
    except FileNotFoundError as error:
        raise ConfigError(args.dataset, "", str(error).split(": ", 1)[-1]) from None
    except DatasetMismatchError as error:
        raise ConfigError(error.root, "", error.reason) from None
    if args.episode not in dataset.episode_ids:
        raise ConfigError("--episode", "", f"{args.dataset} has no episode {args.episode}")
    if args.out.exists():
        raise ConfigError("--out", "", f"{args.out} exists; rosbag2 writes a new folder")
    output_folder(args.out)
    if args.ros1 is not None:
        output_file(args.ros1, "--ros1")
        if args.ros1.exists():
            raise ConfigError("--ros1", "", f"{args.ros1} exists; the export writes a new .bag")
    counts = export_bag(
        dataset, args.episode, args.out, ros1_path=args.ros1, time_offset_s=args.time_offset
    )
    topics = ", ".join(f"{topic} {n}" for topic, n in counts.items())
    print(f"episode {args.episode} written to {args.out} (rosbag2, MCAP): {topics}")
    if args.ros1 is not None:
        print(f"and to {args.ros1} (ROS 1)")
    return 0
