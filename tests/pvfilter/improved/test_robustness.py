"""Odd input for the improved filter: empty, invalid, changing scans; properties."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pvfilter import ImprovedParams, ImprovedPitchVariationFilter, Scan

from .conftest import room_scan


def scan_of(ranges, stamp=0.0, increment=0.01):
    return Scan(ranges=ranges, angle_min=-1.0, angle_increment=increment, range_min=0.05,
                range_max=12.0, stamp=stamp)  # fmt: skip


@pytest.mark.parametrize(
    "ranges",
    [[], [np.nan] * 50, [np.inf, -np.inf, np.nan, 0.0, 20.0, -3.0], [1.0]],
    ids=["empty", "all-nan", "all-invalid", "single-beam"],
)
def test_degenerate_scans_give_a_same_length_result_with_nothing_removed(ranges):
    pvf = ImprovedPitchVariationFilter()
    for stamp in (0.0, 0.1, 0.2):
        result = pvf.process(scan_of(ranges, stamp))
        assert result.removed.shape == (len(ranges),) and not result.removed.any()


def test_beam_count_and_angles_may_change_mid_stream():
    pvf = ImprovedPitchVariationFilter()
    pvf.process(room_scan(stamp=0.0)[0])
    result = pvf.process(scan_of(np.full(100, 2.0), stamp=0.1, increment=0.02))
    assert result.removed.shape == (100,) and not result.removed.any()  # a new memory
    result = pvf.process(room_scan(stamp=0.2)[0])
    assert result.removed.shape == (720,)


range_values = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(min_value=0.0, max_value=3.0),  # dense enough to form segments
)


@settings(max_examples=60, deadline=None)
@given(
    st.lists(st.lists(range_values, min_size=0, max_size=80), min_size=1, max_size=4),
    st.booleans(),
)
def test_any_ranges_keep_the_length_and_remove_only_valid_beams(sequence, imu):
    pvf = ImprovedPitchVariationFilter(ImprovedParams(min_points=2))
    for k, ranges in enumerate(sequence):
        scan = scan_of(ranges, stamp=0.1 * k)
        result = pvf.process(scan, pitch_rad=0.1 if imu else None)
        assert len(result.scan) == len(ranges) and result.removed.shape == (len(ranges),)
        assert not (result.removed & ~scan.valid_mask()).any()
        nan_in = np.isnan(scan.ranges)
        assert np.isnan(result.scan.ranges[nan_in]).all()
        np.testing.assert_array_equal(result.scores > pvf.params.p_th, result.removed)
