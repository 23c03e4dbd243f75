"""The evaluation, end to end: simulate each run once, replay it through every method.

Per (sequence, house, seed): simulate once (:mod:`~twsb_sim.evaluation.recording`), then
over the stored frames

1. the timed pass: every method at its operating point, interleaved per frame;
2. the sweeps: a fresh method per threshold (P_th, speed, band) over the whole run;
3. the miss diagnosis of the filter at Table I;
4. the scan-matching experiment at every pitch-variation event.

:class:`Evaluation` accumulates what each run gives; :meth:`Evaluation.results` turns it
into the JSON-ready figures the report and plots are made from.
"""

from __future__ import annotations

import dataclasses
import time
from collections import defaultdict

import numpy as np
from tqdm import tqdm

from pvfilter import FilterParams, filter_entry
from scaneval.metrics import pr_curve
from twsb_sim.evaluation.config import EvalConfig, parse_house
from twsb_sim.evaluation.diagnosis import RunDiagnosis, diagnose_run
from twsb_sim.evaluation.families import (
    FILTERS,
    LABELS,
    OPERATING_POINTS,
    SWEPT,
    family_filter,
    sweep_values,
)
from twsb_sim.evaluation.improved import ImprovedEvaluation
from twsb_sim.evaluation.passes import operating_pass, score_sweep_counts, sweep_counts
from twsb_sim.evaluation.recording import Recording, record, sequence_in_house, with_robot
from twsb_sim.evaluation.scan_matching import align, pitch_variation_runs, summarize


@dataclasses.dataclass
class Evaluation:
    """What the runs have given so far, per sequence."""

    config: EvalConfig
    counts: dict = dataclasses.field(default_factory=dict)  # (seq, family) -> (k, 3)
    run_rows: list = dataclasses.field(default_factory=list)
    seconds: dict = dataclasses.field(default_factory=lambda: defaultdict(list))
    first_run: str = ""  # the run whose per-frame times are plotted
    first_run_seconds: dict = dataclasses.field(default_factory=dict)
    alignments: dict = dataclasses.field(default_factory=lambda: defaultdict(list))
    events: dict = dataclasses.field(default_factory=lambda: defaultdict(int))
    diagnoses: dict = dataclasses.field(default_factory=lambda: defaultdict(RunDiagnosis))
    wall_s: float = 0.0
    improved: ImprovedEvaluation | None = None

    def __post_init__(self) -> None:
        if self.config.improved and self.improved is None:
            self.improved = ImprovedEvaluation(self.config)

    def add_run(self, recording: Recording, progress: bool = False) -> None:
        """Replay one recorded run through every filter and experiment."""
        config, seq = self.config, recording.sequence
        row = {
            "run": recording.run_id,
            "sequence": seq,
            "house": recording.house,
            "seed": recording.seed,
            "frames": len(recording.frames),
            "fell": recording.summary.fell,
            "max_abs_pitch_deg": recording.summary.max_abs_pitch_deg,
            "pitch_variation_frames": recording.summary.pitch_variation_frames,
            "auc": {},
        }
        # 1. the timed pass, every filter at its operating point
        filters = {
            LABELS[f]: family_filter(f, OPERATING_POINTS[f], recording) for f in config.families
        }
        timed = operating_pass(recording, filters, LABELS["pvf"])
        self.first_run = self.first_run or recording.run_id
        for name, seconds in timed.seconds.items():
            self.seconds[name].append(seconds)
            self.first_run_seconds.setdefault(name, seconds)
        # 2. the sweeps
        for family in config.families:
            values = sweep_values(config, family)
            if filter_entry(FILTERS[family]).one_pass:  # its state ignores the threshold
                one = family_filter(family, 0.0, recording)
                counts = score_sweep_counts(recording, one, values)
            else:  # a fresh filter per value
                counts = sweep_counts(
                    recording, lambda v, f=family: family_filter(f, v, recording), values,
                    progress, desc=f"{LABELS[family]} sweep",
                )  # fmt: skip
            key = (seq, family)
            self.counts[key] = self.counts.get(key, 0) + counts
            row["auc"][family] = pr_curve(values, *counts.T).auc
            if family == "pvf":
                pvf_counts = counts
        self.run_rows.append(row)
        # the improved filter beside the paper's (it reuses the paper filter's sweep)
        if self.improved is not None:
            self.improved.add_run(recording, "sequences", seq, paper_counts=pvf_counts)
        # 3. why the filter misses, at Table I
        params = FilterParams()
        self.diagnoses[seq].merge(
            diagnose_run(
                recording.frames, timed.pvf_results, params, recording.geom_names,
                recording.run_id,
            )
        )  # fmt: skip
        # 4. scan matching at every pitch-variation event
        removed = timed.removed[LABELS["pvf"]]
        events = pitch_variation_runs(recording.frames)[: config.max_events_per_run]
        self.events[seq] += len(events)
        for onset, peak in tqdm(events, desc="scan matching", disable=not progress, leave=False):
            for kind, source in (("onset", onset), ("peak", peak)):
                self.alignments[seq].extend(
                    align(recording.frames, removed, kind, source, onset - 1, config.matchers)
                )

    def results(self) -> dict:
        """Every figure, JSON-ready (see the report for what each means)."""
        config = self.config
        pr = defaultdict(dict)
        for (seq, family), counts in self.counts.items():
            values = sweep_values(config, family)
            curve = pr_curve(values, *counts.T)
            run_aucs = [r["auc"][family] for r in self.run_rows if r["sequence"] == seq]
            pr[seq][family] = {
                "label": LABELS[family],
                "swept": SWEPT[family],
                "thresholds": list(values),
                "precision": curve.precision.tolist(),
                "recall": curve.recall.tolist(),
                "tp": curve.tp.tolist(),
                "fp": curve.fp.tolist(),
                "fn": curve.fn.tolist(),
                "auc": curve.auc,
                "auc_runs": {
                    "min": float(np.min(run_aucs)),
                    "mean": float(np.mean(run_aucs)),
                    "max": float(np.max(run_aucs)),
                },
            }
        timing = {}
        for name, chunks in self.seconds.items():
            seconds = np.concatenate(chunks)
            timing[name] = {
                "frames": int(seconds.size),
                "mean_ms": 1e3 * float(seconds.mean()),
                "median_ms": 1e3 * float(np.median(seconds)),
                "p95_ms": 1e3 * float(np.percentile(seconds, 95)),
                "rate_hz": float(1.0 / seconds.mean()),
            }
        datmo = timing.get(LABELS["datmo"], {"rate_hz": float("nan")})
        ratio = timing[LABELS["pvf"]]["rate_hz"] / datmo["rate_hz"]
        matching = {
            seq: self._matching(rows, self.events[seq]) for seq, rows in self.alignments.items()
        }
        pooled = [a for rows in self.alignments.values() for a in rows]
        matching["all"] = self._matching(pooled, sum(self.events.values()))
        return {
            "config": dataclasses.asdict(config),
            "wall_s": self.wall_s,
            "runs": self.run_rows,
            "pr": dict(pr),
            "timing": {
                "methods": timing,
                "families": list(config.families),
                "first_run": self.first_run,
                "first_run_ms": {n: (1e3 * s).tolist() for n, s in self.first_run_seconds.items()},
                "pvf_over_datmo_rate": ratio,
                "operating_points": {LABELS[f]: OPERATING_POINTS[f] for f in config.families},
            },
            "scan_matching": matching,
            "diagnosis": {seq: _diagnosis_json(d) for seq, d in self.diagnoses.items()},
            **({"improved": self.improved.results()} if self.improved is not None else {}),
        }

    def _matching(self, alignments: list, events: int) -> dict:
        """Scan-matching summaries of some alignments, onset and peak apart."""
        return {
            "events": events,
            **{
                kind: summarize([a for a in alignments if a.kind == kind], self.config.matchers)
                for kind in ("onset", "peak")
            },
        }


def _diagnosis_json(diagnosis: RunDiagnosis) -> dict:
    scores = np.array(diagnosis.scores, dtype=float).reshape(-1, 5)
    groups = {
        "pitch-variation clusters, onset frames": (scores[:, 0] == 1) & (scores[:, 1] == 1),
        "pitch-variation clusters, later frames": (scores[:, 0] == 1) & (scores[:, 1] == 0),
        "structure clusters": scores[:, 0] == 0,
    }
    return {
        "misses": dict(diagnosis.misses),
        "false_alarms": [
            {"hit": kind, "seen": seen, "removed_by": route, "beams": beams}
            for (kind, seen, route), beams in diagnosis.false_alarms.most_common()
        ],
        "cluster_scores": {name: _percentiles(scores[mask, 2:]) for name, mask in groups.items()},
    }


def _percentiles(rows: np.ndarray) -> dict:
    """Count and 10/50/90th percentiles of P(theta), P(L), P(C_pv) over scored clusters."""
    out = {"clusters": len(rows)}
    for column, name in enumerate(("p_theta", "p_likelihood", "p_pv")):
        values = rows[:, column]
        out[name] = np.percentile(values, [10, 50, 90]).tolist() if len(values) else []
    return out


def run_evaluation(config: EvalConfig, progress: bool = True) -> tuple[dict, Evaluation]:
    """Simulate every (sequence, house, seed) once and evaluate it.

    Returns:
        The results (JSON-ready) and the evaluation itself (for the example pictures).
    """
    started = time.perf_counter()
    evaluation = Evaluation(config)
    runs = [(s, h, seed) for s in config.sequences for h in config.houses for seed in config.seeds]
    bar = tqdm(runs, desc="evaluation", unit="run", disable=not progress)
    for sequence, house_text, seed in bar:
        bar.set_postfix_str(f"{sequence} {house_text} seed {seed}")
        name, house_seed = parse_house(house_text)
        scenario, house = sequence_in_house(sequence, name, house_seed, config.duration_s)
        evaluation.add_run(record(scenario, house, seed), progress)
    if config.variations and evaluation.improved is not None:
        robustness_runs(evaluation.improved, progress)
    evaluation.wall_s = time.perf_counter() - started
    return evaluation.results(), evaluation


def robustness_runs(improved: ImprovedEvaluation, progress: bool = True) -> None:
    """The held-out houses (default robot) and the robot variations, seed 0."""
    config = improved.config
    runs = [("heldout", seq, seq, house, {}) for seq in config.sequences
            for house in config.heldout_houses]  # fmt: skip
    runs += [
        ("variations", name, seq, house, overrides)
        for name, overrides in config.robot_variations.items()
        for seq in config.sequences
        for house in config.variation_houses
    ]
    bar = tqdm(runs, desc="robustness runs", unit="run", disable=not progress)
    for group, key, sequence, house_text, overrides in bar:
        bar.set_postfix_str(f"{key} {house_text}")
        name, house_seed = parse_house(house_text)
        scenario, house = sequence_in_house(sequence, name, house_seed, config.duration_s)
        improved.add_run(record(with_robot(scenario, overrides), house, 0), group, key)
