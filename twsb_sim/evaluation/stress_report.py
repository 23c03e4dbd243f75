"""The stress matrix as files: ``results.json``, ``report.md`` and ``stress_heatmap.png``."""

from __future__ import annotations

import json
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

# heat-map panels: (cell key, title, colour map, how a value is printed, value range)
PANELS = (
    ("auc", "PR-curve AUC", "viridis", "{:.2f}", (0.0, 1.0)),
    ("recall", "recall at the operating point", "viridis", "{:.2f}", (0.0, 1.0)),
    ("static_removed", "STATIC beams removed (%)", "magma_r", "{:.1f}", None),
    ("translation_error_m", "scan-matching error (cm)", "magma_r", "{:.1f}", None),
)
SCALE = {"static_removed": 100.0, "translation_error_m": 100.0}  # shown in % and cm


def _grid(results: dict, key: str) -> np.ndarray:
    rows = results["conditions"]
    return np.array(
        [[rows[c]["methods"][m][key] * SCALE.get(key, 1.0) for m in results["methods"]]
         for c in rows]
    )  # fmt: skip


def heat_map(results: dict, path: Path) -> None:
    """Conditions (rows) x methods (columns), one panel per figure of :data:`PANELS`."""
    conditions, methods = list(results["conditions"]), list(results["methods"].values())
    fig, axes = plt.subplots(
        1, len(PANELS), figsize=(4.2 * len(PANELS), 0.45 * len(conditions) + 2)
    )
    for ax, (key, title, cmap, fmt, limits) in zip(axes, PANELS, strict=True):
        values = _grid(results, key)
        finite = values[np.isfinite(values)]
        low, high = limits or (0.0, float(finite.max()) if finite.size else 1.0)
        ax.imshow(np.ma.masked_invalid(values), cmap=cmap, vmin=low, vmax=high or 1.0,
                  aspect="auto")  # fmt: skip
        for (i, j), value in np.ndenumerate(values):
            text = fmt.format(value) if math.isfinite(value) else "-"
            shade = (value - low) / ((high or 1.0) - low) if math.isfinite(value) else 0.0
            dark = shade > 0.55 if not cmap.endswith("_r") else shade < 0.45
            ax.text(j, i, text, ha="center", va="center", fontsize=8,
                    color="black" if dark else "white")  # fmt: skip
        ax.set_xticks(range(len(methods)), methods, rotation=35, ha="right", fontsize=8)
        ax.set_yticks(range(len(conditions)), conditions if ax is axes[0] else [], fontsize=8)
        ax.set_title(title, fontsize=10)
    fig.suptitle("Stress matrix: conditions x methods", fontsize=12)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def _cell(value: float, fmt: str) -> str:
    return fmt.format(value) if math.isfinite(value) else "–"


def markdown(results: dict, command: str) -> str:
    """The report: what was run, the condition rows, and one table per figure."""
    rows, methods = results["conditions"], results["methods"]
    config = results["config"]
    lines = [
        "# Stress matrix",
        "",
        f"Command: `{command}`. {config['episodes']} episode(s) per condition (data-set seed "
        f"{config['seed']}); methods at their operating points (paper P_th 0.8, improved "
        "P_th 0.5, IMU gate band 0.2 m). DYNAMIC beams are neither hits nor false alarms.",
        "",
        "| condition | episodes | frames | positive beams | CEILING | HORIZONTAL | DYNAMIC |"
        " falls | max pitch (deg) |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for name, row in rows.items():
        labels = row["labels"]
        lines.append(
            f"| {name} | {row['episodes']} | {row['frames']} | {row['positives']} | "
            f"{labels['CEILING']} | {labels['HORIZONTAL']} | {labels['DYNAMIC']} | "
            f"{row['falls']} | {row['max_abs_pitch_deg']:.1f} |"
        )
    tables = (
        ("PR-curve AUC", lambda c: _cell(c["auc"], "{:.3f}")),
        ("Precision / recall at the operating point",
         lambda c: f"{_cell(c['precision'], '{:.2f}')} / {_cell(c['recall'], '{:.2f}')}"),
        ("STATIC / DYNAMIC beams removed (%)",
         lambda c: f"{_cell(100 * c['static_removed'], '{:.2f}')} / "
                   f"{_cell(100 * c['dynamic_removed'], '{:.1f}')}"),
        ("Scan-matching error against the true relative pose: translation (cm) / rotation (deg)",
         lambda c: f"{_cell(100 * c['translation_error_m'], '{:.1f}')} / "
                   f"{_cell(c['rotation_error_deg'], '{:.2f}')}"),
    )  # fmt: skip
    for title, show in tables:
        lines += ["", f"## {title}", "", "| condition | " + " | ".join(methods.values()) + " |",
                  "|---|" + "---|" * len(methods)]  # fmt: skip
        for name, row in rows.items():
            lines.append(
                f"| {name} | " + " | ".join(show(row["methods"][m]) for m in methods) + " |"
            )
    lines += ["", "![stress heat map](stress_heatmap.png)", ""]
    return "\n".join(lines)


def write_stress_outputs(results: dict, out: Path, command: str) -> None:
    """results.json, report.md and stress_heatmap.png in ``out``."""
    out.mkdir(parents=True, exist_ok=True)
    (out / "results.json").write_text(json.dumps(results, indent=1) + "\n", encoding="utf-8")
    heat_map(results, out / "stress_heatmap.png")
    (out / "report.md").write_text(markdown(results, command), encoding="utf-8")
