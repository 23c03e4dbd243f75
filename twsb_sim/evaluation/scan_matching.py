"""The scan-matching experiment of section IV-D, with the truth only a simulator has.

An **event** is where a pitch variation occurs, from ground truth: the first frame of a
run of consecutive frames that hold at least one pitch-variation beam with a finite
range (the paper's "frame where it occurs"). Its **source** scan is that frame, its
**target** the frame just before (which holds none). A second variant, ``peak``, aligns
the run's frame with the most pitch-variation beams onto that same target. Each matcher
aligns source onto target under three conditions: the raw scans (without the filter),
the filtered scans (the Pitch Variation Filter run over the whole sequence, its removed
beams dropped from both scans), and an oracle that drops every pitch-variation beam by
its label (the most any filter could do). Per alignment:

- the Chamfer distance (eq. 6, m^2) between the aligned source and the target, as the
  paper reports it;
- the same at the TRUE relative pose (what the best alignment would give);
- the error of the aligned pose against the true relative sensor pose: translation (m)
  and rotation (rad) of ``true^-1 * estimate``.

The matchers start from the identity, as for consecutive scans without odometry.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import numpy as np

from scaneval.geometry import compose, invert, scan_points, transform_points
from scaneval.matching import MATCHERS
from scaneval.metrics import chamfer_distance
from twsb_sim.evaluation.passes import beam_truth
from twsb_sim.frame import Frame
from twsb_sim.robot_inputs import sensor_pose_2d

CONDITIONS: tuple[str, ...] = ("without", "with", "oracle")  # no filter, the PVF, the truth


@dataclasses.dataclass(frozen=True)
class Alignment:
    """One matcher on one event under one condition.

    Attributes:
        kind: ``onset`` (the event's first frame) or ``peak`` (its frame with the most
            pitch-variation beams; the target is still the frame before the event).
        source_index, target_index: the frames aligned (source onto target).
        matcher: ``icp``, ``ndt`` or ``hsm``.
        condition: ``without`` (raw scans), ``with`` (the Pitch Variation Filter's removed
            beams dropped from both) or ``oracle`` (every pitch-variation beam dropped,
            from the labels: what a perfect filter would give).
        chamfer_m2: eq. 6 after alignment, m^2.
        chamfer_at_truth_m2: eq. 6 at the true relative pose, m^2.
        translation_error_m: of the aligned pose against the truth, m.
        rotation_error_rad: the same, rad (absolute).
        converged: what the matcher reported.
        pv_beams: pitch-variation beams in the source scan.
        removed_pv_beams: of those, dropped under this condition.
    """

    kind: str
    source_index: int
    target_index: int
    matcher: str
    condition: str
    chamfer_m2: float
    chamfer_at_truth_m2: float
    translation_error_m: float
    rotation_error_rad: float
    converged: bool
    pv_beams: int
    removed_pv_beams: int


def pitch_variation_runs(frames: Sequence[Frame]) -> list[tuple[int, int]]:
    """Each run of frames with pitch-variation beams: (first frame, frame with the most).

    A frame counts when at least one beam with a finite range is a pitch-variation
    point. A run that starts at frame 0 has no frame before it and is left out.
    """
    counts = [int(np.logical_and(*beam_truth(f)).sum()) for f in frames]
    runs = []
    for k in range(1, len(frames)):
        if counts[k] and not counts[k - 1]:
            end = k
            while end + 1 < len(frames) and counts[end + 1]:
                end += 1
            runs.append((k, k + int(np.argmax(counts[k : end + 1]))))
    return runs


def true_relative_pose(target: Frame, source: Frame) -> np.ndarray:
    """The source sensor's SE(2) pose in the target sensor's frame, from the truth."""
    return compose(invert(sensor_pose_2d(target.truth)), sensor_pose_2d(source.truth))


def align(
    frames: Sequence[Frame],
    removed: np.ndarray,
    kind: str,
    source_index: int,
    target_index: int,
    matchers: Sequence[str],
) -> list[Alignment]:
    """Align one source frame onto one target with every matcher under every condition.

    Args:
        frames: the run's frames.
        removed: the filter's removed mask per frame, ``(frames, n)``.
        kind: ``onset`` or ``peak`` (recorded in the result).
        source_index, target_index: the frames.
        matchers: names in :data:`scaneval.matching.MATCHERS`.
    """
    source, target = frames[source_index], frames[target_index]
    truth = true_relative_pose(target, source)
    pv = np.logical_and(*beam_truth(source))
    drops = {
        "without": (None, None),
        "with": (removed[source_index], removed[target_index]),
        "oracle": (beam_truth(source)[0], beam_truth(target)[0]),
    }
    alignments = []
    for condition, (drop_source, drop_target) in drops.items():
        source_xy = scan_points(source.scan, drop_source)
        target_xy = scan_points(target.scan, drop_target)
        at_truth = chamfer_distance(transform_points(source_xy, truth), target_xy)
        for name in matchers:
            match = MATCHERS[name](source_xy, target_xy)
            error = compose(invert(truth), match.pose)
            aligned = transform_points(source_xy, match.pose)
            alignments.append(
                Alignment(
                    kind=kind,
                    source_index=source_index,
                    target_index=target_index,
                    matcher=name,
                    condition=condition,
                    chamfer_m2=chamfer_distance(aligned, target_xy),
                    chamfer_at_truth_m2=at_truth,
                    translation_error_m=float(np.hypot(error[0], error[1])),
                    rotation_error_rad=float(abs(error[2])),
                    converged=bool(match.converged),
                    pv_beams=int(pv.sum()),
                    removed_pv_beams=0 if drop_source is None else int((pv & drop_source).sum()),
                )
            )
    return alignments


def summarize(alignments: Sequence[Alignment], matchers: Sequence[str]) -> dict:
    """Per matcher and condition: means and medians; normalized CD and reductions.

    The normalized mean Chamfer distance divides by the mean without the filter (paper
    Fig. 6: without = 1); a reduction is ``1 - condition / without``, in %.
    """
    summary = {}
    for name in matchers:
        per = {}
        for condition in CONDITIONS:
            rows = [a for a in alignments if a.matcher == name and a.condition == condition]
            values = lambda field, rows=rows: np.array([getattr(a, field) for a in rows])  # noqa: E731
            pv, dropped = values("pv_beams").sum(), values("removed_pv_beams").sum()
            per[condition] = {
                "alignments": len(rows),
                "mean_chamfer_m2": _mean(values("chamfer_m2")),
                "median_chamfer_m2": _median(values("chamfer_m2")),
                "mean_chamfer_at_truth_m2": _mean(values("chamfer_at_truth_m2")),
                "mean_translation_error_m": _mean(values("translation_error_m")),
                "median_translation_error_m": _median(values("translation_error_m")),
                "mean_rotation_error_deg": _mean(np.degrees(values("rotation_error_rad"))),
                "median_rotation_error_deg": _median(np.degrees(values("rotation_error_rad"))),
                "converged_share": _mean(values("converged").astype(float)),
                "pv_beams_removed_share": float(dropped / pv) if pv else float("nan"),
            }
        without = per["without"]["mean_chamfer_m2"]
        normalized = {c: per[c]["mean_chamfer_m2"] / without for c in CONDITIONS}
        summary[name] = {
            **per,
            "normalized_mean_chamfer": normalized,
            "chamfer_reduction_pct": 100.0 * (1.0 - normalized["with"]),
            "oracle_chamfer_reduction_pct": 100.0 * (1.0 - normalized["oracle"]),
        }
    return summary


def _mean(values: np.ndarray) -> float:
    values = values[np.isfinite(values)]
    return float(values.mean()) if values.size else float("nan")


def _median(values: np.ndarray) -> float:
    values = values[np.isfinite(values)]
    return float(np.median(values)) if values.size else float("nan")
