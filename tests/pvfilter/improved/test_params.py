"""ImprovedParams: defaults, validation that names the field, derived quantities."""

import math

import pytest

from pvfilter import ImprovedParams


def test_defaults_are_valid_and_physical():
    params = ImprovedParams()
    assert params.lidar_height_m == 0.25 and 0.0 < params.p_th < 1.0
    assert params.min_line_distance_m == pytest.approx(0.25 / math.sin(math.radians(45.0)))


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
    ],
)
def test_invalid_values_raise_naming_the_field(field, value, message):
    with pytest.raises(ValueError, match=message):
        ImprovedParams(**{field: value})


def test_switches_that_turn_parts_off_are_accepted():
    ImprovedParams(memory_shrink_mps=float("inf"), max_event_s=float("inf"), extend_beams=0,
                   spread=False, ego_motion=False)  # fmt: skip
