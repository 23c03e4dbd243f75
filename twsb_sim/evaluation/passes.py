"""Passes of methods over a recording: threshold sweeps, and the timed operating-point pass.

Every pass replays the stored frames of one simulated run; nothing is simulated again.
A sweep builds a fresh method per threshold and runs it over the whole sequence
(DESIGN.md: the P_th sweep is run afresh per value), summing per-beam counts over the
beams whose input range is finite.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable, Mapping, Sequence

import numpy as np
from tqdm import tqdm

from pvfilter import FilterResult
from twsb_sim.evaluation.methods import Method, PvfMethod
from twsb_sim.evaluation.recording import Recording
from twsb_sim.frame import Frame
from twsb_sim.labels import is_pitch_variation


def beam_truth(frame: Frame) -> tuple[np.ndarray, np.ndarray]:
    """Per beam: is it a pitch-variation point, and is its input range finite."""
    return is_pitch_variation(frame.labels), np.isfinite(frame.scan.ranges)


def confusion(frame: Frame, removed: np.ndarray) -> np.ndarray:
    """(tp, fp, fn) of one mask on one frame, over its finite beams."""
    positive, finite = beam_truth(frame)
    predicted = removed & finite
    positive = positive & finite
    tp = np.count_nonzero(predicted & positive)
    return np.array([tp, np.count_nonzero(predicted) - tp, np.count_nonzero(positive) - tp])


def run_method(method: Method, frames: Sequence[Frame]) -> np.ndarray:
    """Run a method over frames from a reset; summed (tp, fp, fn)."""
    method.reset()
    counts = np.zeros(3, dtype=np.int64)
    for frame in frames:
        counts += confusion(frame, np.asarray(method.process(frame), dtype=bool))
    return counts


def sweep_counts(
    recording: Recording,
    make_method: Callable[[float], Method],
    thresholds: Sequence[float],
    progress: bool = False,
    desc: str = "",
) -> np.ndarray:
    """(tp, fp, fn) per threshold, shape ``(k, 3)``: a fresh method per threshold.

    Args:
        recording: the frames to replay.
        make_method: builds the method for one threshold value.
        thresholds: the swept values.
        progress: show a progress bar over the thresholds.
        desc: its label.
    """
    values = tqdm(thresholds, desc=desc, unit="value", disable=not progress, leave=False)
    return np.array([run_method(make_method(v), recording.frames) for v in values])


def score_sweep_counts(
    recording: Recording, method: Method, thresholds: Sequence[float]
) -> np.ndarray:
    """(tp, fp, fn) per threshold, shape ``(k, 3)``, from one pass of a method whose
    state does not depend on the threshold and that removes the beams scoring above it.

    Args:
        recording: the frames to replay.
        method: has ``beam_scores()``, per beam after each ``process`` (NaN: never removed).
        thresholds: the swept values; a beam is removed at ``v`` when its score is ``> v``.
    """
    method.reset()
    values = np.asarray(thresholds, dtype=np.float64)
    counts = np.zeros((values.size, 3), dtype=np.int64)
    for frame in recording.frames:
        method.process(frame)
        with np.errstate(invalid="ignore"):
            masks = method.beam_scores()[None, :] > values[:, None]
        counts += [confusion(frame, mask) for mask in masks]
    return counts


@dataclasses.dataclass(frozen=True, eq=False)
class OperatingPass:
    """What the timed pass of every method at its operating point leaves.

    Attributes:
        seconds: per method name, the wall time of each ``process`` call, s, ``(frames,)``.
        counts: per method name, summed (tp, fp, fn).
        removed: per method name, the removed mask of every frame, ``(frames, n)``.
        pvf_results: the Pitch Variation Filter's full result per frame (for the
            diagnosis), from the method named ``pvf_name``.
    """

    seconds: dict[str, np.ndarray]
    counts: dict[str, np.ndarray]
    removed: dict[str, np.ndarray]
    pvf_results: tuple[FilterResult, ...]


def operating_pass(
    recording: Recording, methods: Mapping[str, Method], pvf_name: str
) -> OperatingPass:
    """Run every method over the frames, interleaved per frame, timing each call.

    Interleaving puts every method under the same machine load at the same moment, so
    their rates compare within the run even on a shared machine.

    Args:
        recording: the frames.
        methods: name -> method at its operating point.
        pvf_name: the name of the :class:`PvfMethod` whose results are kept.
    """
    for method in methods.values():
        method.reset()
    n_frames = len(recording.frames)
    seconds = {name: np.zeros(n_frames) for name in methods}
    counts = {name: np.zeros(3, dtype=np.int64) for name in methods}
    removed = {name: [] for name in methods}
    results: list[FilterResult] = []
    pvf = methods[pvf_name]
    assert isinstance(pvf, PvfMethod)
    clock = time.perf_counter
    for k, frame in enumerate(recording.frames):
        for name, method in methods.items():
            start = clock()
            mask = method.process(frame)
            seconds[name][k] = clock() - start
            mask = np.asarray(mask, dtype=bool)
            counts[name] += confusion(frame, mask)
            removed[name].append(mask)
        results.append(pvf.last_result)
    stacked = {name: np.array(masks, dtype=bool) for name, masks in removed.items()}
    return OperatingPass(seconds, counts, stacked, tuple(results))
