"""Detection (Algorithm 1): eqs. 1-5 against hand computations, and the issue's geometry."""

import math

import numpy as np
import pytest
from scipy.spatial import cKDTree

from pvfilter import FilterParams, cluster_scan, detect_clusters
from pvfilter.paper.detection import (
    angular_confidence,
    cluster_likelihood,
    perpendicular_variance_ratio,
    pitch_variation_probability,
    point_likelihood,
)
from pvfilter.synthetic import cross_line, room_segments, segment_scan

WALLS = room_segments(5.0, 5.0, 3.0, 3.0)


def test_eq1_perpendicular_variance_ratio():
    variances = np.array([[1.0, 3.0], [0.0, 2.0], [2.0, 0.0], [0.0, 0.0]])
    # 3 / (1 + 3), a line across x, a line along x, and coincident points (no direction)
    np.testing.assert_allclose(perpendicular_variance_ratio(variances), [0.75, 1.0, 0.0, 0.0])


def test_eq2_angular_confidence():
    centroids = np.array([[2.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [1.0, math.sqrt(3.0)]])
    # cos^2 = 1, 0, 1, 1/4 at 0, 90, 180 and 60 degrees; sigma_theta = 1
    expected = [math.exp(-0.5), 1.0, math.exp(-0.5), math.exp(-0.125)]
    np.testing.assert_allclose(angular_confidence(centroids, 1.0), expected)
    np.testing.assert_allclose(angular_confidence(centroids[:1], 0.5), [math.exp(-2.0)])


def test_eq3_point_likelihood():
    distances = np.array([0.0, 1.0, 2.0])
    expected = [1.0, math.exp(-0.5), math.exp(-2.0)]
    np.testing.assert_allclose(point_likelihood(distances, 1.0), expected)
    np.testing.assert_allclose(point_likelihood(distances[1:2], 0.5), [math.exp(-2.0)])


def test_eq4_cluster_likelihood_is_the_mean_per_cluster():
    likelihoods = np.array([1.0, 0.5, 0.2, 0.4, 0.9])
    labels = np.array([0, 0, 1, 1, 1])
    np.testing.assert_allclose(cluster_likelihood(likelihoods, labels, 2), [0.75, 0.5])


def test_eq5_pitch_variation_probability():
    assert pitch_variation_probability(np.array([0.5]), np.array([0.4]))[0] == pytest.approx(0.8)


def test_algorithm_one_end_to_end_by_hand():
    # the line x = 1 m, |y| <= 0.5 m; the previous scan's nearest points are 2 m behind each
    # point (x = 3 m), so L = exp(-2^2 / 2) for every point
    scan = segment_scan(cross_line(1.0, 0.5))
    ys = scan.points()[scan.valid_mask(), 1]
    previous = cKDTree(np.column_stack((np.full(ys.size, 3.0), ys)))
    detection = detect_clusters(cluster_scan(scan, FilterParams()), previous, FilterParams())
    p_theta, p_likelihood = math.exp(-0.5), math.exp(-2.0)
    assert detection.v_c[0] == pytest.approx(1.0)
    assert detection.p_theta[0] == pytest.approx(p_theta)
    assert detection.p_likelihood[0] == pytest.approx(p_likelihood)
    assert detection.p_pv[0] == pytest.approx(1.0 - p_theta * p_likelihood)  # 0.918 > 0.8
    assert detection.detected.tolist() == [True]


def detect_line(line, previous_segments, params=None):
    params = params or FilterParams()
    previous = cluster_scan(segment_scan(previous_segments), params)
    current = cluster_scan(segment_scan(np.concatenate((WALLS, line))), params)
    detection = detect_clusters(current, previous.tree, params)
    return detection, current.labels[np.flatnonzero(np.isfinite(segment_scan(line).ranges))[0]]


def test_new_line_one_metre_ahead_is_detected():
    detection, line = detect_line(cross_line(1.0, 0.5), WALLS)
    assert detection.detected[line]
    assert detection.detected.sum() == 1  # the walls are not


def test_line_present_in_previous_scan_is_not_detected():
    line_and_walls = np.concatenate((WALLS, cross_line(1.0, 0.5)))
    detection, line = detect_line(cross_line(1.0, 0.5), line_and_walls)
    assert detection.p_likelihood[line] == pytest.approx(1.0)
    assert detection.p_pv[line] == pytest.approx(1.0 - math.exp(-0.5))
    assert not detection.detected.any()


def test_wall_parallel_to_x_is_gated_out_by_v_c():
    side_wall = np.array([[[0.2, 1.0], [1.5, 1.0]]])
    detection, wall = detect_line(side_wall, WALLS)
    assert detection.v_c[wall] < FilterParams().v_th
    assert math.isnan(detection.p_likelihood[wall]) and math.isnan(detection.p_pv[wall])
    assert not detection.detected.any()


@pytest.mark.parametrize("mode", ["scan_order", "radius"])
def test_line_behind_behaves_like_line_ahead(mode):
    params = FilterParams(clustering=mode)
    ahead, a = detect_line(cross_line(1.0, 0.5), WALLS, params)
    behind, b = detect_line(cross_line(-1.0, 0.5), WALLS, params)
    assert behind.detected[b] and ahead.detected[a]
    assert behind.clusters.sizes[b] == ahead.clusters.sizes[a]  # not cut at the scan's seam
    for values in ("v_c", "p_theta", "p_likelihood", "p_pv"):
        assert getattr(behind, values)[b] == pytest.approx(getattr(ahead, values)[a], abs=1e-9)


def test_without_previous_scan_nothing_is_detected():
    scan = segment_scan(np.concatenate((WALLS, cross_line(1.0, 0.5))))
    clusters = cluster_scan(scan, FilterParams())
    for previous in (None, cKDTree(np.zeros((0, 2)))):
        detection = detect_clusters(clusters, previous, FilterParams())
        assert not detection.detected.any()


def test_p_th_is_a_strict_threshold():
    detection, line = detect_line(cross_line(1.0, 0.5), WALLS)
    at_threshold = FilterParams(p_th=float(detection.p_pv[line]))
    again, _ = detect_line(cross_line(1.0, 0.5), WALLS, at_threshold)
    assert not again.detected[line]
