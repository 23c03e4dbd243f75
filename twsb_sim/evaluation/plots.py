"""The report's plots (matplotlib, Agg backend): Fig. 4, 5 and 6 of the paper, and pose errors.

Each function takes the results dict of :meth:`Evaluation.results` and writes one PNG.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only, no display

import matplotlib.pyplot as plt
import numpy as np

from twsb_sim.evaluation.config import PAPER_DATMO_SPEEDS_MPS

FAMILY_STYLES = {  # family -> (colour, line style, marker)
    "pvf": ("#2166ac", "-", "o"),
    "pvf_detection_only": ("#67a9cf", "--", "s"),
    "datmo": ("#b2182b", "-", "^"),
    "imu_gate": ("#4d9221", "-.", "d"),
    "imu_gate_truth": ("#a6dba0", ":", "d"),
}
CONDITION_STYLES = {  # scan-matching condition -> (label, colour)
    "without": ("without filter", "#d6604d"),
    "with": ("with PVF (Table I)", "#4393c3"),
    "oracle": ("oracle (labels)", "#bababa"),
}
DPI = 90  # small files: the plots are committed to the docs


def save_figure(fig: plt.Figure, path: Path) -> None:
    """Lay out, write (small PNG) and close a figure."""
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)
    plt.close(fig)


def style_pr_axes(ax: plt.Axes, sequence: str, legend_loc: str) -> None:
    """Axes, labels, title and legend shared by every PR-curve panel."""
    ax.set_xlim(-0.02, 1.02)
    ax.set_ylim(-0.02, 1.02)
    ax.set_xlabel("recall")
    ax.set_ylabel("precision")
    ax.set_title(sequence.replace("_", " "))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7.5, loc=legend_loc)


def plot_pr_curves(results: dict, path: Path) -> None:
    """PR curves of every method per sequence (paper Fig. 4), AUC in the legend."""
    sequences = list(results["pr"])
    fig, axes = plt.subplots(1, len(sequences), figsize=(5.2 * len(sequences), 4.6), squeeze=False)
    for ax, seq in zip(axes[0], sequences, strict=True):
        for family, curve in results["pr"][seq].items():
            colour, style, marker = FAMILY_STYLES[family]
            recall, precision = np.array(curve["recall"]), np.array(curve["precision"])
            order = np.argsort(recall, kind="stable")
            ax.plot(
                recall[order], precision[order], style, color=colour, marker=marker, ms=3.5,
                label=f"{curve['label']} (AUC {curve['auc']:.3f})",
            )  # fmt: skip
            if family == "datmo":  # the paper's three speeds
                for speed in PAPER_DATMO_SPEEDS_MPS:
                    if speed in curve["thresholds"]:
                        i = curve["thresholds"].index(speed)
                        ax.annotate(f"{speed:g}", (recall[i], precision[i]), fontsize=7)
        style_pr_axes(ax, seq, legend_loc="upper right")
    save_figure(fig, path)


def plot_timing(results: dict, path: Path) -> None:
    """Per-frame time of every method (log scale) and its rate (paper Fig. 5)."""
    timing = results["timing"]
    fig, (left, right) = plt.subplots(1, 2, figsize=(10.5, 4.0), width_ratios=(2, 1))
    names = list(timing["methods"])
    colours = [FAMILY_STYLES[f][0] for f in timing["families"]]
    for name, colour in zip(names, colours, strict=True):
        left.plot(timing["first_run_ms"][name], lw=0.8, color=colour, label=name)
    left.set_yscale("log")
    left.set_xlabel(f"frame ({timing['first_run']})")
    left.set_ylabel("time per frame (ms)")
    left.grid(alpha=0.3, which="both")
    left.legend(fontsize=7.5)
    rates = [timing["methods"][n]["rate_hz"] for n in names]
    rows = np.arange(len(names))[::-1]
    bars = right.barh(rows, rates, color=colours)
    right.bar_label(bars, fmt="%.0f Hz", fontsize=7.5, padding=2)
    right.set_yticks(rows, [n.replace(" (", "\n(") for n in names], fontsize=7.5)
    right.set_xlabel("frames per second (all runs)")
    right.set_xlim(right=max(rates) * 1.35)  # room for the labels
    right.grid(alpha=0.3, axis="x")
    save_figure(fig, path)


def plot_chamfer(results: dict, path: Path) -> None:
    """Normalized mean Chamfer distance per matcher, without/with filter (paper Fig. 6)."""
    matching = results["scan_matching"]["all"]
    kinds = ("onset", "peak")
    fig, axes = plt.subplots(1, 2, figsize=(10.0, 3.8))
    for ax, kind in zip(axes, kinds, strict=True):
        matchers = list(matching[kind])
        x = np.arange(len(matchers))
        for j, (condition, (label, colour)) in enumerate(CONDITION_STYLES.items()):
            values = [matching[kind][m]["normalized_mean_chamfer"][condition] for m in matchers]
            bars = ax.bar(x + (j - 1) * 0.27, values, 0.27, color=colour, label=label)
            ax.bar_label(bars, fmt="%.2f", fontsize=7)
        ax.set_xticks(x, [m.upper() for m in matchers])
        ax.set_ylabel("normalized mean Chamfer distance")
        ax.set_ylim(0, 1.25 * max(ax.get_ylim()[1], 1.0))  # room for the legend
        what = "first frame of each pitch variation" if kind == "onset" else "its peak frame"
        ax.set_title(f"{kind}: {what} ({matching['events']} events)", fontsize=9)
        ax.grid(alpha=0.3, axis="y")
        ax.legend(fontsize=7.5, ncols=3, loc="upper center")
    save_figure(fig, path)


def plot_pose_errors(results: dict, path: Path) -> None:
    """Mean error of the aligned pose against the true relative pose, per matcher."""
    matching = results["scan_matching"]["all"]
    fig, axes = plt.subplots(2, 2, figsize=(10.0, 6.4))
    quantities = (("mean_translation_error_m", 100.0, "translation error (cm)"),
                  ("mean_rotation_error_deg", 1.0, "rotation error (deg)"))  # fmt: skip
    for row, kind in enumerate(("onset", "peak")):
        matchers = list(matching[kind])
        x = np.arange(len(matchers))
        for col, (key, scale, label) in enumerate(quantities):
            ax = axes[row, col]
            for j, (condition, (name, colour)) in enumerate(CONDITION_STYLES.items()):
                values = [scale * matching[kind][m][condition][key] for m in matchers]
                bars = ax.bar(x + (j - 1) * 0.27, values, 0.27, color=colour, label=name)
                ax.bar_label(bars, fmt="%.2f", fontsize=6.5)
            ax.set_xticks(x, [m.upper() for m in matchers])
            ax.set_ylabel(label)
            ax.set_ylim(0, 1.3 * ax.get_ylim()[1])  # room for the legend
            ax.set_title(f"{kind} frames", fontsize=9)
            ax.grid(alpha=0.3, axis="y")
    axes[0, 0].legend(fontsize=7.5, ncols=3, loc="upper center")
    save_figure(fig, path)
