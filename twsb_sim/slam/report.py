"""The experiment's outputs in words and numbers: ``report.md`` (Table II next to the
paper's) and ``results.json`` (every run, the aggregates, the definitions)."""

from __future__ import annotations

import dataclasses
import json
import math
import statistics
from collections.abc import Sequence
from pathlib import Path

from scaneval.slam.scoring import ALIGNMENT, FAILURE_DISTANCE_M
from twsb_sim.slam.experiment import SlamConfig, SlamRunResult
from twsb_sim.slam.methods import IMU_GATE_BAND_M, METHOD_TITLES
from twsb_sim.slam.systems import SYSTEM_TITLES

# Table II of the paper: ATE in m, None where it reports a tracking failure ("–")
PAPER_TABLE_II = {
    "house1_single": {"hector": (1.0522, 0.1903), "cartographer": (0.3551, 0.1101)},
    "house2_multi": {"hector": (None, 0.0779), "cartographer": (0.2106, 0.0964)},
}
PAPER_ROW_NAMES = {"house1_single": "House1", "house2_multi": "House2"}
DEFINITIONS = {
    "ate": "eq. 7: RMSE of the position error over all scans (10 Hz), time-matched by "
    "construction (one estimate per scan), after aligning the estimate to the truth",
    "alignment": f"{ALIGNMENT}: the rotation and translation (no scale) that best fit the "
    "estimated positions onto the true ones (Umeyama), as evo_ape --align",
    "truth": "the LiDAR's exact planar pose from the simulator: position of the sensor "
    "origin (x, y) and the heading of its x axis; the SLAM map frame is the first scan's "
    "sensor frame",
    "tracking_failure": "the system reports losing track (Hector: fewer than 20 % of the "
    "points on known obstacles for 10 scans in a row; KISS-ICP: a non-finite pose; any "
    f"exception), or after the alignment some pose is more than {FAILURE_DISTANCE_M:g} m "
    "from the truth",
    "pvf_p04": "the PVF at P_th 0.4, the best-F1 threshold of twsb eval's sweep on the "
    "simulator's sequences (Table I's P_th 0.8 is the paper's operating point)",
    "improved": "the improved filter (pvfilter.ImprovedPitchVariationFilter) with its "
    "defaults, told the robot's LiDAR height; scans only, no IMU",
    "imu_gate": f"beams ending outside {IMU_GATE_BAND_M[0]:g}-{IMU_GATE_BAND_M[1]:g} m above "
    "the floor (by the IMU's pitch and roll) are removed",
    "truth_labels": "the simulator's ground-truth labels remove exactly the pitch-variation "
    "beams: what a perfect filter would give",
}


@dataclasses.dataclass(frozen=True)
class Cell:
    """One (sequence, system, method) over its seeds."""

    runs: int
    failures: int
    mean_ate_m: float  # over the runs that did not fail; NaN when all failed
    ates_m: tuple[float, ...]  # every run's ATE, failed ones included

    def text(self) -> str:
        """``0.123``, ``–`` (every run failed) or ``0.123 (1/3 –)``."""
        if self.failures == self.runs:
            return "–"
        value = f"{self.mean_ate_m:.4f}"
        return value if not self.failures else f"{value} ({self.failures}/{self.runs} –)"


def cells(results: Sequence[SlamRunResult]) -> dict[tuple[str, str, str], Cell]:
    """Per (sequence, system, method): the mean ATE of the runs that tracked, and failures."""
    grouped: dict[tuple[str, str, str], list[SlamRunResult]] = {}
    for r in results:
        grouped.setdefault((r.sequence, r.system, r.method), []).append(r)
    out = {}
    for key, rows in grouped.items():
        tracked = [r.ate_m for r in rows if not r.failed]
        out[key] = Cell(
            runs=len(rows),
            failures=len(rows) - len(tracked),
            mean_ate_m=statistics.fmean(tracked) if tracked else math.nan,
            ates_m=tuple(r.ate_m for r in rows),
        )
    return out


def _paper(value: float | None) -> str:
    return "–" if value is None else f"{value:.4f}"


def _ordered(results: Sequence[SlamRunResult], field: str) -> list[str]:
    return list(dict.fromkeys(getattr(r, field) for r in results))


def _table(header: list[str], rows: list[list[str]]) -> list[str]:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    return lines + ["| " + " | ".join(row) + " |" for row in rows]


def table_ii(results: Sequence[SlamRunResult]) -> list[str]:
    """The paper's Table II with our numbers beside it (House sequences only)."""
    table = cells(results)
    systems = _ordered(results, "system")
    header = ["sequence", "Hector-SLAM (paper) w/o", "w/"]
    header += ["Hector-style (ours) w/o", "w/ PVF"] if "hector" in systems else []
    header += ["Cartographer (paper) w/o", "w/"]
    header += ["KISS-ICP (ours) w/o", "w/ PVF"] if "kiss_icp" in systems else []
    rows = []
    for sequence in _ordered(results, "sequence"):
        if sequence not in PAPER_TABLE_II:
            continue
        paper = PAPER_TABLE_II[sequence]
        row = [PAPER_ROW_NAMES[sequence], *map(_paper, paper["hector"])]
        for system, paper_key in (("hector", None), ("kiss_icp", "cartographer")):
            if paper_key is not None:
                row += list(map(_paper, paper[paper_key]))
            if system in systems:
                row += [_cell_text(table, sequence, system, m) for m in ("none", "pvf")]
        rows.append(row)
    return _table(header, rows) if rows else []


def _cell_text(table: dict, sequence: str, system: str, method: str) -> str:
    cell = table.get((sequence, system, method))
    return cell.text() if cell is not None else "n/a"


def full_table(results: Sequence[SlamRunResult]) -> list[str]:
    """Every sequence, system and filter: mean ATE over the seeds, failures."""
    table = cells(results)
    methods = _ordered(results, "method")
    lines = []
    for system in _ordered(results, "system"):
        ratios = [m for m in ("pvf", "pvf_p04", "improved", "truth_labels") if m in methods]
        header = ["sequence", *(METHOD_TITLES[m] for m in methods)]
        header += [f"w/o ÷ {METHOD_TITLES[m]}" for m in ratios]
        rows = []
        for sequence in _ordered(results, "sequence"):
            row = [sequence] + [_cell_text(table, sequence, system, m) for m in methods]
            rows.append([*row, *(_reduction(table, sequence, system, m) for m in ratios)])
        lines += [f"**{SYSTEM_TITLES[system]}**", "", *_table(header, rows), ""]
    return lines


def _reduction(table: dict, sequence: str, system: str, method: str) -> str:
    """The ATE without a filter over the ATE with ``method``, or how failures changed."""
    without, with_pvf = table.get((sequence, system, "none")), table.get((sequence, system, method))
    if without is None or with_pvf is None:
        return "n/a"
    if without.failures and not with_pvf.failures:
        return "failure → tracked"
    if with_pvf.failures and not without.failures:
        return "tracked → failure"
    if without.failures or with_pvf.failures:
        return "–"
    return f"{without.mean_ate_m / with_pvf.mean_ate_m:.2f}x"


def run_table(results: Sequence[SlamRunResult]) -> list[str]:
    """One row per run: ATE, largest error, failure reason."""
    header = ["sequence", "seed", "system", "filter", "ATE m", "max m", "failure"]
    rows = [
        [
            r.sequence,
            str(r.seed),
            r.system,
            r.method,
            f"{r.ate_m:.4f}",
            f"{r.max_error_m:.3f}",
            r.failure or "",
        ]
        for r in results
    ]
    return _table(header, rows)


def filter_table(results: Sequence[SlamRunResult]) -> list[str]:
    """Per sequence and filter: the share of pitch-variation beams removed, and precision."""
    header = ["sequence", "filter", "pitch-variation beams", "removed", "recall", "precision"]
    rows, seen = [], set()
    for r in results:
        key = (r.sequence, r.method)
        if key in seen or r.method == "none":
            continue
        seen.add(key)
        same = [x for x in results if (x.sequence, x.method, x.system) == (*key, r.system)]
        positives = sum(x.pitch_variation_beams for x in same)
        removed = sum(x.removed_beams for x in same)
        hits = sum(x.removed_pitch_variation_beams for x in same)
        recall = f"{hits / positives:.2f}" if positives else "n/a"
        precision = f"{hits / removed:.2f}" if removed else "1.00"
        rows.append(
            [r.sequence, METHOD_TITLES[r.method], str(positives), str(removed), recall, precision]
        )
    return _table(header, rows)


def speeds(results: Sequence[SlamRunResult]) -> dict[str, float]:
    """Median scans per second of each system's loop over all its runs."""
    return {
        system: statistics.median(r.scans_per_s for r in results if r.system == system)
        for system in _ordered(results, "system")
    }


def write_report(
    path: Path,
    results: Sequence[SlamRunResult],
    config: SlamConfig,
    figures: Sequence[str],
    command: str,
) -> None:
    """``report.md``: the tables, what was measured, the figures."""
    speed = speeds(results)
    lines = [
        "# SLAM in the loop: ATE with and without the Pitch Variation Filter",
        "",
        f"Produced by `{command}`. Sequences: {', '.join(_ordered(results, 'sequence'))}; "
        f"seeds {', '.join(map(str, config.seeds))}"
        + (f"; each cut to {config.duration_s:g} s" if config.duration_s else "")
        + ".",
        "",
        "## Table II, ours beside the paper's (ATE, m; – = tracking failure)",
        "",
        "The paper's numbers are real-robot runs scored against a Cartographer "
        "pseudo-ground-truth; ours are simulated runs scored against the exact truth. "
        "Our cells are the mean over the seeds that tracked; `(k/n –)` counts failures.",
        "",
        *table_ii(results),
        "",
        "## Every sequence, system and filter (ATE, m)",
        "",
        *full_table(results),
        "## What is measured",
        "",
        *[f"- **{name.replace('_', ' ')}**: {text}." for name, text in DEFINITIONS.items()],
        "",
        "## What the filters removed",
        "",
        *filter_table(results),
        "",
        "## Speed of the SLAM loop",
        "",
        *[
            f"- {SYSTEM_TITLES[s]}: {v:.0f} scans/s (median over runs, one core)"
            for s, v in speed.items()
        ],
        "",
        "## Figures",
        "",
        *[f"![{name}]({name})" for name in figures],
        "",
        "## Every run",
        "",
        *run_table(results),
        "",
    ]
    path.write_text("\n".join(lines), encoding="utf-8")


def write_results(path: Path, results: Sequence[SlamRunResult], config: SlamConfig) -> None:
    """``results.json``: the configuration, definitions, every run and the aggregates."""
    table = cells(results)
    payload = {
        "config": dataclasses.asdict(config),
        "definitions": DEFINITIONS,
        "failure_distance_m": FAILURE_DISTANCE_M,
        "paper_table_ii": PAPER_TABLE_II,
        "runs": [{**dataclasses.asdict(r), "scans_per_s": r.scans_per_s} for r in results],
        "summary": [
            {"sequence": s, "system": y, "method": m, **dataclasses.asdict(c), "text": c.text()}
            for (s, y, m), c in table.items()
        ],
        "scans_per_s": speeds(results),
    }
    path.write_text(json.dumps(payload, indent=1, allow_nan=True) + "\n", encoding="utf-8")
