"""The numbers printed at the end of a run, gathered frame by frame."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from twsb_sim.frame import Frame
from twsb_sim.labels import BeamLabel, is_pitch_variation, with_label


@dataclass
class FilterCounts:
    """Per-beam confusion counts of a filter against ground truth.

    Counted over beams whose input range is finite (docs/conventions.md); positives are the
    pitch-variation labels, a beam is predicted positive when the filter removed it.
    Beams on moving objects (DYNAMIC) are neither: the ones removed are counted apart.
    """

    true_positives: int = 0
    false_positives: int = 0
    false_negatives: int = 0
    true_negatives: int = 0
    dynamic_removed: int = 0  # DYNAMIC beams the filter removed
    dynamic_beams: int = 0  # DYNAMIC beams with a finite range

    @property
    def precision(self) -> float:
        predicted = self.true_positives + self.false_positives
        return self.true_positives / predicted if predicted else 1.0

    @property
    def recall(self) -> float:
        actual = self.true_positives + self.false_negatives
        return self.true_positives / actual if actual else math.nan

    def add(self, ranges: np.ndarray, labels: np.ndarray, removed: np.ndarray) -> None:
        finite = np.isfinite(ranges)
        dynamic = finite & with_label(labels, BeamLabel.DYNAMIC)
        removed = np.asarray(removed, dtype=bool)
        self.dynamic_removed += int(np.count_nonzero(removed & dynamic))
        self.dynamic_beams += int(np.count_nonzero(dynamic))
        finite &= ~dynamic
        truth = is_pitch_variation(labels)[finite]
        predicted = removed[finite]
        self.true_positives += int(np.count_nonzero(truth & predicted))
        self.false_positives += int(np.count_nonzero(~truth & predicted))
        self.false_negatives += int(np.count_nonzero(truth & ~predicted))
        self.true_negatives += int(np.count_nonzero(~truth & ~predicted))


@dataclass
class FilterTally:
    """What one filter removed over a run, against the ground truth."""

    name: str
    counts: FilterCounts
    removed_beams: int = 0

    def format(self, width: int) -> str:
        c = self.counts
        return (
            f"{self.name:<{width}} removed {self.removed_beams} beams, precision "
            f"{c.precision:.3f}, recall {c.recall:.3f} "
            f"(TP {c.true_positives}, FP {c.false_positives}, FN {c.false_negatives})"
        )


# where a reader of the summary learns why the filters differ
WHY_FILTERS_DIFFER = "docs/filters.md#why-the-two-filters-differ"
_LABEL_NAMES = tuple(BeamLabel(code).name for code in range(len(BeamLabel)))  # by code


@dataclass
class RunSummary:
    """What a run did, in numbers (all times in simulated seconds unless said)."""

    scenario: str
    seed: int
    house: str
    simulated_s: float = 0.0
    wall_s: float = 0.0
    frames: int = 0
    max_abs_pitch_deg: float = 0.0
    beams_per_label: dict[str, int] = field(
        default_factory=lambda: {lb.name: 0 for lb in BeamLabel}
    )
    pitch_variation_frames: int = 0  # frames with at least one pitch-variation beam
    max_pitch_variation_beams: int = 0  # in one frame
    mean_pitch_variation_beams: float = 0.0  # per frame
    fell: bool = False
    end_reason: str = "completed"  # "completed", "fell: ...", "interrupted"
    mujoco_warnings: dict[str, int] = field(default_factory=dict)  # MuJoCo's warnings by name
    filter_name: str | None = None
    filter_counts: FilterCounts | None = None
    filter_removed_beams: int = 0
    compared: list[FilterTally] = field(default_factory=list)  # other filters, same frames

    @property
    def real_time_factor(self) -> float:
        return self.simulated_s / self.wall_s if self.wall_s > 0 else math.inf

    def add_frame(self, frame: Frame, removed: np.ndarray | None) -> None:
        """Fold one frame (and the filter's mask for it) into the totals."""
        self.frames += 1
        self.simulated_s = max(self.simulated_s, frame.received_s)
        self.max_abs_pitch_deg = max(
            self.max_abs_pitch_deg, abs(math.degrees(frame.truth.pitch_rad))
        )
        counts = np.bincount(frame.labels, minlength=len(BeamLabel)).tolist()
        for name, count in zip(_LABEL_NAMES, counts, strict=False):
            self.beams_per_label[name] += count
        n_pv = counts[BeamLabel.FLOOR] + counts[BeamLabel.CEILING] + counts[BeamLabel.HORIZONTAL]
        self.pitch_variation_frames += n_pv > 0
        self.max_pitch_variation_beams = max(self.max_pitch_variation_beams, n_pv)
        self.mean_pitch_variation_beams += (n_pv - self.mean_pitch_variation_beams) / self.frames
        if removed is not None:
            self.filter_counts = self.filter_counts or FilterCounts()
            self.filter_counts.add(frame.scan.ranges, frame.labels, removed)
            self.filter_removed_beams += int(np.count_nonzero(removed))

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready values, derived ratios included."""
        values = asdict(self)
        values["real_time_factor"] = self.real_time_factor
        if self.filter_counts is not None:
            values["filter_counts"]["precision"] = self.filter_counts.precision
            values["filter_counts"]["recall"] = self.filter_counts.recall
        for tally, row in zip(self.compared, values["compared"], strict=True):
            row["counts"]["precision"] = tally.counts.precision
            row["counts"]["recall"] = tally.counts.recall
        return values

    def format(self) -> str:
        """A short human-readable report."""
        lines = [
            f"scenario        {self.scenario} (seed {self.seed}, {self.house})",
            f"simulated       {self.simulated_s:.1f} s in {self.wall_s:.1f} s wall"
            f" ({_times(self.real_time_factor)} real time)",
            f"frames          {self.frames}",
            f"max |pitch|     {self.max_abs_pitch_deg:.1f} deg",
            "beams by label  "
            + ", ".join(f"{k} {v}" for k, v in self.beams_per_label.items() if v),
            f"pitch-variation beams per frame: mean {self.mean_pitch_variation_beams:.1f},"
            f" max {self.max_pitch_variation_beams}, in {self.pitch_variation_frames} frames",
            f"falls           {1 if self.fell else 0}",
            f"ended           {self.end_reason}",
        ]
        if self.mujoco_warnings:
            lines.append(
                "MuJoCo warnings " + ", ".join(f"{k} x{v}" for k, v in self.mujoco_warnings.items())
            )
        tallies = []
        if self.filter_counts is not None:
            loop = FilterTally(f"{self.filter_name} (in the loop):", self.filter_counts)
            loop.removed_beams = self.filter_removed_beams
            tallies.append(loop)
        tallies += [FilterTally(f"{t.name} (same frames):", t.counts, t.removed_beams)
                    for t in self.compared]  # fmt: skip
        width = max((len(t.name) for t in tallies), default=0)
        for k, tally in enumerate(tallies):
            lines.append(("filter          " if k == 0 else " " * 16) + tally.format(width))
            c = tally.counts
            if c.dynamic_beams:
                lines.append(
                    " " * 16 + f"{'':<{width}} moving objects: removed {c.dynamic_removed} of"
                    f" {c.dynamic_beams} DYNAMIC beams (not counted above)"
                )
        if len(tallies) > 1:
            lines.append(" " * 16 + f"why these differ: {WHY_FILTERS_DIFFER}")
        return "\n".join(lines)


def _times(factor: float) -> str:
    """A real-time factor as the summary prints it: whole below 10x would round a first
    run that compiles the kernels (0.56x) to "1x", faster than it ran."""
    return f"{factor:.0f}x" if factor >= 10.0 else f"{factor:.1f}x"
