"""Sweep, PR and AUC plumbing on tiny synthetic recordings."""

from __future__ import annotations

import numpy as np
import pytest

from pvfilter import FilterParams, FilterResult, PitchVariationFilter
from pvfilter.synthetic import cross_line, room_segments
from scaneval.metrics import pr_curve
from twsb_sim.evaluation.passes import (
    confusion,
    operating_pass,
    run_filter,
    score_sweep_counts,
    sweep_counts,
)
from twsb_sim.evaluation.recording import Recording
from twsb_sim.frame_filter import frame_filter
from twsb_sim.labels import is_pitch_variation
from twsb_sim.summary import RunSummary

ROOM = room_segments(4.0, 4.0, 2.0, 2.0)


def recording_of(frames) -> Recording:
    return Recording(
        sequence="synthetic",
        house="none",
        seed=0,
        frames=tuple(frames),
        geom_names=("wall", "floor"),
        geometry={"lidar_height_m": 0.25, "axle_height_m": 0.08, "lidar_ahead_m": 0.0},
        summary=RunSummary(scenario="synthetic", seed=0, house="none"),
    )


class ScoreFilter:
    """A frame filter removing the beams whose made-up score exceeds a threshold (floor
    0.9, the wall straight ahead 0.6, everything else 0.1); keeps no state."""

    label = "score"

    def __init__(self, threshold: float = 0.0) -> None:
        self.threshold = threshold

    def reset(self) -> None:
        pass

    def process(self, frame) -> FilterResult:
        ahead = np.abs(frame.scan.angles()) < 0.2
        scores = np.where(is_pitch_variation(frame.labels), 0.9, np.where(ahead, 0.6, 0.1))
        return FilterResult(frame.scan, scores > self.threshold, scores)


def datmo(speed):
    return frame_filter("datmo", "DATMO-like", speed_threshold_mps=speed)


def paper(p_th=0.8):
    return frame_filter("paper", "PVF", p_th=p_th)


@pytest.fixture
def floor_then_room(make_frame):
    return recording_of(
        [make_frame(0, ROOM, cross_line(1.0, 0.6)), make_frame(1, ROOM), make_frame(2, ROOM)]
    )


def test_sweep_counts_match_a_hand_count(floor_then_room):
    frames = floor_then_room.frames
    floor = int(is_pitch_variation(frames[0].labels).sum())
    ahead = [
        int(((np.abs(f.scan.angles()) < 0.2) & ~is_pitch_variation(f.labels)).sum()) for f in frames
    ]
    finite = sum(int(np.isfinite(f.scan.ranges).sum()) for f in frames)
    counts = sweep_counts(floor_then_room, ScoreFilter, [0.0, 0.5, 0.95])
    assert counts.tolist() == [
        [floor, finite - floor, 0],
        [floor, sum(ahead), 0],
        [0, 0, floor],
    ]
    curve = pr_curve([0.0, 0.5, 0.95], *counts.T)
    # points (recall, precision): (1, p0), (1, p1), (0, 1); the curve steps down at recall
    # 1 to p0 and runs from (0, 1) to (1, p1): area (1 + p1) / 2
    p1 = floor / (floor + sum(ahead))
    assert curve.auc == pytest.approx((1.0 + p1) / 2.0)


def test_a_score_sweep_equals_a_fresh_filter_per_threshold(floor_then_room):
    thresholds = [0.0, 0.3, 0.7, 1.0]
    one_pass = score_sweep_counts(floor_then_room, ScoreFilter(), thresholds)
    fresh = sweep_counts(floor_then_room, ScoreFilter, thresholds)
    assert np.array_equal(one_pass, fresh)


def test_the_datmo_speed_sweep_in_one_pass_equals_a_fresh_tracker_per_speed(make_frame):
    box = lambda x: np.array([[[x, -0.3], [x, 0.3]], [[x, 0.3], [x + 0.3, 0.3]]])  # noqa: E731
    frames = [make_frame(k, np.concatenate((ROOM, box(1.0 + 0.05 * k)))) for k in range(12)]
    recording = recording_of(frames)
    speeds = [0.05, 0.1, 0.3, 0.45, 0.6, 1.0]
    one_pass = score_sweep_counts(recording, datmo(0.0), speeds)
    fresh = sweep_counts(recording, datmo, speeds)
    assert np.array_equal(one_pass, fresh)
    assert one_pass[:, 1].max() > 0, "the moving box (0.5 m/s) is removed at low speeds"


def test_the_p_th_sweep_runs_the_filter_afresh_per_value(make_frame):
    frames = []
    for k in range(8):  # a floor line appears ahead in frames 3 and 4
        floor = cross_line(1.0 + 0.1 * k, 0.6) if k in (3, 4) else None
        frames.append(make_frame(k, ROOM, floor))
    recording = recording_of(frames)
    values = [0.0, 0.5, 0.8, 0.95]
    counts = sweep_counts(recording, paper, values)
    # each value's counts equal a filter run alone at that value
    for value, row in zip(values, counts, strict=True):
        alone = PitchVariationFilter(FilterParams(p_th=value))
        direct = sum(confusion(f, alone.process(f.scan).removed) for f in frames)
        assert row.tolist() == direct.tolist()
    assert len(set((counts[:, 0] + counts[:, 2]).tolist())) == 1, "positives are fixed"
    assert counts[2, 0] > 0, "Table I finds the floor line that appears from nowhere"


def test_the_timed_pass_counts_like_separate_runs_and_times_every_frame(floor_then_room):
    methods = {"PVF": paper(), "score": ScoreFilter(0.5)}
    timed = operating_pass(floor_then_room, methods, "PVF")
    n = len(floor_then_room.frames)
    for name, method in methods.items():
        assert timed.seconds[name].shape == (n,)
        assert (timed.seconds[name] > 0).all()
        assert timed.counts[name].tolist() == run_filter(method, floor_then_room.frames).tolist()
        assert timed.removed[name].shape == (n, len(floor_then_room.frames[0].scan))
    assert len(timed.pvf_results) == n
