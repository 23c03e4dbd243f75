"""The stress matrix: every condition x every method, on the condition's own episodes.

Per condition (:mod:`~twsb_sim.evaluation.stress_conditions`), the first ``episodes``
episodes of its family are simulated once each (as ``twsb generate`` draws them) and
replayed through the methods:

| method | what removes a beam |
|---|---|
| ``paper`` | the paper's filter, Table I; P_th swept (a fresh filter per value) |
| ``improved`` | the improved filter (told the LiDAR and axle heights); one pass gives its sweep |
| ``imu_gate`` | the IMU height gate; its band swept |
| ``none`` | nothing |
| ``truth`` | exactly the pitch-variation beams, from the labels |

Per cell: the AUC of the pooled PR curve, precision and recall at the method's operating
point, the shares of STATIC and of DYNAMIC beams it removes there (DYNAMIC beams are
neither hits nor false alarms), and the scan-matching error at every pitch-variation
event (up to ``max_events`` per episode): the event's frame with the most
pitch-variation beams aligned by ICP onto the frame before the event, each with the
method's removed beams dropped, against the true relative pose of the two scans.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

import numpy as np
from tqdm import tqdm

from pvfilter import FilterParams, ImprovedParams
from scaneval.geometry import compose, invert, scan_points
from scaneval.matching import MATCHERS
from scaneval.metrics import pr_curve
from twsb_sim.dataset.episode import draw_episode
from twsb_sim.dataset.randomization import Randomization
from twsb_sim.evaluation.config import DEFAULT_IMU_BAND_M, IMU_BANDS_M, P_TH_VALUES
from twsb_sim.evaluation.families import family_filter
from twsb_sim.evaluation.improved import improved_filter
from twsb_sim.evaluation.passes import beam_truth, confusion, dynamic_removed, sweep_counts
from twsb_sim.evaluation.recording import Recording, record
from twsb_sim.evaluation.scan_matching import pitch_variation_runs, true_relative_pose
from twsb_sim.evaluation.stress_conditions import condition_names, condition_ranges
from twsb_sim.frame_filter import frame_filter
from twsb_sim.labels import BeamLabel, with_label
from twsb_sim.scenario import scenario_from_table

METHODS: dict[str, str] = {
    "paper": "paper filter",
    "improved": "improved filter",
    "imu_gate": "IMU gate",
    "none": "no filter",
    "truth": "truth labels",
}


@dataclasses.dataclass(frozen=True)
class StressConfig:
    """What the stress matrix runs.

    Attributes:
        conditions: the rows (names of registered conditions).
        episodes: episodes per condition (the family's first ones).
        seed: the families' data-set seed.
        duration_s: episode length range overriding the families' (None: theirs).
        p_th_values: the paper's and the improved filter's P_th sweep.
        imu_bands_m: the IMU gate's half-band sweep (m).
        max_events: pitch-variation events matched per episode, at most.
        matcher: the scan matcher (scaneval name).
    """

    conditions: tuple[str, ...] = dataclasses.field(default_factory=condition_names)
    episodes: int = 6
    seed: int = 0
    duration_s: tuple[float, float] | None = None
    p_th_values: tuple[float, ...] = P_TH_VALUES
    imu_bands_m: tuple[float, ...] = IMU_BANDS_M
    max_events: int = 4
    matcher: str = "icp"

    def __post_init__(self) -> None:
        if self.episodes < 1:
            raise ValueError(f"episodes: expected an integer >= 1, got {self.episodes}")
        for value in (FilterParams().p_th, ImprovedParams().p_th):
            if value not in self.p_th_values:
                raise ValueError(f"p_th_values: must hold the operating point {value}")
        if DEFAULT_IMU_BAND_M not in self.imu_bands_m:
            raise ValueError(f"imu_bands_m: must hold the operating point {DEFAULT_IMU_BAND_M}")

    @classmethod
    def quick(cls, **overrides: object) -> StressConfig:
        """A smoke run: one short episode per condition, coarse sweeps."""
        settings = dict(
            episodes=1, duration_s=(6.0, 8.0), p_th_values=(0.0, 0.5, 0.8, 0.95),
            imu_bands_m=(0.05, 0.2, 0.5), max_events=2,
        )  # fmt: skip
        return cls(**{**settings, **overrides})


@dataclasses.dataclass
class Cell:
    """What one method gave on one condition, summed over its episodes."""

    thresholds: tuple[float, ...]
    operating_point: float
    counts: np.ndarray  # (k, 3): tp, fp, fn per threshold
    static: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros(2, np.int64))
    dynamic: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros(2, np.int64))
    translation_m: list[float] = dataclasses.field(default_factory=list)
    rotation_deg: list[float] = dataclasses.field(default_factory=list)

    def summary(self) -> dict:
        """The cell's figures (NaN where there is nothing to count)."""
        return {
            **pr_curve(self.thresholds, *self.counts.T).at(self.operating_point),
            "static_removed": _share(self.static),
            "dynamic_removed": _share(self.dynamic),
            "matching_events": len(self.translation_m),
            "translation_error_m": _mean(self.translation_m),
            "rotation_error_deg": _mean(self.rotation_deg),
        }


def _share(pair: np.ndarray) -> float:
    return float(pair[0] / pair[1]) if pair[1] else math.nan


def _mean(values: list[float]) -> float:
    return float(np.mean(values)) if values else math.nan


def _summed(frames, masks) -> np.ndarray:
    """(tp, fp, fn) of masks over frames, as one row of a sweep."""
    return sum(confusion(f, m) for f, m in zip(frames, masks, strict=True))[None, :]


def _masks_and_counts(
    method: str, recording: Recording, config: StressConfig
) -> tuple[list[np.ndarray], tuple[float, ...], float, np.ndarray]:
    """One method on one recording: its removed masks at the operating point, the swept
    values, the operating point and the (tp, fp, fn) per value."""
    frames = recording.frames
    if method in ("truth", "none"):  # one point each: (recall 1, precision 1) or (0, 1)
        masks = [beam_truth(f)[0] if method == "truth" else np.zeros(len(f.labels), bool)
                 for f in frames]  # fmt: skip
        return masks, (0.0,), 0.0, _summed(frames, masks)
    if method == "improved":
        op, values = ImprovedParams().p_th, config.p_th_values
        improved = improved_filter(recording)
        improved.reset()
        scores = [improved.process(f).scores for f in frames]
        counts = np.array([sum(confusion(f, s > v) for f, s in zip(frames, scores, strict=True))
                           for v in values])  # fmt: skip
        return [s > op for s in scores], values, op, counts
    if method == "paper":
        op, values = FilterParams().p_th, config.p_th_values
        make: Callable = lambda v: frame_filter("paper", METHODS["paper"], p_th=v)  # noqa: E731
    else:
        op, values = DEFAULT_IMU_BAND_M, config.imu_bands_m
        make = lambda v: family_filter("imu_gate", v, recording)  # noqa: E731
    counts = sweep_counts(recording, make, values)
    at_op = make(op)
    at_op.reset()
    return [at_op.process(f).removed for f in frames], values, op, counts


def _matching_errors(recording: Recording, masks: list[np.ndarray], config: StressConfig):
    """(translation m, rotation deg) of each event's alignment with ``masks`` dropped."""
    frames, errors = recording.frames, []
    for onset, peak in pitch_variation_runs(frames)[: config.max_events]:
        source, target = frames[peak], frames[onset - 1]
        match = MATCHERS[config.matcher](
            scan_points(source.scan, masks[peak]), scan_points(target.scan, masks[onset - 1])
        )
        error = compose(invert(true_relative_pose(target, source)), match.pose)
        errors.append((float(np.hypot(error[0], error[1])), float(np.degrees(abs(error[2])))))
    return errors


def condition_recordings(name: str, config: StressConfig, progress: bool = False):
    """The recorded episodes of one condition (a generator, one episode at a time)."""
    ranges = condition_ranges(name)
    if config.duration_s is not None:
        ranges = dataclasses.replace(
            ranges, episode=dataclasses.replace(ranges.episode, duration_s=config.duration_s)
        )
    for k in tqdm(range(config.episodes), desc=name, unit="episode", disable=not progress,
                  leave=False):  # fmt: skip
        yield episode_recording(config.seed, k, ranges, name)


def episode_recording(seed: int, episode: int, ranges: Randomization, name: str) -> Recording:
    """Episode ``episode`` of a family, simulated once and kept."""
    draw = draw_episode(seed, episode, ranges)
    scenario = scenario_from_table(draw.scenario_table, source=f"{name} episode {episode}")
    scenario = dataclasses.replace(scenario, name=f"{name}/episode_{episode}")
    return record(scenario, draw.house, scenario.seed)


def run_condition(name: str, config: StressConfig, progress: bool = False) -> dict:
    """Every method on one condition's episodes: the row of the matrix."""
    cells: dict[str, Cell] = {}
    row = {"episodes": 0, "frames": 0, "positives": 0, "falls": 0, "max_abs_pitch_deg": 0.0,
           "labels": dict.fromkeys((b.name for b in BeamLabel), 0)}  # fmt: skip
    for recording in condition_recordings(name, config, progress):
        row["episodes"] += 1
        row["frames"] += len(recording.frames)
        row["falls"] += recording.summary.fell
        peak = recording.summary.max_abs_pitch_deg
        row["max_abs_pitch_deg"] = max(row["max_abs_pitch_deg"], peak)
        for label, count in recording.summary.beams_per_label.items():
            row["labels"][label] += count
        row["positives"] += sum(
            int(np.count_nonzero(np.logical_and(*beam_truth(f)))) for f in recording.frames
        )
        for method in METHODS:
            masks, values, op, counts = _masks_and_counts(method, recording, config)
            cell = cells.setdefault(method, Cell(values, op, np.zeros_like(counts)))
            cell.counts += counts
            for frame, mask in zip(recording.frames, masks, strict=True):
                static = with_label(frame.labels, BeamLabel.STATIC) & np.isfinite(frame.scan.ranges)
                cell.static += (np.count_nonzero(mask & static), np.count_nonzero(static))
                cell.dynamic += dynamic_removed(frame, mask)
            for translation, rotation in _matching_errors(recording, masks, config):
                cell.translation_m.append(translation)
                cell.rotation_deg.append(rotation)
    return {**row, "methods": {m: cells[m].summary() for m in METHODS}}


def run_stress(config: StressConfig, progress: bool = True) -> dict:
    """The whole matrix, JSON-ready."""
    rows = {}
    for name in tqdm(config.conditions, desc="stress matrix", unit="condition",
                     disable=not progress):  # fmt: skip
        rows[name] = run_condition(name, config, progress)
    return {"config": dataclasses.asdict(config), "methods": METHODS, "conditions": rows}
