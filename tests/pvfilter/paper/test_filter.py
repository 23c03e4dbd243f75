"""PitchVariationFilter.process: the filter contract, records, modes, reset."""

import math

import numpy as np
import pytest

from pvfilter import FilterParams, FilterResult, PitchVariationFilter, Scan
from pvfilter.synthetic import cross_line, room_segments, segment_scan

WALLS = room_segments(5.0, 5.0, 3.0, 3.0)
WITH_LINE = np.concatenate((WALLS, cross_line(1.0, 0.5)))


def first_scan_with_line(pvf):
    pvf.process(segment_scan(WALLS, stamp=0.0))
    return pvf.process(segment_scan(WITH_LINE, stamp=0.1))


def test_result_follows_the_contract():
    result = first_scan_with_line(PitchVariationFilter())
    scan = segment_scan(WITH_LINE)
    assert isinstance(result, FilterResult)
    assert result.removed.dtype == bool and result.removed.shape == (720,)
    assert result.scores.dtype == np.float64 and result.scores.shape == (720,)
    assert isinstance(result.scan, Scan) and len(result.scan) == 720
    assert np.isnan(result.scan.ranges[result.removed]).all()
    np.testing.assert_array_equal(result.scan.ranges[~result.removed], scan.ranges[~result.removed])
    assert result.scan.stamp == 0.1
    on_line = np.isfinite(segment_scan(cross_line(1.0, 0.5)).ranges)
    np.testing.assert_array_equal(result.removed, on_line)


def test_scores_are_the_cluster_p_pv_and_zero_elsewhere():
    result = first_scan_with_line(PitchVariationFilter())
    line, walls = result.clusters[1], result.clusters[0]  # in order of first beam
    assert line.detected and not walls.detected
    assert (result.scores[line.indices] == line.p_pv).all()
    assert math.isnan(walls.p_pv)  # skipped by the v_th gate
    assert (result.scores[walls.indices] == 0.0).all()
    clustered = np.concatenate([c.indices for c in result.clusters])
    assert (np.delete(result.scores, clustered) == 0.0).all()


def test_records_carry_the_per_cluster_values():
    result = first_scan_with_line(PitchVariationFilter())
    line = result.clusters[1]
    assert line.size == len(line.indices) == int(result.removed.sum())
    assert line.centroid == pytest.approx((1.0, 0.0), abs=1e-9)
    assert line.v_c == pytest.approx(1.0)
    assert line.p_theta == pytest.approx(math.exp(-0.5))
    assert line.p_pv == pytest.approx(1.0 - line.p_theta * line.p_likelihood)
    assert line.removed and not line.tracked


def test_parameters_from_the_design_example_are_used():
    pvf = PitchVariationFilter(FilterParams(p_th=0.7, sigma_l=0.5))
    assert pvf.params.p_th == 0.7
    assert PitchVariationFilter().params == FilterParams()


def test_p_th_one_removes_nothing():
    result = first_scan_with_line(PitchVariationFilter(FilterParams(p_th=1.0)))
    assert not result.removed.any()


def test_reset_forgets_the_tracking_queue_and_the_previous_scan():
    pvf = PitchVariationFilter()
    first_scan_with_line(pvf)
    pvf.reset()
    # the drifted line would be tracked; after the reset there is no history at all
    result = pvf.process(segment_scan(np.concatenate((WALLS, cross_line(1.1, 0.5)))))
    assert not result.removed.any()


@pytest.mark.parametrize("mode", ["scan_order", "radius"])
def test_both_clustering_modes_remove_the_line(mode):
    result = first_scan_with_line(PitchVariationFilter(FilterParams(clustering=mode)))
    on_line = np.isfinite(segment_scan(cross_line(1.0, 0.5)).ranges)
    np.testing.assert_array_equal(result.removed, on_line)
