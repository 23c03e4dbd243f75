"""Scan: LaserScan fields, REP-117 semantics, points, validation."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pvfilter import Scan


def make_scan(ranges, **overrides):
    fields = dict(
        ranges=ranges, angle_min=0.0, angle_increment=math.pi / 2, range_min=0.1, range_max=10.0
    )
    fields.update(overrides)
    return Scan(**fields)


def test_fields_default_and_angle_max_is_derived():
    scan = make_scan([1.0, 2.0, 3.0], angle_min=-0.5, angle_increment=0.25)
    assert scan.stamp == 0.0 and scan.time_increment == 0.0 and scan.scan_time == 0.0
    assert scan.intensities is None
    assert len(scan) == 3
    assert scan.angle_max == pytest.approx(0.0)
    np.testing.assert_allclose(scan.angles(), [-0.5, -0.25, 0.0])


def test_ranges_are_a_read_only_float64_copy():
    source = np.array([1, 2, 3])
    scan = make_scan(source)
    source[0] = 9
    assert scan.ranges.dtype == np.float64
    assert scan.ranges[0] == 1.0
    with pytest.raises(ValueError):
        scan.ranges[0] = 5.0


def test_points_are_in_the_sensor_frame_counter_clockwise():
    # beams at 0, 90, 180, 270 degrees: ahead (+x), left (+y), behind (-x), right (-y)
    scan = make_scan([1.0, 2.0, 3.0, 4.0])
    np.testing.assert_allclose(scan.points(), [[1, 0], [0, 2], [-3, 0], [0, -4]], atol=1e-12)


def test_rep117_invalid_beams_have_nan_points():
    scan = make_scan([np.inf, -np.inf, np.nan, 0.05, 11.0, 0.1, 10.0])
    assert scan.valid_mask().tolist() == [False] * 5 + [True, True]
    points = scan.points()
    assert np.isnan(points[:5]).all()
    assert np.isfinite(points[5:]).all()


def test_no_echo_is_plus_inf_range_max_itself_or_zero_as_scanners_write_it():
    range_max = 17.777015701525006  # float32 rounds it down (by 2e-8 m)
    ranges = [np.inf, range_max, float(np.float32(range_max)), 0.0]
    others = [range_max - 1e-3, range_max + 1e-3, 65.533, 0.01, np.nan, -np.inf]
    scan = make_scan(ranges + others, range_max=range_max)
    assert scan.no_echo_mask().tolist() == [True] * 4 + [False] * 6
    assert make_scan([0.0, 1.0], range_min=0.0).no_echo_mask().tolist() == [True, False]


def test_empty_scan_is_allowed():
    scan = make_scan([])
    assert len(scan) == 0
    assert scan.points().shape == (0, 2)
    assert scan.angle_max == scan.angle_min


def test_with_ranges_keeps_the_other_fields():
    scan = make_scan([1.0, 2.0], stamp=3.5, intensities=[7.0, 8.0])
    filtered = scan.with_ranges([np.nan, 2.0])
    assert filtered.stamp == 3.5
    assert filtered.intensities.tolist() == [7.0, 8.0]
    assert np.isnan(filtered.ranges[0])
    with pytest.raises(ValueError, match=r"^ranges:"):
        scan.with_ranges([1.0])


@pytest.mark.parametrize(
    ("overrides", "field"),
    [
        (dict(ranges=[[1.0, 2.0]]), "ranges"),
        (dict(ranges=["a"]), "ranges"),
        (dict(angle_increment=0.0), "angle_increment"),
        (dict(angle_increment=-0.1), "angle_increment"),
        (dict(angle_increment=math.nan), "angle_increment"),
        (dict(range_min=-1.0), "range_min"),
        (dict(range_min=10.0), "range_max"),
        (dict(range_max=math.inf), "range_max"),
        (dict(stamp=math.nan), "stamp"),
        (dict(scan_time=-0.1), "scan_time"),
        (dict(intensities=[1.0]), "intensities"),
    ],
)
def test_invalid_fields_raise_a_value_error_naming_the_field(overrides, field):
    fields = dict(ranges=[1.0, 2.0])
    fields.update(overrides)
    with pytest.raises(ValueError, match=f"^{field}:"):
        make_scan(**fields)


@settings(max_examples=50, deadline=None)
@given(st.lists(st.floats(allow_nan=True, allow_infinity=True, width=64), max_size=50))
def test_any_ranges_give_one_point_row_per_beam_finite_only_when_valid(ranges):
    scan = make_scan(ranges)
    points = scan.points()
    assert points.shape == (len(ranges), 2)
    assert (np.isfinite(points).all(axis=1) == scan.valid_mask()).all()


def test_a_clockwise_laser_scan_is_the_same_beams_counter_clockwise():
    # a message with beams clockwise (negative angle_increment), beam i measured at
    # stamp + i * time_increment: reversed, each beam keeps its angle, range, intensity
    # and measurement time
    n, increment, time_increment = 9, -0.1, 0.001
    ranges, intensities = np.arange(1.0, 1.0 + n), np.arange(n) * 10.0
    message = dict(ranges=ranges, angle_min=0.4, angle_increment=increment, range_min=0.1,
                   range_max=20.0, stamp=5.0, time_increment=time_increment, scan_time=0.1,
                   intensities=intensities)  # fmt: skip
    scan, reversed_beams = Scan.counter_clockwise(**message)
    assert reversed_beams and scan.angle_increment == pytest.approx(0.1)
    angles = 0.4 + increment * np.arange(n)
    times = 5.0 + time_increment * np.arange(n)
    np.testing.assert_allclose(scan.angles()[::-1], angles)
    np.testing.assert_allclose((scan.stamp + scan.time_increment * np.arange(n))[::-1], times)
    np.testing.assert_array_equal(scan.ranges[::-1], ranges)
    np.testing.assert_array_equal(scan.intensities[::-1], intensities)
    same, reversed_beams = Scan.counter_clockwise(**{**message, "angle_increment": 0.1})
    assert not reversed_beams and same.angle_min == 0.4
    np.testing.assert_array_equal(same.ranges, ranges)
    with pytest.raises(ValueError, match="angle_increment"):
        Scan.counter_clockwise(**{**message, "angle_increment": 0.0})


def test_a_clockwise_scan_filters_as_its_counter_clockwise_twin():
    # the improved filter on pitch events, given every scan of a rotating scanner as a
    # clockwise message: what it removes, in the message's order, is what it removes from
    # the same scans counter-clockwise
    import dataclasses

    from pvfilter import ImprovedPitchVariationFilter
    from pvfilter.synthetic import room_sequence

    twin, mine = ImprovedPitchVariationFilter(), ImprovedPitchVariationFilter()
    removed_any = 0
    for scan in room_sequence(30, seed=4).scans:
        scan = dataclasses.replace(scan, time_increment=0.1 / len(scan))
        last = len(scan) - 1
        message = dict(
            ranges=scan.ranges[::-1], angle_min=scan.angle_max,
            angle_increment=-scan.angle_increment, range_min=scan.range_min,
            range_max=scan.range_max, stamp=scan.stamp + last * scan.time_increment,
            time_increment=-scan.time_increment, scan_time=scan.scan_time,
        )  # fmt: skip
        expected = twin.process(scan).removed
        again, reversed_beams = Scan.counter_clockwise(**message)
        assert reversed_beams
        in_message_order = mine.process(again).removed[::-1]
        np.testing.assert_array_equal(in_message_order, expected[::-1])
        removed_any += int(expected.sum())
    assert removed_any > 0
