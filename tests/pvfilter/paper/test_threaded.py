"""The two-thread form gives exactly the sequential results."""

import numpy as np
import pytest

from pvfilter import FilterParams, PitchVariationFilter
from pvfilter.paper.threaded import ThreadedPitchVariationFilter
from pvfilter.synthetic import cross_line, room_segments, segment_scan


def random_sequence(count, seed):
    """Random rooms, random lines ahead or behind that drift, grow and vanish; noise."""
    rng = np.random.default_rng(seed)
    x, half_width = 1.0, 0.5
    for k in range(count):
        walls = room_segments(*rng.uniform([2.5, 2.5, 1.5, 1.5], [6.0, 6.0, 4.0, 4.0]))
        if rng.random() < 0.3:
            x, half_width = rng.choice([-1.0, 1.0]) * rng.uniform(0.4, 2.5), rng.uniform(0.2, 1.5)
        x += rng.normal(0.0, 0.1)
        line = cross_line(x, half_width) if rng.random() < 0.6 else np.zeros((0, 2, 2))
        segments = np.concatenate((walls, line))
        yield segment_scan(segments, stamp=0.1 * k, noise_m=0.01, rng=rng)


def assert_same(sequential, threaded):
    np.testing.assert_array_equal(sequential.removed, threaded.removed)
    np.testing.assert_array_equal(sequential.scores, threaded.scores)
    np.testing.assert_array_equal(sequential.scan.ranges, threaded.scan.ranges)
    assert [(c.detected, c.tracked) for c in sequential.clusters] == [
        (c.detected, c.tracked) for c in threaded.clusters
    ]


@pytest.mark.parametrize("tracking", [True, False])
def test_two_threads_agree_with_sequential_on_a_long_random_sequence(tracking):
    params = FilterParams(tracking=tracking)
    scans = list(random_sequence(300, seed=7))
    pvf = PitchVariationFilter(params)
    sequential = [pvf.process(scan) for scan in scans]
    with ThreadedPitchVariationFilter(params, max_pending=4) as threaded:
        results = list(threaded.process_stream(scans))
    assert len(results) == len(scans)
    assert sum(r.removed.any() for r in sequential) > 20  # the sequence exercises the filter
    for a, b in zip(sequential, results, strict=True):
        assert_same(a, b)


def test_reset_takes_effect_in_scan_order():
    scans = list(random_sequence(40, seed=3))
    pvf = PitchVariationFilter()
    expected = [pvf.process(scan) for scan in scans[:20]]
    pvf.reset()
    expected += [pvf.process(scan) for scan in scans[20:]]
    no_reset = PitchVariationFilter()
    unreset = [no_reset.process(scan).removed for scan in scans]
    assert any(not np.array_equal(u, e.removed) for u, e in zip(unreset, expected, strict=True))
    with ThreadedPitchVariationFilter(max_pending=64) as threaded:
        for scan in scans[:20]:
            threaded.submit(scan)
        threaded.reset()  # while earlier scans are still in flight
        for scan in scans[20:]:
            threaded.submit(scan)
        results = [threaded.result(timeout=30.0) for _ in scans]
    for a, b in zip(expected, results, strict=True):
        assert_same(a, b)


def test_errors_reach_the_caller_and_the_threads_keep_running(monkeypatch):
    scans = list(random_sequence(2, seed=1))
    with ThreadedPitchVariationFilter() as threaded:
        with pytest.raises(TypeError, match="must be a pvfilter"):  # refused at once
            threaded.submit("not a scan")
        detect = threaded._filter.cluster_and_detect
        calls = iter([RuntimeError("failed in the detection thread")])

        def failing_once(scan):
            error = next(calls, None)
            if error is not None:
                raise error
            return detect(scan)

        monkeypatch.setattr(threaded._filter, "cluster_and_detect", failing_once)
        threaded.submit(scans[0])
        with pytest.raises(RuntimeError, match="detection thread"):
            threaded.result(timeout=10.0)
        assert len(threaded.process(scans[0]).removed) == 720
