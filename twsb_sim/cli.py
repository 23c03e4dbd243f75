"""The ``twsb`` command line.

``twsb run SCENARIO`` simulates a scenario with the filter in the loop, shows a progress
bar, prints a summary and (with ``--out``) writes the frames. User mistakes (a bad
scenario file, a wrong flag value) print one line naming the problem and exit with
status 2, never a traceback.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

from twsb_sim.config_errors import ConfigError
from twsb_sim.dataset.cli import add_dataset_commands
from twsb_sim.evaluation.cli import add_eval_parser
from twsb_sim.evaluation.envelope_cli import add_envelope_parser
from twsb_sim.filter_args import add_filter_args, filter_from_args, operating_threshold
from twsb_sim.rerun_log.recording import add_recording_args
from twsb_sim.scenario_files import resolve_scenario
from twsb_sim.slam.cli import add_slam_parser
from twsb_sim.tuning.cli import add_tune_parser

EXIT_USAGE = 2  # a user mistake: bad file, bad value
EXIT_FELL = 3  # the robot fell: the run ended early (its frames are still written)


def _add_run_parser(commands: argparse._SubParsersAction) -> None:
    run = commands.add_parser(
        "run",
        help="simulate a scenario with the filter in the loop",
        description="Simulate a scenario, run the Pitch Variation Filter on every scan, "
        "print a summary, and optionally write the frames.",
    )
    run.add_argument(
        "scenario", help="a scenario file, or the name of a shipped one (e.g. hard_stop)"
    )
    run.add_argument("--seed", type=int, default=None, help="run seed (default: the scenario's)")
    run.add_argument(
        "--out", type=Path, default=None, help="write frames.npz, summary.json, scenario.toml here"
    )
    add_filter_args(run, default="paper")
    run.add_argument("--quiet", action="store_true", help="no progress bar")
    add_recording_args(run)  # --rrd, --spawn and Rerun's own flags
    run.set_defaults(handler=_run)


def _run(args: argparse.Namespace) -> int:
    from twsb_sim.frame_writer import FrameWriter
    from twsb_sim.rerun_log.recording import rerun_sink, wait_while_serving
    from twsb_sim.runner import run_scenario
    from twsb_sim.scenario import load_scenario

    path = resolve_scenario(args.scenario)
    scenario = load_scenario(path)
    if args.seed is not None and args.seed < 0:
        raise ConfigError("--seed", "", f"expected an integer >= 0, got {args.seed}")
    sinks = []
    if args.out is not None:
        sinks.append(FrameWriter(args.out, scenario_file=path))
    scan_filter = filter_from_args(args, scenario)
    # a NullSink when no recording is asked for
    sinks.append(rerun_sink(args, p_th=operating_threshold(scan_filter)))
    summary = run_scenario(
        scenario, seed=args.seed, scan_filter=scan_filter, sinks=sinks, progress=not args.quiet
    )
    report = sys.stderr if args.stdout else sys.stdout  # --stdout carries the recording
    print(summary.format(), file=report)
    if args.out is not None:
        print(f"frames written to {args.out}/frames.npz", file=report)
    if args.rrd is not None:
        print(f"recording written to {args.rrd} (open it with: rerun {args.rrd})", file=report)
    if args.serve:
        wait_while_serving()
    return EXIT_FELL if summary.fell else 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="twsb",
        description="A two-wheeled self-balancing robot with a labeled 2D LiDAR, and the "
        "Pitch Variation Filter in the loop.",
    )
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    _add_run_parser(commands)
    add_eval_parser(commands)
    add_dataset_commands(commands)  # generate, export-bag
    add_slam_parser(commands)
    add_tune_parser(commands)
    add_envelope_parser(commands)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``twsb`` command."""
    args = build_parser().parse_args(argv)
    try:
        return args.handler(args)
    except ConfigError as error:
        print(f"twsb: error: {error}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("twsb: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
