"""``pvfilter eval-logs FILE_OR_DIR...``: false alarms of filters on real logs.

Runs a filter (``--filter NAME``, ``--params FILE``, ``--set NAME=VALUE``; the improved
filter by default) and, beside it, the filters of ``--compare`` (the paper's by default)
over scan files of robots that never pitch into the floor, and reports per log the share
of valid beams removed and the worst scan (:mod:`pvfilter.logs`). A folder stands for
the ``.npz`` files in it; files without scans are skipped with a note. ``--odometry``
gives the filters the logs' wheel odometry. ``--out DIR`` writes ``report.json`` and
``report.md``, which say the parameter options each filter ran with. Exit status: 0
done, 2 a user mistake (one line naming it), 130 interrupted.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from pvfilter.cli_options import setting
from pvfilter.contract import ScanFilter
from pvfilter.exits import run_command
from pvfilter.logs import NO_VALID_BEAM, LogReport, evaluate_log, markdown
from pvfilter.params_file import load_params
from pvfilter.registry import FilterEntry, entry_for_params, filter_entry

DEFAULT_FILTER = "improved"


def build_parser() -> argparse.ArgumentParser:
    """The command's arguments."""
    parser = argparse.ArgumentParser(
        prog="pvfilter eval-logs",
        description="False alarms of filters on real logs that never pitch into the floor: "
        "every beam removed is a false alarm.",
    )
    parser.add_argument("paths", nargs="+", help="scan files (.npz), or folders of them")
    add_filter_arguments(parser)
    parser.add_argument("--odometry", action="store_true", help="give the logs' odometry")
    parser.add_argument("--out", metavar="DIR", help="write report.json and report.md here")
    return parser


def add_filter_arguments(parser: argparse.ArgumentParser) -> None:
    """The filter to evaluate (``--filter``, ``--params``, ``--set``) and those compared
    with it (``--compare``), as the evaluation commands take them."""
    parser.add_argument(
        "--filter",
        metavar="NAME",
        default=DEFAULT_FILTER,
        help="the filter to evaluate (default: improved; 'pvfilter --list' names them all)",
    )
    parser.add_argument("--params", metavar="FILE", help="a parameter file (names its filter)")
    parser.add_argument(
        "--set", action="append", metavar="NAME=VALUE", help="set one parameter (repeatable)"
    )
    parser.add_argument(
        "--compare",
        nargs="*",
        default=["paper"],
        metavar="NAME",
        help="filters run beside it with their defaults (default: paper; '--compare' alone: none)",
    )


def log_files(paths: Sequence[str]) -> list[Path]:
    """The scan files the arguments name (a folder: its ``.npz`` files, sorted).

    Raises:
        ValueError: a path that does not exist, or a folder without ``.npz`` files.
    """
    files = []
    for text in paths:
        path = Path(text)
        if path.is_dir():
            found = sorted(path.glob("*.npz"))
            if not found:
                raise ValueError(f"{path}: no .npz scan files in this folder")
            files.extend(found)
        elif path.is_file():
            files.append(path)
        else:
            raise ValueError(f"{path}: no such file or folder")
    return files


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command; returns the exit status."""
    args = build_parser().parse_args(argv)
    return run_command("pvfilter eval-logs", lambda: _evaluate(args))


def chosen_entry(args: argparse.Namespace) -> tuple[FilterEntry, Any, dict[str, Any]]:
    """The filter the options name, its parameters and the values that replace theirs:
    ``--params`` (the file names its filter) or ``--filter``, with ``--set NAME=VALUE``
    values (read as TOML).

    Raises:
        ValueError: a parameter file of another filter, or a bad ``--set``.
    """
    try:
        params = load_params(args.params) if args.params else None
    except OSError as error:  # (a missing file, a folder: its errno text alone names neither)
        raise ValueError(f"--params {args.params}: {error.strerror or error}") from None
    entry = entry_for_params(params) if params is not None else filter_entry(args.filter)
    if params is not None and args.filter not in (entry.name, DEFAULT_FILTER):
        raise ValueError(f"{args.params}: holds parameters of {entry.name!r}, not {args.filter!r}")
    fields = dict(setting(text) for text in args.set or ())
    entry.make(params, **fields)  # checks the fields now, before any file is read
    return entry, params, fields


def chosen(args: argparse.Namespace) -> tuple[str, Callable[[], ScanFilter]]:
    """The filter the options name and how to build it (:func:`chosen_entry`)."""
    entry, params, fields = chosen_entry(args)
    return entry.name, lambda: entry.make(params, **fields)


def settings_of(args: argparse.Namespace) -> str:
    """The options that set the chosen filter's parameters, as given (``defaults``: none):
    a report that does not say them cannot be told from one of the defaults."""
    options = ([f"--params {args.params}"] if args.params else []) + [
        f"--set {text}" for text in args.set or ()
    ]
    return " ".join(options) or "defaults"


def output_folder(text: str | None) -> Path | None:
    """The ``--out`` folder, made now: a path it cannot be is reported before the work."""
    if text is None:
        return None
    out = Path(text)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise ValueError(f"--out {text}: cannot be a folder ({error.strerror or error})") from None
    return out


def compared_label(name: str, runs: dict, settings: dict[str, str]) -> str | None:
    """The label of ``--compare NAME`` beside the ``runs`` so far (``settings``: the chosen
    filter's options, by its name): its name, or ``"NAME (defaults)"`` where the chosen
    filter is that filter with other parameters; None where it would run the same filter
    with the same parameters twice."""
    if name in runs and name not in settings:  # (a compared filter named twice)
        return None
    label = name if name not in runs else f"{name} (defaults)"
    if settings.get(name) == "defaults" or label in runs:
        return None
    return label


def _evaluate(args: argparse.Namespace) -> int:
    name, make = chosen(args)
    makers = {name: make}
    settings = {name: settings_of(args)}
    for name in args.compare:  # compared filters run with their defaults
        label = compared_label(name, makers, settings)
        if label is not None:
            makers[label] = filter_entry(name).make
    out = output_folder(args.out)
    files = log_files(args.paths)
    reports: list[LogReport] = []
    width = max(10, *map(len, makers))  # (the filters' names line up)
    for path in files:
        for name, make in makers.items():
            report = evaluate_log(path, name, make, args.odometry)
            if report is None:
                print(f"pvfilter eval-logs: {path}: no scans (skipped)")
                break
            if name == next(iter(makers)):  # (notes once per log)
                _note_on(path, report, args.odometry)
            reports.append(report)
            worst = (
                f"worst scan {report.worst_scan} {report.worst_scan_share:.2%}"
                if report.worst_scan >= 0
                else "no scan lost a beam"
            )
            print(
                f"{report.log:24s} {name:{width}s} removed {report.removed_share:8.4%} of "
                f"{report.valid_beams} valid beams; {worst}; {report.scans_over_limit} scans "
                f"over 5 %"
            )
    if out is not None:
        rows = [
            dict(
                dataclasses.asdict(r),
                removed_share=r.removed_share,
                settings=settings.get(r.filter, "defaults"),
            )
            for r in reports
        ]
        (out / "report.json").write_text(json.dumps(rows, indent=1) + "\n")
        ran = "; ".join(f"{name}: {settings.get(name, 'defaults')}" for name in makers)
        (out / "report.md").write_text(
            "# False alarms on real logs\n\nEvery removed beam is a false alarm: none of these "
            f"logs pitches into the floor.\n\nParameters: {ran}.\n\n" + markdown(reports)
        )
        print(f"pvfilter eval-logs: wrote {out / 'report.json'} and {out / 'report.md'}")
    return 0


def _note_on(path: Path, report: LogReport, odometry: bool) -> None:
    """A note where a log's report would mislead as it stands: ``--odometry`` given for a
    log without odometry, or no valid beam at all (:data:`pvfilter.logs.NO_VALID_BEAM`)."""
    if odometry and not report.odometry:
        print(f"pvfilter eval-logs: {path}: the log has no odometry (run without it)")
    if report.valid_beams == 0:
        print(f"pvfilter eval-logs: {path}: {NO_VALID_BEAM}")
