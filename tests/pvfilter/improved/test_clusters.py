"""Claim scores per beam: a line's returns in front of a view free by silence alone."""

import math
import types

import numpy as np

from pvfilter.improved import ImprovedParams, ImprovedPitchVariationFilter, clusters
from pvfilter.synthetic import BLOCKED_SECTOR, ray_cast, segment_scan

from .conftest import HEIGHT_M

# a room whose wall ahead has a 1.2 m gap, beyond which nothing lies within range: the
# level view is free there by silence alone (world frame, m)
WALLS = np.array(
    [
        [[4.0, -2.5], [4.0, -0.6]],
        [[4.0, 0.6], [4.0, 2.5]],
        [[-2.5, -2.5], [-2.5, 2.5]],
        [[-2.5, 2.5], [4.0, 2.5]],
        [[-2.5, -2.5], [4.0, -2.5]],
    ]
)
PITCH_RAD = math.radians(8.0)  # nose down from frame 12: the floor 1.8 m ahead
FLOOR = np.array(
    [[[HEIGHT_M / math.sin(PITCH_RAD), -10.0], [HEIGHT_M / math.sin(PITCH_RAD), 10.0]]]
)


def run_standing(frames=14, p_th=0.5):
    """The results of a standing sensor's scans, level, pitched from frame 12 to 19 and
    level again, and per frame which beams hit the floor."""
    params = ImprovedParams(lidar_height_m=HEIGHT_M, axle_height_m=HEIGHT_M, p_th=p_th)
    pvf = ImprovedPitchVariationFilter(params)
    results, on_floor = [], []
    for k in range(frames):
        pitched = 12 <= k < 20
        structure = np.concatenate((WALLS, FLOOR)) if pitched else WALLS
        scan = segment_scan(structure, stamp=0.1 * k, noise_m=0.005,
                            rng=np.random.default_rng(k), blocked=BLOCKED_SECTOR)  # fmt: skip
        results.append(pvf.process(scan))
        hit = ray_cast(FLOOR, scan.angles()) < ray_cast(WALLS, scan.angles())
        on_floor.append(hit & np.isfinite(scan.ranges) & pitched)
    return results, on_floor


def test_a_line_ranks_its_returns_in_front_of_silence_below_those_in_front_of_a_wall():
    # the floor line runs across the gap and in front of the wall: one line, one score,
    # taken at SILENT_VIEW_WEIGHT of it where the view behind knew only silence
    results, on_floor = run_standing()
    for result, floor in zip(results[12:], on_floor[12:], strict=True):
        view = result.lines.level_view_m
        silent, walled = floor & np.isposinf(view), floor & np.isfinite(view)
        assert silent.sum() > 20 and walled.sum() > 100
        line_score = result.scores[walled].max()
        assert line_score > 0.9 and np.ptp(result.scores[walled]) == 0.0
        np.testing.assert_allclose(result.scores[silent], clusters.SILENT_VIEW_WEIGHT * line_score)
        assert result.scores[silent].max() < line_score - 0.1  # ranked below
        assert result.removed[floor].all()  # at the default p_th, removed all the same
        np.testing.assert_array_equal(result.removed, result.scores > result.lines.p_th)


def test_the_weight_changes_the_scores_and_nothing_the_filter_carries(monkeypatch):
    weighed, _ = run_standing(frames=28)  # level again after the tilt: the view learns
    monkeypatch.setattr(clusters, "SILENT_VIEW_WEIGHT", 1.0)
    unweighed, _ = run_standing(frames=28)
    assert any(
        not np.array_equal(a.scores, b.scores) for a, b in zip(weighed, unweighed, strict=True)
    )
    for a, b in zip(weighed, unweighed, strict=True):
        np.testing.assert_array_equal(a.lines.level_view_m, b.lines.level_view_m)
        np.testing.assert_array_equal(a.lines.segment_scores.scores, b.lines.segment_scores.scores)
        assert a.lines.tilted == b.lines.tilted and a.lines.motion == b.lines.motion
        differ = a.scores != b.scores  # only where the view is free by silence
        assert not np.any(differ & ~np.isposinf(a.lines.level_view_m))


def test_a_detected_cluster_holds_only_the_returns_it_removes():
    # at p_th 0.85 the floor line (score 0.99) is detected, and its returns in front of the
    # gap, weighed to 0.79, are not removed: they leave the cluster and join none
    results, on_floor = run_standing(p_th=0.85)
    result, floor = results[12], on_floor[12]
    silent = floor & np.isposinf(result.lines.level_view_m)
    assert silent.sum() > 20 and not result.removed[silent].any()
    assert result.removed[floor & ~silent].all()
    detected = [record for record in result.clusters if record.detected]
    assert len(detected) == 1
    np.testing.assert_array_equal(detected[0].indices, np.flatnonzero(result.removed))
    assert detected[0].size == np.count_nonzero(result.removed)
    clustered = np.concatenate([record.indices for record in result.clusters])
    assert not np.isin(np.flatnonzero(silent), clustered).any()


def test_only_a_view_free_by_silence_weighs_a_claim_down():
    # a surface seen (2 m), free by silence (+inf), unknown (NaN: never new, nothing known)
    segments = types.SimpleNamespace(beams=np.array([0, 1, 2, 3]))
    view = np.array([2.0, np.inf, np.nan, np.inf, 5.0])
    weighed = clusters._weighed_by_view(np.ones(4), segments, view)
    weight = clusters.SILENT_VIEW_WEIGHT
    np.testing.assert_array_equal(weighed, [1.0, weight, 1.0, weight])
    assert clusters._weighed_by_view(np.ones(4), segments, None).tolist() == [1.0] * 4
