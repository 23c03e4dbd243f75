"""ImprovedParams: defaults, validation that names the field, derived quantities."""

import dataclasses
import math

import pytest

from pvfilter import ImprovedParams


def test_defaults_are_valid_and_physical():
    params = ImprovedParams()
    assert params.lidar_height_m == 0.25 and 0.0 < params.p_th < 1.0
    # at 45 deg the scanner has come down from 0.25 m to 0.08 + 0.17 cos 45 deg about the axle
    tilt = math.radians(45.0)
    assert params.min_line_distance_m == pytest.approx(
        (0.08 + 0.17 * math.cos(tilt)) / math.sin(tilt)
    )
    assert params.scanner_height_m(0.0) == pytest.approx(0.25)


@pytest.mark.parametrize(
    ("field", "value", "message"),
    [
        ("lidar_height_m", -0.1, "lidar_height_m: must be > 0 m"),
        ("p_th", 1.5, "p_th: must be <= 1"),
        ("max_tilt_deg", 120.0, "max_tilt_deg: must be <= 90 deg"),
        ("min_points", 2.5, "min_points: must be an integer >= 1"),
        ("ego_motion", 1, "ego_motion: must be true or false"),
        ("free_margin_m", float("nan"), "free_margin_m: must be finite"),
        ("axle_height_m", 0.5, "axle_height_m: must be <= lidar_height_m"),
        ("min_ceiling_m", 0.2, "min_ceiling_m: must be > lidar_height_m"),
        ("max_gap_s", 0.0, "max_gap_s: must be > 0 s"),
        ("odom_slip", 2.0, "odom_slip: must be <= 1"),
        ("line_length_m", -1.0, "line_length_m: must be >= 0 m"),
        ("new_return_score", -0.01, "new_return_score: must be >= 0"),
        ("new_return_score", 1.5, "new_return_score: must be <= 1"),
    ],
)
def test_invalid_values_raise_naming_the_field(field, value, message):
    with pytest.raises(ValueError, match=message):
        ImprovedParams(**{field: value})


def test_switches_that_turn_parts_off_are_accepted():
    ImprovedParams(memory_shrink_mps=float("inf"), max_event_s=float("inf"), extend_beams=0,
                   spread=False, ego_motion=False, max_gap_s=float("inf"),
                   line_length_m=0.0, new_return_score=0.0)  # fmt: skip


def test_point_counts_scale_with_the_beam_spacing():
    # a line at a given distance holds half the points at 1 deg, twice as many at 0.25 deg
    params = ImprovedParams()
    assert params.for_beam_spacing(math.radians(0.5)) is params
    coarse = params.for_beam_spacing(math.radians(1.0))
    assert (coarse.min_points, coarse.down_side_min_new, coarse.extend_beams) == (4, 10, 5)
    fine = params.for_beam_spacing(-math.radians(0.25))  # a clockwise scanner: the spacing
    assert (fine.min_points, fine.down_side_min_new, fine.extend_beams) == (16, 40, 20)
    # a line needs a few points for a direction; a count set lower stays as set
    sparse = params.for_beam_spacing(math.radians(4.0))
    assert (sparse.min_points, sparse.down_side_min_new, sparse.extend_beams) == (3, 5, 2)
    own = ImprovedParams(min_points=2).for_beam_spacing(math.radians(4.0))
    assert own.min_points == 2
    assert (
        dataclasses.replace(coarse, min_points=8, down_side_min_new=20, extend_beams=10) == params
    )


def test_line_distances_grow_with_the_range_noise():
    # two neighbours on one surface lie within 3 standard deviations of the difference of
    # two ranges, a return within 3 of its line; nothing narrows below what was set
    params = ImprovedParams()
    assert params.for_range_noise(0.01) is params  # 1 cm: the defaults cover it
    assert params.for_range_noise(math.nan) is params  # not measured yet
    noisy = params.for_range_noise(0.05)
    assert noisy.break_distance_m == pytest.approx(3.0 * math.sqrt(2.0) * 0.05)
    assert noisy.extend_tolerance_m == pytest.approx(0.15)
    assert dataclasses.replace(noisy, break_distance_m=0.15, extend_tolerance_m=0.03) == params
    wide = ImprovedParams(break_distance_m=0.5).for_range_noise(0.05)
    assert wide.break_distance_m == 0.5 and wide.extend_tolerance_m == pytest.approx(0.15)
