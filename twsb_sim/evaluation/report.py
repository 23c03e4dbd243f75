"""The report folder: ``report.md``, ``results.json``, the plots and the example frames.

``report.md`` puts our numbers next to the paper's (its "Reference numbers from
the paper"); ``results.json`` holds every figure behind it (strict JSON: NaN is null).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

from pvfilter import FilterParams
from twsb_sim.evaluation import plots
from twsb_sim.evaluation.diagnosis import MISS_STAGES
from twsb_sim.evaluation.experiment import Evaluation
from twsb_sim.evaluation.families import LABELS
from twsb_sim.evaluation.frame_pictures import render_snapshot
from twsb_sim.evaluation.improved_report import plot_improved, render_improved_section
from twsb_sim.evaluation.markdown import fmt, table
from twsb_sim.evaluation.scan_matching import CONDITIONS

PAPER = {  # the reference numbers the paper reports
    "pvf_auc_min": 0.92,
    "datmo_auc": 0.24,
    "pvf_rate_hz": 126.87,  # on the robot's Qualcomm RB5
    "datmo_rate_hz": 67.55,
    "chamfer_reduction_pct": {"icp": 24.31, "ndt": 37.10, "hsm": 54.69},
}
IMPROVED_PLOT = "improved_pr_curves.png"  # written when the improved filter was evaluated
REPORT_FILES = (
    "report.md",
    "results.json",
    "pr_curves.png",
    "timing.png",
    "chamfer.png",
    "pose_errors.png",
)


def write_outputs(results: dict, evaluation: Evaluation, out_dir: Path, command: str) -> None:
    """Write every report file into ``out_dir`` (created if needed)."""
    out_dir.mkdir(parents=True, exist_ok=True)
    results = {**results, "paper": PAPER, "command": command}
    plots.plot_pr_curves(results, out_dir / "pr_curves.png")
    plots.plot_timing(results, out_dir / "timing.png")
    plots.plot_chamfer(results, out_dir / "chamfer.png")
    plots.plot_pose_errors(results, out_dir / "pose_errors.png")
    if "improved" in results:
        plot_improved(results, out_dir / IMPROVED_PLOT)
    results["examples"] = _write_examples(evaluation, out_dir)
    (out_dir / "results.json").write_text(json.dumps(_strict(results), indent=1) + "\n")
    (out_dir / "report.md").write_text(render_report(results))


def _write_examples(evaluation: Evaluation, out_dir: Path) -> dict[str, list[str]]:
    """Picture the frames that show the most common misses and false alarms best."""
    written = {}
    for seq, diagnosis in evaluation.diagnoses.items():
        top = [key for key, _ in diagnosis.misses.most_common(evaluation.config.example_frames)]
        names = []
        for key in [*top, "false_alarm"]:
            if key in diagnosis.examples:
                name = f"example_{seq}_{key}.png"
                render_snapshot(diagnosis.examples[key][1], out_dir / name)
                names.append(name)
        written[seq] = names
    return written


def _strict(value: object) -> object:
    """NaN and infinities become null, so the file is strict JSON."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {str(k): _strict(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_strict(v) for v in value]
    return value


def render_report(results: dict) -> str:
    """The text of ``report.md``."""
    sections = [
        _overview(results),
        _headline(results),
        _pr_section(results),
        _timing_section(results),
        _matching_section(results),
        _diagnosis_section(results),
        render_improved_section(results),
    ]
    return "\n\n".join(s for s in sections if s) + "\n"


def _overview(results: dict) -> str:
    config, runs = results["config"], results["runs"]
    falls = sum(r["fell"] for r in runs)
    frames = sum(r["frames"] for r in runs)
    cut = f", cut to {config['duration_s']:g} s" if config["duration_s"] else ""
    return (
        "# Evaluation: the paper's experiments in simulation\n\n"
        f"`{results['command']}`\n\n"
        f"{len(runs)} runs: sequences {', '.join(config['sequences'])}{cut}; houses "
        f"{', '.join(config['houses'])}; seeds {', '.join(map(str, config['seeds']))}. "
        f"{frames} frames, {falls} falls, {results['wall_s']:.0f} s wall time. Each run is "
        "simulated once; every method and threshold replays the same frames. Per-beam counts "
        "run over beams with a finite range; PR curves and AUC pool the counts of all runs of "
        "a sequence (per-run AUCs: min / mean / max)."
    )


def _headline(results: dict) -> str:
    pr, timing, paper = results["pr"], results["timing"], results["paper"]
    matching = results["scan_matching"]["all"]["onset"]
    rows = []
    for seq, curves in pr.items():
        rows.append([f"PVF AUC, {seq}", f"≥ {paper['pvf_auc_min']}", fmt(curves["pvf"]["auc"])])
    for seq, curves in pr.items():
        if "datmo" in curves:
            rows.append(
                [
                    f"DATMO-like AUC (speed sweep), {seq}",
                    f"{paper['datmo_auc']}",
                    fmt(curves["datmo"]["auc"]),
                ]
            )
    methods = timing["methods"]
    if LABELS["datmo"] in methods:
        rows += [
            [
                "PVF rate (Hz)",
                f"{paper['pvf_rate_hz']} (RB5)",
                f"{methods[LABELS['pvf']]['rate_hz']:.0f} (this machine)",
            ],
            [
                "DATMO-like rate (Hz)",
                f"{paper['datmo_rate_hz']} (RB5)",
                f"{methods[LABELS['datmo']]['rate_hz']:.0f} (this machine)",
            ],
            [
                "PVF / DATMO rate",
                f"{paper['pvf_rate_hz'] / paper['datmo_rate_hz']:.2f}x",
                f"{timing['pvf_over_datmo_rate']:.2f}x",
            ],
        ]
    for name, values in matching.items():
        rows.append(
            [
                f"Chamfer-distance reduction, {name.upper()}",
                f"{paper['chamfer_reduction_pct'].get(name, float('nan')):.2f} %",
                f"{values['chamfer_reduction_pct']:.2f} %",
            ]
        )
    return "## Our numbers next to the paper's\n\n" + table(["what", "paper", "ours"], rows)


def _pr_section(results: dict) -> str:
    parts = ["## Precision-recall curves and AUC (paper Fig. 4)", "![PR curves](pr_curves.png)"]
    for seq, curves in results["pr"].items():
        rows = []
        for c in curves.values():
            best = max(
                range(len(c["thresholds"])),
                key=lambda i, c=c: _f1(c["precision"][i], c["recall"][i]),
            )
            runs = c["auc_runs"]
            rows.append(
                [
                    c["label"],
                    fmt(c["auc"]),
                    f"{fmt(runs['min'])} / {fmt(runs['mean'])} / {fmt(runs['max'])}",
                    f"{_f1(c['precision'][best], c['recall'][best]):.3f} at {c['swept']} "
                    f"{c['thresholds'][best]:g} (P {fmt(c['precision'][best])}, "
                    f"R {fmt(c['recall'][best])})",
                ]
            )
        parts.append(
            f"### {seq}\n\n"
            + table(["method", "AUC (pooled)", "AUC per run (min / mean / max)", "best F1"], rows)
        )
        parts.append(_sweep_table(curves))
    return "\n\n".join(parts)


def _f1(precision: float, recall: float) -> float:
    return 2 * precision * recall / (precision + recall) if precision + recall > 0 else 0.0


def _sweep_table(curves: dict) -> str:
    """Every swept point of every method: value, precision, recall, TP, FP, FN."""
    rows = []
    for c in curves.values():
        for i, value in enumerate(c["thresholds"]):
            rows.append(
                [
                    c["label"],
                    f"{c['swept']} = {value:g}",
                    fmt(c["precision"][i]),
                    fmt(c["recall"][i]),
                    str(c["tp"][i]),
                    str(c["fp"][i]),
                    str(c["fn"][i]),
                ]
            )
    header = ["method", "value", "precision", "recall", "TP", "FP", "FN"]
    return (
        "<details><summary>every swept point</summary>\n\n"
        + table(header, rows)
        + ("\n\n</details>")
    )


def _timing_section(results: dict) -> str:
    timing = results["timing"]
    rows = [
        [
            name,
            f"{timing['operating_points'][name]:g}",
            str(t["frames"]),
            fmt(t["mean_ms"]),
            fmt(t["median_ms"]),
            fmt(t["p95_ms"]),
            f"{t['rate_hz']:.0f}",
        ]
        for name, t in timing["methods"].items()
    ]
    header = ["method", "operating point", "frames", "mean ms", "median ms", "p95 ms", "rate Hz"]
    return (
        "## Throughput (paper Fig. 5)\n\n"
        "Every method at its operating point, called in turn on each frame of every run "
        "(one core, the same moment's machine load for all). The DATMO-like time includes "
        "its transform into the world frame, which the paper's figure excludes.\n\n"
        + table(header, rows)
        + f"\n\nPVF / DATMO-like rate: {fmt(timing['pvf_over_datmo_rate'], 2)}x (paper 1.88x).\n\n"
        "![per-frame time](timing.png)"
    )


def _matching_section(results: dict) -> str:
    matching, paper = results["scan_matching"], results["paper"]["chamfer_reduction_pct"]
    parts = [
        "## Scan matching (paper section IV-D, Fig. 6)",
        "Source: the frame where a pitch variation occurs (ground truth: the first frame of "
        "a run of frames with pitch-variation beams, `onset`), or that run's frame with the "
        "most such beams (`peak`); target: the frame before the run. Matchers start at the "
        "identity. Conditions: raw scans, scans filtered by the PVF at Table I (run over "
        "the whole sequence), and an oracle that drops every pitch-variation beam by its "
        "label. Chamfer distance (eq. 6, m²) after alignment; pose error of the alignment "
        "against the true relative sensor pose.",
        "![normalized Chamfer distance](chamfer.png)",
        "![pose errors](pose_errors.png)",
    ]
    for kind in ("onset", "peak"):
        rows = []
        for name, m in matching["all"][kind].items():
            rows.append(
                [
                    name.upper(),
                    *(fmt(m[c]["mean_chamfer_m2"]) for c in CONDITIONS),
                    f"{fmt(m['chamfer_reduction_pct'], 1)} % ({fmt(paper.get(name), 1)} %)",
                    f"{fmt(m['oracle_chamfer_reduction_pct'], 1)} %",
                    " / ".join(fmt(100 * m[c]["mean_translation_error_m"], 2) for c in CONDITIONS),
                    " / ".join(fmt(m[c]["mean_rotation_error_deg"], 3) for c in CONDITIONS),
                ]
            )
        header = [
            "matcher",
            "CD without",
            "CD with PVF",
            "CD oracle",
            "reduction (paper)",
            "oracle reduction",
            "translation error cm (without / with / oracle)",
            "rotation error deg (without / with / oracle)",
        ]
        per_seq = "; ".join(
            f"{seq}: {v['events']} events, reductions " + _reductions(v[kind])
            for seq, v in matching.items()
            if seq != "all"
        )
        parts.append(
            f"### {kind} ({matching['all']['events']} events)\n\n{table(header, rows)}\n\n"
            f"Per sequence: {per_seq}."
        )
    return "\n\n".join(parts)


def _detection_bound() -> str:
    """What Table I asks of P(L) for a cluster straight ahead or behind to be detected."""
    params = FilterParams()
    least_p_theta = math.exp(-1.0 / (2.0 * params.sigma_theta**2))  # cos^2 = 1
    most_p_l = (1.0 - params.p_th) / least_p_theta
    # the mean point likelihood exp(-d^2 / 2 sigma_l^2) falls below it at this distance
    distance = params.sigma_l * math.sqrt(-2.0 * math.log(most_p_l))
    return (
        f"With Table I, P(θ) is at least exp(-1 / 2σ_θ²) = {least_p_theta:.2f} (straight "
        f"ahead or behind), so P(C_pv) > P_th = {params.p_th:g} needs P(L) < "
        f"{most_p_l:.2f}: were its points all at one distance from the previous scan, "
        f"that distance would have to exceed {distance:.1f} m (σ_l = {params.sigma_l:g} m)."
    )


def _reductions(per_matcher: dict) -> str:
    return ", ".join(
        f"{name.upper()} {fmt(m['chamfer_reduction_pct'], 1)} %" for name, m in per_matcher.items()
    )


def _diagnosis_section(results: dict) -> str:
    parts = [
        "## Why it misses (the filter at Table I)",
        "For every missed pitch-variation beam, the first pipeline stage that lost it; for "
        "every false alarm, what it hit (from the hit geom), whether that surface was seen "
        "for the first time (no hit of the previous frame within 0.3 m), and whether "
        "detection or tracking removed it. P(θ), P(L) and P(C_pv) of the clusters that "
        "pass the v_C gate show what separates pitch variation from structure.",
        _detection_bound(),
    ]
    for seq, d in results["diagnosis"].items():
        total = sum(d["misses"].values())
        rows = [
            [MISS_STAGES[key], str(beams), f"{100 * beams / total:.1f} %"]
            for key, beams in sorted(d["misses"].items(), key=lambda kv: -kv[1])
        ]
        fa_total = sum(r["beams"] for r in d["false_alarms"])
        fa_rows = [
            [
                r["hit"],
                r["seen"],
                r["removed_by"],
                str(r["beams"]),
                f"{100 * r['beams'] / fa_total:.1f} %",
            ]
            for r in d["false_alarms"]
        ]
        score_rows = [
            [
                group,
                str(s["clusters"]),
                *(
                    " / ".join(f"{v:.2f}" for v in s[k]) if s[k] else "n/a"
                    for k in ("p_theta", "p_likelihood", "p_pv")
                ),
            ]
            for group, s in d["cluster_scores"].items()
        ]
        pictures = "\n".join(
            f"![{name}]({name})" for name in results.get("examples", {}).get(seq, [])
        )
        parts.append(
            f"### {seq}\n\n**Misses** ({total} beams)\n\n"
            + table(["stage that lost it", "beams", "share"], rows)
            + f"\n\n**False alarms** ({fa_total} beams)\n\n"
            + table(["what it hit", "surface", "removed by", "beams", "share"], fa_rows)
            + "\n\n**Cluster scores** (10th / 50th / 90th percentile)\n\n"
            + table(["clusters", "count", "P(θ)", "P(L)", "P(C_pv)"], score_rows)
            + f"\n\n{pictures}"
        )
    return "\n\n".join(parts)
