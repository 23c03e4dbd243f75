"""The improved filter's part of the report: its tables, and its PR-curve plot."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only, no display

import matplotlib.pyplot as plt
import numpy as np

from twsb_sim.evaluation.markdown import fmt, table
from twsb_sim.evaluation.plots import save_figure, style_pr_axes

TARGETS = {"auc": 0.95, "precision": 0.9, "static_removed_pct": 1.0, "rate_hz": 2000.0}
STYLES = {  # method -> (colour, line style, marker)
    "pvf": ("#2166ac", "-", "o"),
    "improved": ("#d6604d", "-", "s"),
    "improved_tuned": ("#b2182b", "--", "v"),
    "improved_imu": ("#f4a582", "-.", "^"),
    "improved_imu_truth": ("#fddbc7", ":", "^"),
    "imu_gate": ("#4d9221", ":", "d"),
}


def _method_rows(per_method: dict, labels: dict, timing: dict | None = None) -> list[list[str]]:
    rows = []
    for name, m in per_method.items():
        rate = ""
        if timing is not None:
            rate = f"{timing[name]['rate_hz']:.0f}" if name in timing else "–"
        rows.append(
            [
                labels.get(name, name),
                fmt(m["auc"]),
                f"{m['operating_point']:g}",
                f"{fmt(m['precision'])} / {fmt(m['recall'])}",
                f"{fmt(m['static_removed_pct'], 2)} %",
                *([rate] if timing is not None else []),
            ]
        )
    return rows


HEADER = ["method", "AUC", "operating point", "precision / recall there", "STATIC removed"]


def render_improved_section(results: dict) -> str:
    """The markdown of the improved filter's section (empty when it was not evaluated)."""
    improved = results.get("improved")
    if not improved:
        return ""
    labels = improved["labels"]
    timing = improved["timing"]
    parts = [
        "## The improved filter beside the paper's",
        "The paper's filter (Table I; P_th swept afresh per value), the improved filter "
        "(`pvfilter.ImprovedPitchVariationFilter`, defaults; tuned parameters when a file "
        "was given; with the IMU's pitch and roll) and the IMU height gate, on the same "
        "runs. Operating points: P_th for the filters, the half-band in m for the gate. "
        "STATIC removed: the share of STATIC beams (walls, furniture sides) removed over "
        "whole sequences. Rates from the same loop over every frame of the runs above. "
        f"Targets for the improved filter: AUC ≥ {TARGETS['auc']}, precision ≥ "
        f"{TARGETS['precision']} at its default operating point, STATIC removed ≤ "
        f"{TARGETS['static_removed_pct']:g} %, ≥ {TARGETS['rate_hz']:.0f} scans/s.",
        "![improved PR curves](improved_pr_curves.png)",
    ]
    rate_of = {"pvf": timing.get("same_loop_paper"), **timing}
    rate_of["improved"] = timing.get("same_loop_improved", timing.get("improved"))
    for seq, per_method in improved.get("sequences", {}).items():
        parts.append(
            f"### {seq}\n\n"
            + table([*HEADER, "rate Hz"], _method_rows(per_method, labels, rate_of))
        )
    if "same_loop_paper" in timing:
        paper, mine = timing["same_loop_paper"], timing["same_loop_improved"]
        parts.append(
            f"Same loop, every frame: paper PVF {paper['rate_hz']:.0f} Hz "
            f"({paper['mean_ms']:.3f} ms), improved {mine['rate_hz']:.0f} Hz "
            f"({mine['mean_ms']:.3f} ms): the improved filter takes "
            f"{mine['mean_ms'] / paper['mean_ms']:.2f}x the paper filter's time."
        )
    if "ablation" in improved:
        switches = improved["ablation_switches"]
        for seq, per_variant in improved["ablation"].items():
            rows = [
                [
                    name,
                    switches[name],
                    fmt(m["auc"]),
                    f"{fmt(m['precision'])} / {fmt(m['recall'])}",
                    f"{fmt(m['static_removed_pct'], 2)} %",
                ]
                for name, m in per_variant.items()
            ]
            parts.append(
                f"### Ablation, {seq}\n\n"
                + table(
                    ["variant", "switched off", "AUC", "precision / recall", "STATIC removed"],
                    rows,
                )
            )
    for seq, d in improved.get("diagnosis", {}).items():
        missed = sum(d["misses"].values())
        rows = [[why, str(n), f"{100 * n / max(d['positives'], 1):.1f} %"]
                for why, n in sorted(d["misses"].items(), key=lambda kv: -kv[1])]  # fmt: skip
        alarms = sum(r["beams"] for r in d["false_alarms"])
        fa_rows = [[r["hit"], r["seen"], str(r["beams"])] for r in d["false_alarms"][:8]]
        parts.append(
            f"### Where the improved filter (defaults) still fails, {seq}\n\n"
            f"Missed {missed} of {d['positives']} pitch-variation beams:\n\n"
            + table(["why", "beams", "of all pitch-variation beams"], rows)
            + f"\n\nFalse alarms ({alarms} beams), by what they hit:\n\n"
            + table(["what it hit", "surface", "beams"], fa_rows)
        )
    for group, title in (("heldout", "Held-out random houses"), ("variations", "Robot variations")):
        for key, per_method in improved.get(group, {}).items():
            rows = table(HEADER, _method_rows(per_method, labels))
            parts.append(f"### {title}: {key}\n\n{rows}")
    return "\n\n".join(parts)


def plot_improved(results: dict, path: Path) -> None:
    """PR curves of the compared methods per sequence, AUC in the legend."""
    per_sequence = results["improved"]["sequences"]
    labels = results["improved"]["labels"]
    sequences = list(per_sequence)
    fig, axes = plt.subplots(1, len(sequences), figsize=(5.2 * len(sequences), 4.6), squeeze=False)
    for ax, seq in zip(axes[0], sequences, strict=True):
        for name, m in per_sequence[seq].items():
            colour, style, marker = STYLES.get(name, ("#777777", "-", "."))
            recall, precision = np.array(m["recall_curve"]), np.array(m["precision_curve"])
            order = np.argsort(recall, kind="stable")
            ax.plot(
                recall[order], precision[order], style, color=colour, marker=marker, ms=3,
                label=f"{labels.get(name, name)} (AUC {m['auc']:.3f})",
            )  # fmt: skip
        style_pr_axes(ax, seq, legend_loc="lower left")
    save_figure(fig, path)
