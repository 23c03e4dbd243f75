"""``pvfilter eval-labels FILE_OR_DIR...``: PR-curve AUC of filters on labelled scan files.

Runs a filter (``--filter NAME``, ``--params FILE``, ``--set NAME=VALUE``; the improved
filter by default) and, beside it, the filters of ``--compare`` (the paper's by default)
over scan files whose beams carry ground-truth ``labels`` (:mod:`pvfilter.labelled`), from
the scans alone unless ``--inputs imu odometry`` gives them the robot inputs the files
hold. Per file and filter it prints the PR curve's AUC and the precision and recall at the
filter's operating point; then, per filter, the pooled AUC (every file's counts summed),
the mean and lowest AUC over the files and how many fall below ``--target``.
``--range-noise M`` adds Gaussian range noise first (a noisier scanner; only a body that
``--occluded-reads M`` puts in the blocked sector comes before it);
``--occluded-reads VALUE`` reads every OCCLUDED beam as ``inf``, ``-inf`` or ``nan`` (how
drivers report the sector the body blocks differs), or as a range in metres (the body
returns there: a mast or a frame a few decimetres from the sensor; before the noise, which
scatters it too); ``--dropout SHARE`` loses that share of the returns as no echo (a scanner
that misses dark or shiny surfaces); ``--no-echo-reads
VALUE`` writes every beam without an echo as ``0``, ``nan`` or ``range_max`` (how scanners
write no echo differs; the scores count returns only); ``--angle-jitter BEAMS`` moves each
scan's ``angle_min`` within half that many beams either way (drivers that take it from each
turn's first sample); ``--imu-nose-up`` negates the IMU's pitch (the other convention);
``--every N`` keeps every Nth scan first (a thinned log, a scanner that scans less often);
``--beam-stride N`` then every Nth beam (a scanner with a coarser spacing); ``--range-max M``
reads every return beyond M metres as no echo after the noise (a scanner that reaches
less far).
A folder stands for the ``.npz`` files in it; files without scans are skipped with a note.
``--out DIR`` writes ``report.json`` (every count of every curve) and ``report.md``;
``--per-scan`` adds ``per_scan/<file>.<filter>.csv`` there, the counts per scan at the
operating point (:class:`pvfilter.labelled.ScanCounts`).
Exit status: 0 done, 2 a user mistake (one line naming it), 130 interrupted.
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import json
import math
import re
from collections.abc import Sequence
from pathlib import Path

from pvfilter.eval_logs import (
    add_filter_arguments,
    chosen_entry,
    compared_label,
    log_files,
    output_folder,
    settings_of,
)
from pvfilter.exits import run_command
from pvfilter.labelled import INPUT_KEYS, LabelledReport, evaluate_labelled, pooled
from pvfilter.registry import filter_entry

DEFAULT_TARGET_AUC = 0.90  # the AUC every sequence should reach (the improved filter's goal)
PER_SCAN_FOLDER = "per_scan"  # --per-scan: the tables' folder in --out


def build_parser() -> argparse.ArgumentParser:
    """The command's arguments."""
    parser = argparse.ArgumentParser(
        prog="pvfilter eval-labels",
        description="Per-beam precision, recall and PR-curve AUC of filters on scan files "
        "whose beams carry ground-truth labels.",
    )
    parser.add_argument("paths", nargs="+", help="labelled scan files (.npz), or folders of them")
    add_filter_arguments(parser)
    parser.add_argument(
        "--inputs",
        nargs="*",
        default=[],
        choices=sorted(INPUT_KEYS),
        help="robot inputs to give the filters that take them (default: the scans alone)",
    )
    parser.add_argument(
        "--target",
        type=float,
        default=DEFAULT_TARGET_AUC,
        metavar="AUC",
        help=f"count the files below this AUC (default: {DEFAULT_TARGET_AUC})",
    )
    parser.add_argument(
        "--range-noise",
        type=float,
        default=0.0,
        metavar="M",
        help="add Gaussian noise of this standard deviation (m) to every finite range, the "
        "same draws every run: a noisier scanner than the files' (default: 0, none)",
    )
    parser.add_argument(
        "--occluded-reads",
        metavar="VALUE",
        help="read every OCCLUDED beam (the sector the robot's body blocks) as inf (no "
        "echo, as some drivers report it), -inf (closer than range_min, REP-117), nan, or "
        "a range in m (the body returns there, as a mast or a frame does; default: as the "
        "files have them)",
    )
    parser.add_argument(
        "--dropout",
        type=float,
        default=0.0,
        metavar="SHARE",
        help="lose this share (0-1) of the returns as no echo (+inf), the same draws every "
        "run: a scanner that misses dark or shiny surfaces (default: 0, none)",
    )
    parser.add_argument(
        "--no-echo-reads",
        choices=sorted(NO_ECHO_READS),
        metavar="VALUE",
        help="write every beam that returned nothing (+inf) as 0, nan or range_max, as "
        "scanners and simulators that do not follow REP-117 write it; applied last "
        "(default: inf, as the files have it)",
    )
    parser.add_argument(
        "--angle-jitter",
        type=float,
        default=0.0,
        metavar="BEAMS",
        help="move each scan's angle_min by a uniform draw within half this many beams "
        "either way, the same draws every run: drivers that take it from each turn's first "
        "sample (default: 0, none)",
    )
    parser.add_argument(
        "--imu-nose-up",
        action="store_true",
        help="negate the IMU's pitch (with --inputs imu): an IMU that gives it positive nose "
        "up, the other convention, wired in as it is",
    )
    parser.add_argument(
        "--every",
        type=int,
        default=1,
        metavar="N",
        help="keep every Nth scan, from the first, with its labels and robot inputs, "
        "before any other change: a log thinned out, or a scanner that scans N times less "
        "often (each scan's own sweep timing kept; the improved filter compares no scans "
        "farther apart than its max_gap_s) (default: 1, every scan)",
    )
    parser.add_argument(
        "--beam-stride",
        type=int,
        default=1,
        metavar="N",
        help="keep every Nth beam of each scan, from beam 0, with its labels, after --every: "
        "a scanner with an N times coarser spacing over the same sweep (on a full turn, "
        "an N that divides the beam count keeps the spacing across the seam) (default: 1, "
        "every beam)",
    )
    parser.add_argument(
        "--range-max",
        type=float,
        default=None,
        metavar="M",
        help="read every return beyond M metres as no echo, and M as range_max, after "
        "--range-noise: a scanner that reaches less far (default: the files' range_max)",
    )
    parser.add_argument(
        "--ignore-geometry",
        action="store_true",
        help="tell the filters none of the robot geometry the files state (lidar_height_m "
        "...): a user who did not set it, so the filters take their defaults",
    )
    parser.add_argument("--out", metavar="DIR", help="write report.json and report.md here")
    parser.add_argument(
        "--per-scan",
        action="store_true",
        help="also write, per file and filter, its counts per scan at the operating point "
        "(positives, hits, false alarms, STATIC removed, each positive label found) as "
        "DIR/per_scan/<file>.<filter>.csv, replacing an earlier run's: where in a sequence a "
        "filter fails (needs --out)",
    )
    return parser


OCCLUDED_READS = {"inf": math.inf, "-inf": -math.inf, "nan": math.nan}  # --occluded-reads
MAX_ANGLE_JITTER_BEAMS = 100.0  # --angle-jitter: beyond this it is no jitter but a turn
NO_ECHO_READS = {"0": 0.0, "nan": math.nan, "range_max": "range_max"}  # --no-echo-reads


def occluded_read(text: str | None) -> float | None:
    """What ``--occluded-reads`` asks every OCCLUDED beam to read, m: ``inf``, ``-inf``,
    ``nan``, or a range > 0 (the body returns there); None: as the files have it."""
    if text is None:
        return None
    if text in OCCLUDED_READS:
        return OCCLUDED_READS[text]
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not 0.0 < value < math.inf:  # (NaN: not a number)
        raise ValueError(
            f"--occluded-reads: inf, -inf, nan or a range > 0 m (the body returns there), "
            f"got {text!r}"
        )
    return value


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command; returns the exit status."""
    args = build_parser().parse_args(argv)
    return run_command("pvfilter eval-labels", lambda: _evaluate(args))


def _evaluate(args: argparse.Namespace) -> int:
    if not 0.0 <= args.target <= 1.0:
        raise ValueError(f"--target: an AUC is in [0, 1], got {args.target}")
    if not 0.0 <= args.range_noise < math.inf:
        raise ValueError(f"--range-noise: a standard deviation >= 0 m, got {args.range_noise}")
    occluded = occluded_read(args.occluded_reads)
    if not 0.0 <= args.dropout <= 1.0:
        raise ValueError(f"--dropout: a share in [0, 1], got {args.dropout}")
    if args.imu_nose_up and "imu" not in args.inputs:
        raise ValueError("--imu-nose-up: add --inputs imu (it negates the IMU's pitch)")
    if not 0.0 <= args.angle_jitter <= MAX_ANGLE_JITTER_BEAMS:
        raise ValueError(
            f"--angle-jitter: beams in [0, {MAX_ANGLE_JITTER_BEAMS:g}], got {args.angle_jitter}"
        )
    if args.every < 1:
        raise ValueError(f"--every: a number of scans >= 1, got {args.every}")
    if args.range_max is not None and not args.range_max > 0.0:
        raise ValueError(f"--range-max: a range > 0 m, got {args.range_max}")
    if args.beam_stride < 1:
        raise ValueError(f"--beam-stride: a number of beams >= 1, got {args.beam_stride}")
    if args.per_scan and args.out is None:
        raise ValueError("--per-scan: add --out DIR (the per-scan tables are written there)")
    entry, params, fields = chosen_entry(args)
    runs = {entry.name: (entry, params, fields)}
    settings = {entry.name: settings_of(args)}
    for name in args.compare:  # compared filters run with their defaults
        label = compared_label(name, runs, settings)
        if label is not None:
            runs[label] = (filter_entry(name), None, {})
    given = {key for name in args.inputs for key in INPUT_KEYS[name]}
    for label, (run_entry, _, _) in runs.items():
        missing = [key for key in run_entry.needs if key not in given]
        if missing:
            asked = [name for name, keys in INPUT_KEYS.items() if missing[0] in keys]
            raise ValueError(f"filter {label!r} needs {missing[0]}: add --inputs {' '.join(asked)}")
    out = output_folder(args.out)
    files = log_files(args.paths)
    names = _names(files)
    reports: dict[str, list[LabelledReport]] = {name: [] for name in runs}
    for path in files:
        for name, (run_entry, run_params, run_fields) in runs.items():
            report = evaluate_labelled(
                path,
                run_entry,
                run_params,
                run_fields,
                args.inputs,
                name=names[path],
                range_noise_m=args.range_noise,
                occluded_reads=occluded,
                dropout_share=args.dropout,
                no_echo_reads=NO_ECHO_READS.get(args.no_echo_reads),
                angle_jitter_beams=args.angle_jitter,
                imu_nose_up=args.imu_nose_up,
                every=args.every,
                beam_stride=args.beam_stride,
                range_max_m=args.range_max,
                ignore_geometry=args.ignore_geometry,
                counts_per_scan=args.per_scan,
            )
            if report is None:
                print(f"pvfilter eval-labels: {path}: no scans (skipped)")
                break
            report = dataclasses.replace(report, filter=name)
            reports[name].append(report)
            print(_line(report))
    if not any(reports.values()):
        raise ValueError("no scans in any of the files")
    summaries = {name: _summary(found, args.target) for name, found in reports.items() if found}
    for name, summary in summaries.items():
        print(
            f"{'all ' + str(summary['files']) + ' files':24s} {name:10s} pooled AUC "
            f"{summary['pooled_auc']:.3f}; per file mean {summary['mean_auc']:.3f}, lowest "
            f"{summary['lowest_auc']:.3f} ({summary['lowest_file']}), "
            f"{summary['below_target']} below {args.target:g}"
        )
    if out is not None:
        _write(out, args, reports, summaries, settings)
        if args.per_scan:
            _write_per_scan(out / PER_SCAN_FOLDER, reports)
    return 0


def _names(files: list[Path]) -> dict[Path, str]:
    """Each file's name in the reports: without extension, and all with their folder's
    where two files share a name (sequences of several sets, say)."""
    stems = [path.stem for path in files]
    if len(set(stems)) == len(stems):
        return {path: path.stem for path in files}
    return {path: f"{path.parent.name}/{path.stem}" for path in files}


def _line(report: LabelledReport) -> str:
    at = "" if math.isnan(report.operating_point) else f" at {report.operating_point:g}"
    return (
        f"{report.file:24s} {report.filter:10s} AUC {report.auc:.3f}; precision "
        f"{report.precision:.3f}, recall {report.recall:.3f}{at}; {report.positives} of "
        f"{report.beams} beams positive; {report.scans_per_s:.0f} scans/s"
    )


def _summary(reports: list[LabelledReport], target: float) -> dict:
    curve = pooled(reports)
    aucs = [r.auc for r in reports]
    lowest = min(range(len(aucs)), key=aucs.__getitem__)
    operating = reports[0].operating_point
    at = curve.at(operating) if not math.isnan(operating) else {}
    return {
        "files": len(reports),
        "pooled_auc": curve.auc,
        "pooled_precision": at.get("precision", float(curve.precision[0])),
        "pooled_recall": at.get("recall", float(curve.recall[0])),
        "mean_auc": sum(aucs) / len(aucs),
        "lowest_auc": aucs[lowest],
        "lowest_file": reports[lowest].file,
        "below_target": sum(a < target for a in aucs),
    }


def _write(out: Path, args, reports, summaries, settings) -> None:
    rows = [
        dict(
            _without_scans(r),
            auc=r.auc,
            precision=r.precision,
            recall=r.recall,
            settings=settings.get(r.filter, "defaults"),
        )
        for found in reports.values()
        for r in found
    ]
    document = {
        "inputs": args.inputs,
        "range_noise_m": args.range_noise,
        "occluded_reads": args.occluded_reads,
        "dropout_share": args.dropout,
        "no_echo_reads": args.no_echo_reads,
        "angle_jitter_beams": args.angle_jitter,
        "imu_nose_up": args.imu_nose_up,
        "every": args.every,
        "beam_stride": args.beam_stride,
        "range_max_m": args.range_max,
        "ignore_geometry": args.ignore_geometry,
        "target_auc": args.target,
        "summary": summaries,
    }
    as_json = json.dumps(_no_nan({**document, "files": rows}), indent=1, allow_nan=False)
    (out / "report.json").write_text(as_json + "\n")
    changes = _scanner_changes(args)
    as_markdown = markdown(reports, summaries, args.inputs, args.target, settings, changes)
    (out / "report.md").write_text(as_markdown)
    print(f"pvfilter eval-labels: wrote {out / 'report.json'} and {out / 'report.md'}")


def _without_scans(report: LabelledReport) -> dict:
    """The report's fields but its per-scan counts (the tables hold them), as a dict."""
    fields = dataclasses.asdict(dataclasses.replace(report, per_scan=None))
    del fields["per_scan"]
    return fields


def _write_per_scan(folder: Path, reports: dict[str, list[LabelledReport]]) -> None:
    """One CSV per file and filter: its :class:`~pvfilter.labelled.ScanCounts` rows. The
    folder holds this run's tables only (those of an earlier run are replaced), each
    named once (two files named alike get ``-2``, ``-3``, ...)."""
    folder.mkdir(exist_ok=True)
    for old in folder.glob("*.csv"):
        old.unlink()
    names: set[str] = set()
    for found in reports.values():
        for report in found:
            stem = f"{_file_name(report.file)}.{_file_name(report.filter)}"
            name, k = stem, 1
            while name in names:
                k += 1
                name = f"{stem}-{k}"
            names.add(name)
            rows = report.per_scan.rows()
            with (folder / f"{name}.csv").open("w", newline="") as table:
                writer = csv.DictWriter(table, fieldnames=list(rows[0]))
                writer.writeheader()
                writer.writerows(rows)
    tables = "table" if len(names) == 1 else "tables"
    print(f"pvfilter eval-labels: wrote {len(names)} per-scan {tables} in {folder}")


def _file_name(text: str) -> str:
    """``text`` as part of a file name: runs of anything but letters, digits, ``-``, ``_``
    and ``.`` become one ``_``, none at either end (a file's folder/name, a filter's label
    with spaces: ``improved (defaults)`` is ``improved_defaults``)."""
    return re.sub(r"[^\w.-]+", "_", text).strip("_")


def _no_nan(value):
    """``value`` with every NaN as None: strict JSON has no NaN (a label the file lacks)."""
    if isinstance(value, dict):
        return {key: _no_nan(item) for key, item in value.items()}
    if isinstance(value, list | tuple):
        return [_no_nan(item) for item in value]
    if isinstance(value, float) and math.isnan(value):
        return None
    return value


def _scanner_changes(args: argparse.Namespace) -> str:
    """What the scans were changed by before the filters ran, as sentences ("" for none)."""
    changes = ""
    if args.every > 1:  # first: the other changes are drawn on the scans kept
        changes += f" Every {_ordinal(args.every)} scan kept, from the first."
    if args.beam_stride > 1:
        changes += f" Every {_ordinal(args.beam_stride)} beam kept, from beam 0."
    if args.range_noise > 0.0:
        changes += (
            f" Range noise added: {args.range_noise * 100:g} cm (Gaussian, the same draws "
            "every run)."
        )
    if args.range_max is not None:
        reach = f"{args.range_max:g} m"
        changes += f" Returns beyond {reach} read no echo (range_max {reach})."
    if args.occluded_reads is not None:
        unit = "" if args.occluded_reads in OCCLUDED_READS else " m (the body)"
        changes += f" Every OCCLUDED beam reads {args.occluded_reads}{unit}."
    if args.dropout > 0.0:
        changes += f" Returns lost as no echo: {args.dropout * 100:g} % (the same draws every run)."
    if args.no_echo_reads is not None:
        changes += f" Every beam without an echo reads {args.no_echo_reads}."
    if args.imu_nose_up:
        changes += " The IMU's pitch is negated (positive nose up)."
    if args.ignore_geometry:
        changes += " The robot geometry the files state is not told to the filters."
    if args.angle_jitter > 0.0:
        changes += (
            f" Each scan's angle_min moved within {args.angle_jitter / 2:g} beam either way "
            "(the same draws every run)."
        )
    return changes


def _ordinal(n: int) -> str:
    """``2nd``, ``3rd``, ``4th``, ``11th``, ``21st``."""
    if 10 <= n % 100 <= 20:
        return f"{n}th"
    return f"{n}{ {1: 'st', 2: 'nd', 3: 'rd'}.get(n % 10, 'th') }"


def markdown(reports, summaries, inputs, target, settings, changes="") -> str:
    """The reports as Markdown: one row per file and filter, then one per filter;
    ``changes``: what the scans were changed by first (:func:`_scanner_changes`)."""
    given = ", ".join(inputs) if inputs else "none (the scans alone)"
    ran = "; ".join(f"{name}: {settings.get(name, 'defaults')}" for name in reports)
    lines = [
        "# Filters on labelled scans",
        "",
        f"Robot inputs: {given}. Parameters: {ran}.{changes} The returns count (ranges in "
        "[range_min, range_max)), DYNAMIC and OCCLUDED beams excepted; positives are FLOOR, "
        "CEILING and HORIZONTAL beams.",
        "",
        "| file | filter | AUC | precision | recall | operating point | positives | beams | "
        "FLOOR / CEILING / HORIZONTAL found | STATIC removed | geometry from the file (m) | "
        "scans/s |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for found in reports.values():
        for r in found:
            by_label = " / ".join(
                "–" if math.isnan(v) else f"{v:.2f}" for v in r.recall_by_label.values()
            )
            static = r.static_removed / r.static_beams if r.static_beams else 0.0
            lines.append(
                f"| {r.file} | {r.filter} | {r.auc:.3f} | {r.precision:.3f} | {r.recall:.3f} | "
                f"{r.operating_point:g} | {r.positives} | {r.beams} | {by_label} | "
                f"{static:.2%} | {_geometry(r.geometry)} | {r.scans_per_s:.0f} |"
            )
    lines += [
        "",
        f"| filter | files | pooled AUC | pooled precision / recall | mean AUC | lowest AUC | "
        f"files below {target:g} |",
        "|---|---|---|---|---|---|---|",
    ]
    for name, s in summaries.items():
        lines.append(
            f"| {name} | {s['files']} | {s['pooled_auc']:.3f} | {s['pooled_precision']:.3f} / "
            f"{s['pooled_recall']:.3f} | {s['mean_auc']:.3f} | {s['lowest_auc']:.3f} "
            f"({s['lowest_file']}) | {s['below_target']} |"
        )
    return "\n".join(lines) + "\n"


def _geometry(geometry: dict[str, float]) -> str:
    """The geometry a filter was told, as a table cell (– : none)."""
    return ", ".join(f"{key} {value:.3f}" for key, value in geometry.items()) or "–"
