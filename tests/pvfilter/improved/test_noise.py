"""The scanner's range noise, from the second differences of one scan's ranges."""

import math
import warnings

import numpy as np
import pytest

from pvfilter.improved.noise import (
    NOISE_EVERY_SCANS,
    NOISE_STEP_M,
    NOISE_WINDOW_SCANS,
    RangeNoise,
    range_noise_m,
)

from .conftest import room_scan


def wall_ranges(noise_m: float, seed: int = 0) -> np.ndarray:
    """Ranges to a wall 3 m ahead, across the x axis, over +-60 deg at 0.5 deg."""
    angles = np.radians(np.arange(-60.0, 60.25, 0.5))
    ranges = 3.0 / np.cos(angles)
    return ranges + np.random.default_rng(seed).normal(0.0, noise_m, angles.size)


@pytest.mark.parametrize("noise_m", [0.005, 0.01, 0.05])
def test_a_walls_range_noise_is_measured_whatever_the_incidence(noise_m):
    # 241 beams: the median of 239 second differences errs by about 8 %
    for seed in range(3):
        assert range_noise_m(wall_ranges(noise_m, seed)) == pytest.approx(noise_m, rel=0.25)


def test_a_noiseless_wall_shows_only_its_curvature():
    assert range_noise_m(wall_ranges(0.0)) < 0.002


def test_only_three_consecutive_returns_count():
    # a return between returns two beams apart would add the wall's slope (metres per
    # radian at 60 deg incidence): such triples are left out
    ranges = wall_ranges(0.02)
    holed = ranges.copy()
    holed[::4] = np.nan
    holed[1::8] = np.inf
    assert range_noise_m(holed) == pytest.approx(0.02, rel=0.25)
    assert math.isnan(range_noise_m(np.full(10, np.nan)))
    assert math.isnan(range_noise_m(ranges[:2]))
    assert math.isnan(range_noise_m(np.where(np.arange(30) % 2 == 0, 3.0, np.nan)))


def test_corners_and_range_jumps_do_not_count_as_noise():
    # a room's four corners and the blocked sector's edges are a few beams of 720
    scan, _ = room_scan(noise_m=0.01)
    assert range_noise_m(np.where(scan.valid_mask(), scan.ranges, np.nan)) == pytest.approx(
        0.01, rel=0.2
    )


def test_a_picket_fence_of_range_jumps_leaves_the_median_alone():
    # a post every 12th beam, a metre in front of the wall: a quarter of the triples
    # straddle a jump of a metre. Over 0.6745 sqrt(6), their mean would read 0.3 m; the
    # median reads the noise, raised to the 67th percentile of the unspoiled ones
    ranges = wall_ranges(0.01)
    ranges[::12] -= 1.0
    assert 0.01 < range_noise_m(ranges) < 0.02


def test_infinite_ranges_count_as_no_return_without_a_warning():
    ranges = wall_ranges(0.02)
    ranges[10:14] = np.inf  # no echo
    ranges[40:42] = -np.inf  # nearer than range_min
    ranges[42] = np.inf
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert range_noise_m(ranges) == pytest.approx(0.02, rel=0.25)


def test_the_scanners_noise_is_followed_over_the_scans():
    noise = RangeNoise()
    assert math.isnan(noise.noise_m)
    assert not noise.update(np.full(10, np.nan))  # no estimate: nothing changes
    noise.reset()
    assert noise.update(wall_ranges(0.05, seed=0))  # changed: the parameters follow
    assert noise.noise_m == pytest.approx(0.05, abs=0.25 * 0.05 + NOISE_STEP_M)
    assert noise.noise_m / NOISE_STEP_M == pytest.approx(round(noise.noise_m / NOISE_STEP_M))
    # one scan in every NOISE_EVERY_SCANS is measured
    for _ in range(NOISE_EVERY_SCANS - 1):
        assert not noise.update(wall_ranges(0.5))
    # a few cluttered scans do not move the median of the window
    for seed in range(1, NOISE_WINDOW_SCANS * NOISE_EVERY_SCANS):
        noise.update(wall_ranges(0.05, seed))
    settled = noise.noise_m
    for _ in range(5 * NOISE_EVERY_SCANS):
        assert not noise.update(np.where(np.arange(241) % 2 == 0, 1.0, 5.0))
    assert noise.noise_m == settled
    # a quieter scanner takes over within a window
    for seed in range(NOISE_WINDOW_SCANS * NOISE_EVERY_SCANS):
        noise.update(wall_ranges(0.005, seed))
    assert noise.noise_m <= 0.0075
    noise.reset()
    assert math.isnan(noise.noise_m)
