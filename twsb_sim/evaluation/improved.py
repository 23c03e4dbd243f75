"""The improved filter in the evaluation: beside the paper's, its ablation, and robustness.

For every run of the main evaluation, and for the robustness runs (held-out random houses
and robot variations, ``twsb eval --variations``):

- **side by side**: the paper's filter (Table I, the P_th sweep run afresh per value),
  the improved filter with its defaults, with a tuned parameter file
  (``--improved-params``), and with the IMU's pitch and roll, and the IMU height gate;
- **ablation** (main runs): the improved filter with one part switched off at a time;
- per method: PR curve and AUC, precision and recall at its operating point, the share of
  STATIC beams it removes over whole sequences, and (main runs) its rate, timed in the
  same loop as the paper's filter.

The improved filter's state does not depend on ``p_th`` and its scores say at which
thresholds a beam is removed, so one pass over a run gives its whole sweep, exactly.
The improved filter is always told the robot's LiDAR and axle heights (a user knows them).
"""

from __future__ import annotations

import dataclasses
import time
from collections import Counter, defaultdict
from collections.abc import Callable

import numpy as np

from pvfilter import FilterParams, ImprovedParams, load_params
from scaneval.metrics import pr_curve
from twsb_sim.evaluation.config import DEFAULT_IMU_BAND_M, EvalConfig
from twsb_sim.evaluation.diagnosis import describe_false_alarms
from twsb_sim.evaluation.families import family_filter
from twsb_sim.evaluation.passes import beam_truth, sweep_counts
from twsb_sim.evaluation.recording import Recording
from twsb_sim.frame_filter import FrameFilter, frame_filter
from twsb_sim.labels import BeamLabel, with_label

# ablation: name -> (what is switched off, how)
ABLATION: dict[str, tuple[str, Callable[[ImprovedParams], ImprovedParams]]] = {
    "full": ("nothing (the defaults)", lambda p: p),
    "no_ego_motion": (
        "ego-motion: the level view is not moved",
        lambda p: _set(p, ego_motion=False),
    ),
    "no_reanchor": (
        "re-anchoring the level view against the scan (its dead-reckoning drift stays)",
        lambda p: _set(p, reanchor_view=False),
    ),
    "previous_scan_only": (
        "level-view memory: the view follows every return at once, except where it holds",
        lambda p: _set(p, memory_shrink_mps=float("inf"), line_shrink_mps=float("inf")),
    ),
    "no_line_rate": (
        "the slower approach of the view behind segments across the travel (as elsewhere)",
        lambda p: _set(p, line_shrink_mps=float("inf")),
    ),
    "no_hold": (
        "holding the view behind possible floor lines (it shrinks there too)",
        lambda p: _set(p, hold_behind_lines=False),
    ),
    "no_roll_learning": (
        "measuring the plane's roll on confident floor lines (the gates keep max_roll_deg)",
        lambda p: _set(p, learn_roll=False),
    ),
    "no_line_split": (
        "segmentation by line direction: segments split at range jumps only",
        lambda p: _set(p, line_angle_deg=90.0),
    ),
    "no_geometry_gates": (
        "tilted-plane gates (distance, implied roll)",
        lambda p: _set(p, max_roll_deg=90.0, max_tilt_deg=90.0),
    ),
    "no_down_side": (
        "the down side (lines beyond the strongest line keep their score)",
        lambda p: _set(p, up_side_weight=1.0),
    ),
    "no_extension": ("line extension at the ends", lambda p: _set(p, extend_beams=0)),
    "no_spread": (
        "spreading a line over the points along it (and a cut line's new points together)",
        lambda p: _set(p, spread=False),
    ),
    "no_claim_weight": (
        "half the line's score for a claimed point that is not new (all at the line's)",
        lambda p: _set(p, claimed_not_new_weight=1.0),
    ),
    "no_settle": (
        "settling the view after max_event_s",
        lambda p: _set(p, max_event_s=float("inf")),
    ),
    "no_line_length": (
        "weighting a line by its length (a short line scores as a whole floor line)",
        lambda p: _set(p, line_length_m=0.0),
    ),
    "no_new_return_score": (
        "the score of a new return that no line takes in (it scores 0, as a known return)",
        lambda p: _set(p, new_return_score=0.0),
    ),
    "no_sweep_bend": (
        "allowing for the bend a pitch rate puts in a rotating scan's floor line",
        lambda p: _set(p, max_pitch_rate_rad_s=0.0),
    ),
}
# the robot's inputs added to the defaults (scans alone otherwise): name -> (what, inputs)
ABLATION_INPUTS: dict[str, tuple[str, tuple[str, ...]]] = {
    "with_imu": ("nothing; given the attitude estimate (IMU)", ("pitch_rad", "roll_rad")),
    "with_odometry": ("nothing; given the wheel odometry's pose", ("pose_sensor_in_odom",)),
    "with_imu_odometry": (
        "nothing; given both",
        ("pitch_rad", "roll_rad", "pose_sensor_in_odom"),
    ),
}


# why the improved filter misses a pitch-variation beam, first that holds
IMPROVED_MISSES: dict[str, str] = {
    "not_new": "not in front of the level view by the margin (not new)",
    "small": "new, but in a segment smaller than min_points",
    "gates": "new, but its segment fails the tilted-plane gates",
    "share": "new, but its segment's share of new points is at most p_th",
}


def _set(params: ImprovedParams, **changes: object) -> ImprovedParams:
    return dataclasses.replace(params, **changes)


def improved_filter(
    recording: Recording,
    params: ImprovedParams | None = None,
    imu: bool = False,
    label: str = "",
    truth: bool = False,
    inputs: tuple[str, ...] | None = None,
) -> FrameFilter:
    """The improved filter told the recorded robot's LiDAR and axle heights (a user knows
    them); with ``imu`` it is also given the robot's attitude estimate (with ``truth``, the
    true attitude instead); ``inputs`` names the robot inputs it gets instead."""
    inputs = inputs if inputs is not None else (("pitch_rad", "roll_rad") if imu else ())
    return frame_filter(
        "improved", label or "improved", params, recording.geometry, inputs, truth_inputs=truth
    )


@dataclasses.dataclass
class Tally:
    """What one filter gave over some runs: sweep counts and STATIC beams at its operating
    point."""

    thresholds: tuple[float, ...]
    operating_point: float
    counts: np.ndarray | None = None  # (k, 3): tp, fp, fn per threshold
    static_removed: int = 0
    static_total: int = 0

    def add(self, counts: np.ndarray, static_removed: int, static_total: int) -> None:
        self.counts = counts if self.counts is None else self.counts + counts
        self.static_removed += static_removed
        self.static_total += static_total

    def summary(self) -> dict:
        curve = pr_curve(self.thresholds, *self.counts.T)
        return {
            **curve.at(self.operating_point),
            "static_removed_pct": 100.0 * self.static_removed / max(self.static_total, 1),
            "thresholds": list(self.thresholds),
            "precision_curve": curve.precision.tolist(),
            "recall_curve": curve.recall.tolist(),
        }


def one_pass(
    recording: Recording, improved: FrameFilter, thresholds: tuple[float, ...], op: float
) -> tuple[np.ndarray, int, int, np.ndarray]:
    """Sweep counts, STATIC beams removed at ``op`` and per-frame seconds, from one pass."""
    values = np.asarray(thresholds)[:, None]
    counts = np.zeros((len(thresholds), 3), dtype=np.int64)
    static_removed = static_total = 0
    seconds = np.zeros(len(recording.frames))
    improved.reset()
    for k, frame in enumerate(recording.frames):
        start = time.perf_counter()
        scores = improved.process(frame).scores
        seconds[k] = time.perf_counter() - start
        positive, finite = beam_truth(frame)
        removed = (scores[None, :] > values) & finite
        tp = np.count_nonzero(removed & positive, axis=1)
        fn = np.count_nonzero(positive & finite) - tp
        counts += np.stack((tp, removed.sum(axis=1) - tp, fn), axis=1)
        static = with_label(frame.labels, BeamLabel.STATIC) & finite
        static_removed += int(np.count_nonzero(scores[static] > op))
        static_total += int(np.count_nonzero(static))
    return counts, static_removed, static_total, seconds


def static_at(recording: Recording, frame_filter: FrameFilter) -> tuple[int, int]:
    """STATIC beams a filter removes over a run, and all STATIC beams with a finite range."""
    frame_filter.reset()
    removed = total = 0
    for frame in recording.frames:
        mask = frame_filter.process(frame).removed
        static = with_label(frame.labels, BeamLabel.STATIC) & np.isfinite(frame.scan.ranges)
        removed += int(np.count_nonzero(mask & static))
        total += int(np.count_nonzero(static))
    return removed, total


def diagnose(recording: Recording, params: ImprovedParams) -> tuple[Counter, Counter, int]:
    """Why the improved filter misses beams, and what its false alarms hit, over a run.

    Returns:
        Missed beams per :data:`IMPROVED_MISSES` key, false-alarm beams per (surface kind,
        first seen or seen before, detected), and the run's pitch-variation beams.
    """
    improved = improved_filter(recording, params)
    misses, false_alarms, positives, previous = Counter(), Counter(), 0, None
    for frame in recording.frames:
        result = improved.process(frame)
        positive, finite = beam_truth(frame)
        positive &= finite
        positives += int(np.count_nonzero(positive))
        missed = np.flatnonzero(positive & ~result.removed)
        lines = result.lines
        cluster = lines.clusters.labels[missed]
        new = lines.new_points[missed]
        gated = np.append(lines.passes_gates, False)[cluster]
        misses["not_new"] += int(np.count_nonzero(~new))
        misses["small"] += int(np.count_nonzero(new & (cluster < 0)))
        misses["gates"] += int(np.count_nonzero(new & (cluster >= 0) & ~gated))
        misses["share"] += int(np.count_nonzero(new & (cluster >= 0) & gated))
        false_alarms.update(describe_false_alarms(frame, previous, result, recording.geom_names))
        previous = frame
    return misses, false_alarms, positives


@dataclasses.dataclass
class ImprovedEvaluation:
    """The improved filter's results so far: (group, key) -> method -> :class:`Tally`.

    Groups: ``sequences`` (keyed by sequence), ``ablation`` (sequence), ``heldout``
    (sequence) and ``variations`` (robot condition).
    """

    config: EvalConfig
    tuned: ImprovedParams | None = None
    tallies: dict = dataclasses.field(default_factory=lambda: defaultdict(dict))
    seconds: dict = dataclasses.field(default_factory=lambda: defaultdict(list))
    labels: dict = dataclasses.field(default_factory=dict)
    misses: dict = dataclasses.field(default_factory=lambda: defaultdict(Counter))
    false_alarms: dict = dataclasses.field(default_factory=lambda: defaultdict(Counter))
    positives: dict = dataclasses.field(default_factory=lambda: defaultdict(int))

    def __post_init__(self) -> None:
        if self.config.improved_params and self.tuned is None:
            tuned = load_params(self.config.improved_params)
            if not isinstance(tuned, ImprovedParams):
                raise ValueError(f"{self.config.improved_params}: not improved-filter parameters")
            self.tuned = tuned

    def improved_filters(self, recording: Recording) -> dict[str, FrameFilter]:
        """name -> the improved filter's variants compared."""
        filters = {
            "improved": improved_filter(recording, label="improved (defaults)"),
            "improved_imu": improved_filter(recording, imu=True, label="improved + IMU"),
            "improved_imu_truth": improved_filter(
                recording, imu=True, label="improved + true attitude", truth=True
            ),
        }
        if self.tuned is not None:
            filters["improved_tuned"] = improved_filter(
                recording, self.tuned, label="improved (tuned)"
            )
        return filters

    def _tally(self, group: str, key: str, name: str, thresholds, op) -> Tally:
        return self.tallies[(group, key)].setdefault(name, Tally(tuple(thresholds), op))

    def add_run(self, recording: Recording, group: str, key: str, paper_counts=None) -> None:
        """Replay one run through the compared filters (and, for main runs, the ablation).

        Args:
            recording: the run.
            group: ``sequences``, ``heldout`` or ``variations``.
            key: the sequence or the robot condition.
            paper_counts: the paper filter's P_th sweep counts of this run, when the main
                evaluation has them already (they are then not computed again).
        """
        config = self.config
        p_th = tuple(config.p_th_values)
        # the paper's filter: the P_th sweep run afresh per value, STATIC at Table I
        paper = lambda v: family_filter("pvf", v, recording)  # noqa: E731
        if paper_counts is None:
            paper_counts = sweep_counts(recording, paper, p_th)
        paper_op = FilterParams().p_th
        self.labels["pvf"] = "paper PVF (Table I)"
        self._tally(group, key, "pvf", p_th, paper_op).add(
            paper_counts, *static_at(recording, paper(paper_op))
        )
        # the IMU height gate: stateless, its band sweep is cheap
        bands = tuple(config.imu_bands_m)
        gate = lambda band: family_filter("imu_gate", band, recording)  # noqa: E731
        self.labels["imu_gate"] = "IMU height gate"
        self._tally(group, key, "imu_gate", bands, DEFAULT_IMU_BAND_M).add(
            sweep_counts(recording, gate, bands), *static_at(recording, gate(DEFAULT_IMU_BAND_M))
        )
        # the improved filter's variants: one pass each gives the whole sweep
        for name, improved in self.improved_filters(recording).items():
            self.labels[name] = improved.label
            op = improved.scan_filter.params.p_th
            values = tuple(sorted({*p_th, op}))  # a tuned operating point joins the sweep
            counts, removed, total, seconds = one_pass(recording, improved, values, op)
            self._tally(group, key, name, values, op).add(counts, removed, total)
            if group == "sequences":
                self.seconds[name].append(seconds)
        if group == "sequences":
            self._ablation(recording, key, p_th)
            self._time_against_paper(recording)
            misses, false_alarms, positives = diagnose(recording, ImprovedParams())
            self.misses[key].update(misses)
            self.false_alarms[key].update(false_alarms)
            self.positives[key] += positives

    def _ablation(self, recording: Recording, key: str, p_th: tuple[float, ...]) -> None:
        base = ImprovedParams()
        values = tuple(sorted({*p_th, base.p_th}))
        variants = [(name, change(base), ()) for name, (_, change) in ABLATION.items()]
        variants += [(name, base, inputs) for name, (_, inputs) in ABLATION_INPUTS.items()]
        for name, params, inputs in variants:
            improved = improved_filter(recording, params, inputs=inputs)
            counts, removed, total, _ = one_pass(recording, improved, values, base.p_th)
            self._tally("ablation", key, name, values, base.p_th).add(counts, removed, total)

    def _time_against_paper(self, recording: Recording) -> None:
        """Paper's filter and improved filter called in turn on each frame, timed."""
        pair = (family_filter("pvf", FilterParams().p_th, recording), improved_filter(recording))
        seconds = np.zeros((2, len(recording.frames)))
        for each in pair:
            each.reset()
        for k, frame in enumerate(recording.frames):
            for row, each in enumerate(pair):
                start = time.perf_counter()
                each.process(frame)
                seconds[row, k] = time.perf_counter() - start
        self.seconds["same_loop_paper"].append(seconds[0])
        self.seconds["same_loop_improved"].append(seconds[1])

    def results(self) -> dict:
        """Every figure of this part, JSON-ready (see :mod:`twsb_sim.evaluation.report`)."""
        switches = {name: what for name, (what, _) in (*ABLATION.items(),
                                                        *ABLATION_INPUTS.items())}  # fmt: skip
        out: dict = {"labels": dict(self.labels), "ablation_switches": switches}
        for (group, key), tallies in self.tallies.items():
            out.setdefault(group, {})[key] = {n: t.summary() for n, t in tallies.items()}
        timing = {}
        for name, chunks in self.seconds.items():
            seconds = np.concatenate(chunks)
            timing[name] = {
                "frames": int(seconds.size),
                "mean_ms": 1e3 * float(seconds.mean()),
                "rate_hz": float(1.0 / seconds.mean()),
            }
        out["timing"] = timing
        out["diagnosis"] = {
            key: {
                "positives": self.positives[key],
                "misses": {IMPROVED_MISSES[k]: n for k, n in self.misses[key].items()},
                "false_alarms": [
                    {"hit": kind, "seen": seen, "beams": beams}
                    for (kind, seen, _), beams in self.false_alarms[key].most_common()
                ],
            }
            for key in self.misses
        }
        out["tuned_params"] = dataclasses.asdict(self.tuned) if self.tuned is not None else None
        return out
