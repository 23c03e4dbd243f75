"""Passes of filters over a recording: threshold sweeps, and the timed operating-point pass.

Every pass replays the stored frames of one simulated run; nothing is simulated again.
A sweep builds a fresh filter per threshold and runs it over the whole sequence (the
P_th sweep is run afresh per value), summing per-beam counts over the beams whose input
range is finite; a filter whose state does not depend on the threshold and that removes
exactly the beams scoring above it gives every threshold in one pass.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable, Mapping, Sequence

import numpy as np
from tqdm import tqdm

from pvfilter import FilterResult
from twsb_sim.evaluation.recording import Recording
from twsb_sim.frame import Frame
from twsb_sim.frame_filter import FrameFilter
from twsb_sim.labels import BeamLabel, is_pitch_variation, with_label


def beam_truth(frame: Frame) -> tuple[np.ndarray, np.ndarray]:
    """Per beam: is it a pitch-variation point, and is it scored.

    A beam is scored when its input range is finite and it did not hit a moving object:
    DYNAMIC beams a filter removes are neither hits nor false alarms for pitch variation
    (:func:`dynamic_removed` counts them apart).
    """
    scored = np.isfinite(frame.scan.ranges) & ~with_label(frame.labels, BeamLabel.DYNAMIC)
    return is_pitch_variation(frame.labels), scored


def dynamic_removed(frame: Frame, removed: np.ndarray) -> tuple[int, int]:
    """(DYNAMIC beams removed, DYNAMIC beams with a finite range) of one mask on one frame."""
    dynamic = with_label(frame.labels, BeamLabel.DYNAMIC) & np.isfinite(frame.scan.ranges)
    return int(np.count_nonzero(removed & dynamic)), int(np.count_nonzero(dynamic))


def confusion(frame: Frame, removed: np.ndarray) -> np.ndarray:
    """(tp, fp, fn) of one mask on one frame, over its scored beams (:func:`beam_truth`)."""
    positive, finite = beam_truth(frame)
    predicted = removed & finite
    positive = positive & finite
    tp = np.count_nonzero(predicted & positive)
    return np.array([tp, np.count_nonzero(predicted) - tp, np.count_nonzero(positive) - tp])


def run_filter(frame_filter: FrameFilter, frames: Sequence[Frame]) -> np.ndarray:
    """Run a filter over frames from a reset; summed (tp, fp, fn)."""
    frame_filter.reset()
    counts = np.zeros(3, dtype=np.int64)
    for frame in frames:
        counts += confusion(frame, frame_filter.process(frame).removed)
    return counts


def sweep_counts(
    recording: Recording,
    make_filter: Callable[[float], FrameFilter],
    thresholds: Sequence[float],
    progress: bool = False,
    desc: str = "",
) -> np.ndarray:
    """(tp, fp, fn) per threshold, shape ``(k, 3)``: a fresh filter per threshold.

    Args:
        recording: the frames to replay.
        make_filter: builds the filter for one threshold value.
        thresholds: the swept values.
        progress: show a progress bar over the thresholds.
        desc: its label.
    """
    values = tqdm(thresholds, desc=desc, unit="value", disable=not progress, leave=False)
    return np.array([run_filter(make_filter(v), recording.frames) for v in values])


def score_sweep_counts(
    recording: Recording, frame_filter: FrameFilter, thresholds: Sequence[float]
) -> np.ndarray:
    """(tp, fp, fn) per threshold, shape ``(k, 3)``, from one pass of a filter whose
    state does not depend on the threshold and that removes the beams scoring above it.

    Args:
        recording: the frames to replay.
        frame_filter: a filter whose result's ``scores`` say at which thresholds each beam
            is removed (a ``one_pass`` filter of the registry).
        thresholds: the swept values; a beam is removed at ``v`` when its score is ``> v``.
    """
    frame_filter.reset()
    values = np.asarray(thresholds, dtype=np.float64)
    counts = np.zeros((values.size, 3), dtype=np.int64)
    for frame in recording.frames:
        scores = frame_filter.process(frame).scores
        masks = scores[None, :] > values[:, None]
        counts += [confusion(frame, mask) for mask in masks]
    return counts


@dataclasses.dataclass(frozen=True, eq=False)
class OperatingPass:
    """What the timed pass of every method at its operating point leaves.

    Attributes:
        seconds: per method name, the wall time of each ``process`` call, s, ``(frames,)``.
        counts: per method name, summed (tp, fp, fn).
        removed: per method name, the removed mask of every frame, ``(frames, n)``.
        pvf_results: the paper filter's full result per frame (for the diagnosis), from
            the filter named ``pvf_name``.
    """

    seconds: dict[str, np.ndarray]
    counts: dict[str, np.ndarray]
    removed: dict[str, np.ndarray]
    pvf_results: tuple[FilterResult, ...]


def operating_pass(
    recording: Recording, filters: Mapping[str, FrameFilter], pvf_name: str
) -> OperatingPass:
    """Run every filter over the frames, interleaved per frame, timing each call.

    Interleaving puts every filter under the same machine load at the same moment, so
    their rates compare within the run even on a shared machine.

    Args:
        recording: the frames.
        filters: name -> filter at its operating point.
        pvf_name: the name of the paper filter whose results are kept.
    """
    for frame_filter in filters.values():
        frame_filter.reset()
    n_frames = len(recording.frames)
    seconds = {name: np.zeros(n_frames) for name in filters}
    counts = {name: np.zeros(3, dtype=np.int64) for name in filters}
    removed = {name: [] for name in filters}
    results: list[FilterResult] = []
    clock = time.perf_counter
    for k, frame in enumerate(recording.frames):
        for name, frame_filter in filters.items():
            start = clock()
            result = frame_filter.process(frame)
            seconds[name][k] = clock() - start
            counts[name] += confusion(frame, result.removed)
            removed[name].append(result.removed)
            if name == pvf_name:
                results.append(result)
    stacked = {name: np.array(masks, dtype=bool) for name, masks in removed.items()}
    return OperatingPass(seconds, counts, stacked, tuple(results))
