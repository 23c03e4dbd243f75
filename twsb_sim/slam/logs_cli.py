"""``twsb slam-logs``: SLAM on recorded scan files with and without the filters.

What a filter's removals cost a SLAM front end on logs the simulator did not make (see
:mod:`scaneval.slam.logs`); writes ``report.md`` and ``results.json``.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import sys
from pathlib import Path

from pvfilter.eval_logs import log_files
from pvfilter.registry import filter_entry
from twsb_sim.config_errors import ConfigError
from twsb_sim.output_paths import output_folder
from twsb_sim.staging import staged_folder

SYSTEMS = ("hector", "kiss_icp")


def add_slam_logs_parser(commands: argparse._SubParsersAction) -> None:
    """Register ``twsb slam-logs`` on the ``twsb`` command line."""
    parser = commands.add_parser(
        "slam-logs",
        help="SLAM on recorded scan files with and without the filters",
        description="Run the Hector-style SLAM and KISS-ICP over scan files (.npz, as the "
        "pvfilter command reads them) with no filter and with each filter; score each "
        "trajectory against the file's reference poses (or its odometry) and against the "
        "run without a filter; write report.md and results.json.",
    )
    parser.add_argument("paths", nargs="+", help="scan files (.npz), or folders of them")
    parser.add_argument("--out", type=Path, required=True, help="output folder")
    parser.add_argument(
        "--filters", nargs="+", default=["improved", "paper"], metavar="NAME",
        help="registered filters to compare with no filter (default: improved paper)",
    )  # fmt: skip
    parser.add_argument(
        "--systems", nargs="+", default=list(SYSTEMS), choices=SYSTEMS, metavar="SYSTEM",
        help="SLAM systems: hector, kiss_icp (default: both; kiss_icp needs KISS-ICP)",
    )  # fmt: skip
    parser.add_argument("--quiet", action="store_true", help="no line per log")
    parser.set_defaults(handler=_run)


def _run(args: argparse.Namespace) -> int:
    from scaneval.slam.logs import markdown, slam_on_log
    from twsb_sim.slam.systems import available_systems

    output_folder(args.out)
    try:
        files = log_files(args.paths)
        entries = {name: filter_entry(name) for name in args.filters}
    except ValueError as error:
        raise ConfigError("twsb slam-logs", "", str(error)) from None
    for name, entry in entries.items():
        if entry.needs:
            raise ConfigError("--filters", "", f"{name} needs {', '.join(entry.needs)}, which "
                              "scan files do not give it")  # fmt: skip
    systems = [s for s in args.systems if s in available_systems()]
    if len(systems) < len(args.systems):
        print('twsb slam-logs: KISS-ICP is not installed (pip install "twsb-pvfilter[slam]"): '
              "running the Hector-style SLAM only", file=sys.stderr)  # fmt: skip
    builders = {name: (lambda e=e: e.make(None)) for name, e in entries.items()}
    runs = []
    for path in files:
        try:
            found = slam_on_log(path, builders, systems)
        except ValueError as error:
            raise ConfigError(str(path), "", str(error)) from None
        if found and not args.quiet:
            print(f"twsb slam-logs: {path.name}: {len(found)} runs", file=sys.stderr)
        runs.extend(found)
    command = "twsb " + " ".join(sys.argv[1:]) if sys.argv[1:2] == ["slam-logs"] else ""
    report = f"# SLAM on recorded logs, with and without the filters\n\n`{command}`\n\n"
    report += markdown(runs)
    rows = [{k: _json_value(v) for k, v in dataclasses.asdict(r).items()} for r in runs]
    with staged_folder(args.out) as staging:  # the outputs appear whole or not at all
        (staging / "report.md").write_text(report)
        text = json.dumps({"command": command, "runs": rows}, indent=2, allow_nan=False)
        (staging / "results.json").write_text(text + "\n")
    failed = sum(r.failed for r in runs)
    logs = len({r.log for r in runs})  # files of relations only hold no scans
    print(f"{len(runs)} SLAM runs on {logs} logs, {failed} tracking failures; "
          f"report: {args.out / 'report.md'}, results: {args.out / 'results.json'}")  # fmt: skip
    return 0


def _json_value(value: object) -> object:
    """Strict JSON: NaN is null, numpy scalars are Python numbers."""
    if isinstance(value, float | int) and not isinstance(value, bool):
        number = float(value)
        return None if math.isnan(number) else (int(value) if isinstance(value, int) else number)
    return value
