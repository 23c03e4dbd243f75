"""Odd input: empty, invalid, single-beam and changing scans, stamps going back; properties."""

import math
import warnings

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from pvfilter import FilterParams, PitchVariationFilter, Scan, StampWentBackWarning
from pvfilter.synthetic import cross_line, room_segments, segment_scan

WALLS = room_segments(5.0, 5.0, 3.0, 3.0)


def scan_of(ranges, stamp=0.0, increment=0.01):
    return Scan(
        ranges=ranges,
        angle_min=-1.0,
        angle_increment=increment,
        range_min=0.05,
        range_max=12.0,
        stamp=stamp,
    )


@pytest.mark.parametrize(
    "ranges",
    [[], [np.nan] * 50, [np.inf, -np.inf, np.nan, 0.0, 20.0, -3.0], [1.0]],
    ids=["empty", "all-nan", "all-invalid", "single-beam"],
)
def test_degenerate_scans_give_a_same_length_result_with_nothing_removed(ranges):
    pvf = PitchVariationFilter()
    for stamp in (0.0, 0.1):
        result = pvf.process(scan_of(ranges, stamp))
        assert len(result.scan) == len(ranges) and result.removed.shape == (len(ranges),)
        assert not result.removed.any() and result.clusters == ()


def test_beam_count_and_angles_may_change_mid_stream():
    pvf = PitchVariationFilter()
    pvf.process(segment_scan(WALLS, stamp=0.0, beams=720))
    result = pvf.process(
        segment_scan(np.concatenate((WALLS, cross_line(1.0, 0.5))), stamp=0.1, beams=1080)
    )
    # history is kept as points, so the new line is still detected at the new resolution
    assert result.removed.shape == (1080,) and result.removed.any()
    result = pvf.process(scan_of(np.full(100, 2.0), stamp=0.2, increment=0.02))
    assert result.removed.shape == (100,)


def test_stamp_going_back_warns_and_resets_the_history():
    pvf = PitchVariationFilter()
    pvf.process(segment_scan(WALLS, stamp=1.0))
    with pytest.warns(StampWentBackWarning, match="earlier than the previous"):
        result = pvf.process(segment_scan(np.concatenate((WALLS, cross_line(1.0, 0.5))), stamp=0.5))
    assert not result.removed.any()  # no previous scan any more: nothing to compare with


def test_equal_stamps_and_reset_do_not_warn():
    pvf = PitchVariationFilter()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        pvf.process(segment_scan(WALLS, stamp=1.0))
        pvf.process(segment_scan(WALLS, stamp=1.0))
        pvf.reset()
        pvf.process(segment_scan(WALLS, stamp=0.0))


range_values = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(min_value=0.0, max_value=3.0),  # dense enough to form clusters
)


@settings(max_examples=60, deadline=None)
@given(
    st.lists(st.lists(range_values, max_size=60), min_size=1, max_size=4),
    st.sampled_from(["scan_order", "radius"]),
    st.booleans(),
)
def test_any_ranges_keep_length_and_nan_stays_nan(sequence, mode, tracking):
    pvf = PitchVariationFilter(FilterParams(m_th=2, clustering=mode, tracking=tracking))
    for k, ranges in enumerate(sequence):
        scan = scan_of(ranges, stamp=0.1 * k, increment=2.0 * math.pi / max(len(ranges), 1))
        result = pvf.process(scan)
        assert len(result.scan) == len(ranges) == result.removed.size == result.scores.size
        assert np.isnan(result.scan.ranges[np.isnan(scan.ranges)]).all()
        assert np.isnan(result.scan.ranges[result.removed]).all()
        assert not result.removed[~scan.valid_mask()].any()
        assert ((result.scores >= 0.0) & (result.scores <= 1.0)).all()


@settings(max_examples=80, deadline=None)
@given(
    increment=st.floats(min_value=1e-9, max_value=2 * math.pi),
    angle_min=st.floats(min_value=-4 * math.pi, max_value=4 * math.pi),
    beams=st.integers(min_value=0, max_value=400),
    stamps=st.lists(st.floats(min_value=0.0, max_value=1e308), min_size=1, max_size=4),
    name=st.sampled_from(["paper", "improved"]),
)
# stamps a denormal apart: a velocity over that step overflowed to NaN points
@example(increment=1.0, angle_min=0.0, beams=1, stamps=[0.0, 5e-324], name="improved")
def test_every_scan_that_scan_accepts_is_filtered_without_error_or_warning(
    increment, angle_min, beams, stamps, name
):
    from pvfilter import make_filter

    rng = np.random.default_rng(beams)
    pvf = make_filter(name)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        warnings.simplefilter("ignore", StampWentBackWarning)
        for stamp in stamps:
            ranges = rng.uniform(0.1, 5.0, beams)
            ranges[::7] = np.nan
            scan = Scan(ranges=ranges, angle_min=angle_min, angle_increment=increment,
                        range_min=0.05, range_max=12.0, stamp=stamp)  # fmt: skip
            result = pvf.process(scan)
            assert result.removed.shape == (beams,)


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("angle_increment", 5e-324),
        ("angle_increment", 1e308),
        ("angle_min", 1e300),
        ("range_max", 1e300),
    ],
)
def test_scans_no_scanner_can_make_are_refused_naming_the_field(field, value):
    fields = {"angle_min": 0.0, "angle_increment": 0.01, "range_max": 12.0, field: value}
    with pytest.raises(ValueError, match=field):
        Scan(ranges=np.ones(5), range_min=0.05, **fields)
