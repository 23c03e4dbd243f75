"""``pvfilter IN.npz OUT.npz``: run any registered filter over a scan file.

The scan file's layout is documented in :mod:`pvfilter.io`; ``pvfilter bag IN OUT``
filters a ROS bag instead (:mod:`pvfilter.bag.command`). ``--filter NAME`` picks the
filter (``--list`` shows them), ``--params FILE`` reads a parameter file, ``--set
NAME=VALUE`` and the paper's symbol flags set single parameters. Robot inputs the file
carries (``pitch_rad``, ``roll_rad``, ``pose_sensor_in_odom``) are passed to the filter,
and ground-truth ``labels`` give precision and recall. Exit status: 0 done, 2 a user
mistake (a bad option or file, one line naming it), 130 interrupted.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from pvfilter.cli_options import (
    add_filter_options,
    filter_notes,
    filter_options,
    robot_inputs,
    with_geometry,
)
from pvfilter.exits import run_command
from pvfilter.io import read_arrays, save_results, scans_from_arrays
from pvfilter.labelled import geometry_of, scan_labels, truth_of
from pvfilter.logs import NO_VALID_BEAM
from pvfilter.paper import ThreadedPitchVariationFilter
from pvfilter.registry import filter_entry, filter_names


def build_parser() -> argparse.ArgumentParser:
    """The command's arguments: files, the filter, its parameters, the modes."""
    parser = argparse.ArgumentParser(
        prog="pvfilter",
        description="Remove pitch-variation points (floor and ceiling hits) from the 2D LiDAR\n"
        "scans of an .npz scan file and write the filtered scans, masks and scores.",
        epilog="other commands (each has its --help):\n"
        "  pvfilter bag IN OUT          filter the scans of a ROS bag (rosbag2 or ROS 1)\n"
        "  pvfilter eval-logs FILE...   false alarms of filters on unlabelled real logs\n"
        "  pvfilter eval-labels FILE... PR-curve AUC of filters on labelled scan files",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("input", nargs="?", help="scan file (.npz: ranges, stamps, LaserScan)")
    parser.add_argument("output", nargs="?", help="the filtered scan file to write (.npz)")
    parser.add_argument("--list", action="store_true", help="list the registered filters and exit")
    add_filter_options(parser)
    parser.add_argument("--threaded", action="store_true", help="paper: the two-thread form")
    parser.add_argument(
        "--scans-only", action="store_true", help="ignore robot inputs the file carries"
    )
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command; returns the exit status. ``pvfilter eval-logs ...`` evaluates
    filters on real logs (:mod:`pvfilter.eval_logs`), ``pvfilter eval-labels ...`` on
    labelled scan files (:mod:`pvfilter.eval_labels`), ``pvfilter bag IN OUT`` filters a
    ROS bag (:mod:`pvfilter.bag.command`)."""
    argv = sys.argv[1:] if argv is None else list(argv)
    if argv[:1] == ["eval-logs"]:
        from pvfilter.eval_logs import main as eval_logs  # imports the command's own module

        return eval_logs(argv[1:])
    if argv[:1] == ["eval-labels"]:
        from pvfilter.eval_labels import main as eval_labels

        return eval_labels(argv[1:])
    if argv[:1] == ["bag"]:
        from pvfilter.bag.command import main as bag

        return bag(argv[1:])
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.list:
        for name in filter_names():
            print(f"{name:12s} {filter_entry(name).summary}")
        return 0
    if args.input is None or args.output is None:
        parser.error("the input and output files are required")
    return run_command(
        "pvfilter", lambda: _filter_file(args), "interrupted; the output was not written"
    )


def _filter_file(args: argparse.Namespace) -> int:
    options = filter_options(args)  # the options' own mistakes, before the input is read
    source, output = Path(args.input), Path(args.output)
    _check_output(source, output)
    arrays = read_arrays(source)
    scans = scans_from_arrays(arrays, source=str(source))
    stated = geometry_of(arrays, str(source))  # the robot that recorded the file
    entry, params = with_geometry(args, options, stated, str(source))
    # labels the score needs, checked before the work: a bad one ends the command first
    labels = None
    if "labels" in arrays:
        labels = scan_labels(arrays, str(source), len(scans))
    inputs = [{}] * len(scans) if args.scans_only else robot_inputs(arrays, len(scans), str(source))
    start = time.perf_counter()
    if args.threaded:
        with ThreadedPitchVariationFilter(params) as pvf:
            results = list(pvf.process_stream(scans))
    else:
        scan_filter = entry.make(params)
        results = [scan_filter.process(s, **i) for s, i in zip(scans, inputs, strict=True)]
    elapsed = time.perf_counter() - start
    output.parent.mkdir(parents=True, exist_ok=True)
    save_results(output, arrays, results)
    valid = sum(int(scan.valid_mask().sum()) for scan in scans)
    removed = sum(int(result.removed.sum()) for result in results)
    share = 100.0 * removed / valid if valid else 0.0
    rate = len(scans) / elapsed if elapsed > 0 else float("inf")
    used = sorted(inputs[0]) if inputs and inputs[0] else []
    print(
        f"pvfilter: {entry.name} filter, {len(scans)} scans"
        + (f" with {', '.join(used)}" if used else "")
        + f", removed {removed} of {valid} valid beams ({share:.2f} %), {rate:.0f} scans/s"
    )
    if scans and not valid:
        print(f"pvfilter: {source}: {NO_VALID_BEAM}")
    for note in filter_notes("pvfilter", args, params, stated):
        print(note)
    if labels is not None and scans:
        print(_label_score(labels, scans, results))
    print(f"pvfilter: wrote {output}")
    return 0


def _check_output(source: Path, output: Path) -> None:
    """Refuse, before any work, an output that would overwrite the input or cannot be written."""
    if output.exists() and source.exists() and output.resolve() == source.resolve():
        raise ValueError(f"{output}: is the input file; write the output to another file")
    if output.is_dir():
        raise ValueError(f"{output}: is a folder; give the output file's name")
    for parent in output.parents:
        if parent.exists():
            if not parent.is_dir():
                raise ValueError(f"{output}: {parent} is not a folder")
            break


def _label_score(labels: np.ndarray, scans: list, results: list) -> str:
    """Per-beam precision and recall against the file's ground-truth ``labels`` (in the
    scans' beam order), counted as ``pvfilter eval-labels`` counts them
    (:func:`pvfilter.labelled.truth_of`)."""
    truth = truth_of(labels, scans)
    removed = np.array([r.removed for r in results], dtype=bool).reshape(labels.shape)
    predicted = removed & truth.counted
    tp = int(np.count_nonzero(predicted & truth.positive))
    fp, fn = int(np.count_nonzero(predicted)) - tp, int(np.count_nonzero(truth.positive)) - tp
    precision = tp / (tp + fp) if tp + fp else float("nan")
    recall = tp / (tp + fn) if tp + fn else float("nan")
    return (
        f"pvfilter: against the file's labels: precision {precision:.3f}, recall {recall:.3f} "
        f"(TP {tp}, FP {fp}, FN {fn})"
    )


if __name__ == "__main__":
    sys.exit(main())
