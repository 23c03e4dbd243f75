"""Tracking (Algorithm 2): association, the v_C, radial and size checks, the queue."""

import numpy as np

from pvfilter import FilterParams, PitchVariationFilter, TrackingQueue
from pvfilter.paper.tracking import associate
from pvfilter.synthetic import cross_line, room_segments, segment_scan

WALLS = room_segments(5.0, 5.0, 3.0, 3.0)


def run(lines, params=None):
    """Filter a walls-only scan, then one scan per line; the line's removal per scan."""
    pvf = PitchVariationFilter(params)
    pvf.process(segment_scan(WALLS, stamp=0.0))
    removed = []
    for k, line in enumerate(lines, start=1):
        result = pvf.process(segment_scan(np.concatenate((WALLS, line)), stamp=0.1 * k))
        on_line = np.isfinite(segment_scan(line).ranges)
        assert result.removed[on_line].all() or not result.removed[on_line].any()
        assert not result.removed[~on_line].any()
        removed.append(bool(result.removed[on_line].all()))
    return removed


def test_line_drifting_ten_centimetres_per_scan_stays_tracked():
    assert run([cross_line(1.0 + 0.1 * k, 0.5) for k in range(8)]) == [True] * 8


def test_without_tracking_only_the_first_scan_of_the_line_is_removed():
    lines = [cross_line(1.0 + 0.1 * k, 0.5) for k in range(4)]
    assert run(lines, FilterParams(tracking=False)) == [True, False, False, False]


def test_line_is_dropped_when_its_size_more_than_doubles():
    lines = [cross_line(1.0 + 0.1 * k, 0.5) for k in range(4)] + [cross_line(1.4, 1.5)]
    assert run(lines) == [True, True, True, True, False]


def test_line_is_dropped_when_it_leaves_the_radial_band():
    lines = [cross_line(x, 0.5) for x in (1.65, 1.75, 1.85, 1.95, 2.05)]
    assert run(lines) == [True, True, True, True, False]


def test_dropped_line_is_not_tracked_again():
    lines = [cross_line(x, 0.5) for x in (1.75, 1.85, 1.95, 2.05, 1.95)]
    assert run(lines) == [True, True, True, False, False]


def queue_of(*centroid_size):
    return TrackingQueue(
        np.array([c for c, _ in centroid_size], dtype=float),
        np.array([s for _, s in centroid_size]),
    )


def test_association_uses_the_nearest_queued_cluster_within_d_track():
    queue = queue_of(((1.0, 0.0), 20), ((1.0, 1.0), 100))
    centroids = np.array([[1.1, 0.0], [1.0, 0.9], [1.0, -1.6]])
    sizes = np.array([20, 20, 20])
    v_c = np.ones(3)
    # nearest of the second is the cluster of 100 points (ratio 0.2): rejected;
    # the third is 1.6 m from its nearest (> d_track = 1.5)
    assert associate(centroids, sizes, v_c, queue, FilterParams()).tolist() == [True, False, False]


def test_association_checks_v_c_radius_and_size_ratio_bounds_inclusive():
    queue = queue_of(((1.0, 0.0), 20))
    centroids = np.array([[1.0, 0.0], [1.0, 0.0], [0.25, 0.0], [1.0, 0.0], [1.0, 0.0]])
    sizes = np.array([20, 20, 20, 10, 41])
    v_c = np.array([0.65, 0.6, 1.0, 1.0, 1.0])
    expected = [True, False, False, True, False]  # v_C >= v_th; 0.25 m < d_min; 10/20 = 0.5
    assert associate(centroids, sizes, v_c, queue, FilterParams()).tolist() == expected


def test_empty_queue_tracks_nothing():
    centroids, sizes, v_c = np.ones((2, 2)), np.array([20, 20]), np.ones(2)
    tracked = associate(centroids, sizes, v_c, TrackingQueue(), FilterParams())
    assert tracked.tolist() == [False, False]
