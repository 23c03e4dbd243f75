"""The ``twsb`` command line.

``twsb run SCENARIO`` simulates a scenario with the filter in the loop, shows a progress
bar, prints a summary and (with ``--out``) writes the frames.

Exit status, the same for every command (``docs/robustness.md``): 0 done; 2 a user
mistake (a bad scenario file, a wrong flag value, an output path that cannot be written),
printed as one line naming the file or flag and the key, never a traceback; 3 the robot
fell (``twsb run``); 130 interrupted by Ctrl-C (SIGINT) or SIGTERM, after what was made
is kept or cleaned so that the same command can be run again; 141 the reader of the
output went away (``twsb run ... | head -1``).
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Sequence
from pathlib import Path

from twsb_sim.config_errors import ConfigError
from twsb_sim.output_paths import output_folder
from twsb_sim.scenario_files import resolve_scenario
from twsb_sim.stopping import Terminated, print_stop, stopping

EXIT_USAGE = 2  # a user mistake: bad file, bad value
EXIT_FELL = 3  # the robot fell: the run ended early (its frames are still written)
EXIT_INTERRUPTED = 130  # 128 + SIGINT, as a shell reports a Ctrl-C
EXIT_BROKEN_PIPE = 141  # 128 + SIGPIPE, as a shell reports `yes | head -1`


def _add_run_parser(commands: argparse._SubParsersAction) -> None:
    from twsb_sim.filter_args import add_filter_args
    from twsb_sim.rerun_log.recording import add_recording_args  # imports rerun: slow

    run = commands.add_parser(
        "run",
        help="simulate a scenario with the filter in the loop",
        description="Simulate a scenario, run a pitch-variation filter on every scan (the "
        "improved filter unless --filter names another), print a summary with the paper's "
        "filter on the same frames, and optionally write the frames and a Rerun recording.",
    )
    run.add_argument(
        "scenario", help="a scenario file, or the name of a shipped one (e.g. hard_stop)"
    )
    run.add_argument("--seed", type=int, default=None, help="run seed (default: the scenario's)")
    run.add_argument(
        "--out", type=Path, default=None, help="write frames.npz, summary.json, scenario.toml here"
    )
    add_filter_args(run, default="improved")
    run.add_argument("--quiet", action="store_true", help="no progress bar")
    add_recording_args(run)  # --rrd, --spawn and Rerun's own flags
    run.set_defaults(handler=_run)


def _run(args: argparse.Namespace) -> int:
    from twsb_sim.comparison import FilterComparison
    from twsb_sim.filter_args import (
        compared_filters,
        filter_from_args,
        operating_threshold,
        robot_geometry,
    )
    from twsb_sim.frame_writer import FrameWriter
    from twsb_sim.rerun_log.recording import rerun_sink, wait_while_serving
    from twsb_sim.runner import run_scenario
    from twsb_sim.scenario import load_scenario

    path = resolve_scenario(args.scenario)
    scenario = load_scenario(path)
    if args.seed is not None and args.seed < 0:
        raise ConfigError("--seed", "", f"expected an integer >= 0, got {args.seed}")
    if args.out is not None:
        output_folder(args.out)
    sinks = []
    if args.out is not None:
        sinks.append(FrameWriter(args.out, path, robot_geometry(scenario)))
    scan_filter = filter_from_args(args, scenario)
    compared = compared_filters(args, scenario, scan_filter)
    if compared:  # first, so its counts are in the summary the other sinks write
        sinks.insert(0, FilterComparison(compared))
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
    """The ``twsb`` parser with every command (imported here, once the signal handlers
    of :func:`main` are in place, so that a Ctrl-C during the imports is a clean stop)."""
    from twsb_sim.dataset.cli import add_dataset_commands
    from twsb_sim.evaluation.cli import add_eval_parser
    from twsb_sim.evaluation.envelope_cli import add_envelope_parser
    from twsb_sim.slam.cli import add_slam_parser
    from twsb_sim.slam.logs_cli import add_slam_logs_parser
    from twsb_sim.tuning.cli import add_tune_parser

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
    add_slam_logs_parser(commands)
    add_tune_parser(commands)
    add_envelope_parser(commands)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``twsb`` command: runs one command, returns its exit status."""
    try:
        with stopping():  # SIGTERM stops as Ctrl-C does; a stop is never lost
            args = build_parser().parse_args(argv)
            status = args.handler(args)
            sys.stdout.flush()  # a closed pipe shows here, not in Python's exit-time flush
        return status
    except ConfigError as error:
        print(f"twsb: error: {error}", file=sys.stderr)
        return EXIT_USAGE
    except (FileExistsError, IsADirectoryError, NotADirectoryError, PermissionError) as error:
        # a path the user gave that cannot be written (the checks before the work catch
        # most; these are the ones only the file system knows)
        print(f"twsb: error: {error.filename}: {error.strerror}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt as error:
        what = "terminated (SIGTERM)" if isinstance(error, Terminated) else "interrupted"
        print_stop(f"twsb: {what}")
        return EXIT_INTERRUPTED
    except BrokenPipeError:
        # the reader left (| head): say nothing more, and keep Python's exit-time flush
        # of stdout from failing again
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return EXIT_BROKEN_PIPE


if __name__ == "__main__":
    sys.exit(main())
