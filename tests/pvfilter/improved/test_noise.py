"""The scanner's range noise, from the second differences of one scan's ranges."""

import math
import warnings

import numpy as np
import pytest

from pvfilter.improved.noise import (
    MAX_LINE_NOISE_M,
    NOISE_EVERY_SCANS,
    NOISE_HYSTERESIS,
    NOISE_MIN_ESTIMATES,
    NOISE_WINDOW,
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


def follow(noise: RangeNoise, scans: list[np.ndarray]) -> list[bool]:
    """``noise.update`` of each scan in turn."""
    return [noise.update(ranges) for ranges in scans]


def test_the_scanners_noise_is_measured_on_one_scan_in_four_once_three_tell():
    noise = RangeNoise()
    changed = follow(noise, [wall_ranges(0.05, seed) for seed in range(12)])
    # scans 0, 4 and 8 are measured; the third estimate gives the first measure
    assert changed == [False] * 8 + [True] + [False] * 3
    assert noise.noise_m == pytest.approx(0.05, rel=0.25)
    assert NOISE_MIN_ESTIMATES == 3 and NOISE_EVERY_SCANS == 4


def test_a_scan_without_an_estimate_leaves_the_next_one_due():
    # a scan with no three consecutive returns (a scanner spinning up) tells nothing: the
    # next scan is measured, not the one four later
    noise = RangeNoise()
    blank = np.full(241, np.nan)
    scans = [blank, blank] + [wall_ranges(0.05, seed) for seed in range(9)]
    assert follow(noise, scans) == [False] * 10 + [True]


def test_the_followed_noise_holds_within_its_hysteresis():
    # a 1 cm scanner's estimates vary by a few per cent: the noise followed does not flap,
    # and the parameters are worked out once
    noise = RangeNoise()
    changed = follow(noise, [wall_ranges(0.01, seed) for seed in range(400)])
    assert sum(changed) == 1
    assert noise.noise_m == pytest.approx(0.01, rel=0.25)
    # a cluttered stretch shorter than half the window does not move it either
    clutter = np.where(np.arange(241) % 2 == 0, 1.0, 5.0)
    assert not any(follow(noise, [clutter] * (NOISE_EVERY_SCANS * (NOISE_WINDOW // 2))))


def test_another_scanner_takes_over_within_a_window_and_clutter_is_capped():
    noise = RangeNoise()
    follow(noise, [wall_ranges(0.01, seed) for seed in range(NOISE_EVERY_SCANS * NOISE_WINDOW)])
    quiet = noise.noise_m
    follow(noise, [wall_ranges(0.05, seed) for seed in range(NOISE_EVERY_SCANS * NOISE_WINDOW)])
    assert noise.noise_m == pytest.approx(0.05, rel=0.25)
    assert noise.noise_m > (1.0 + NOISE_HYSTERESIS) * quiet
    # range jumps on every beam measure the scene, metres of "noise": never more than the cap
    clutter = np.where(np.arange(241) % 2 == 0, 1.0, 5.0)
    follow(noise, [clutter] * (NOISE_EVERY_SCANS * NOISE_WINDOW))
    assert noise.noise_m == MAX_LINE_NOISE_M
    noise.reset()
    assert math.isnan(noise.noise_m)
    assert follow(noise, [wall_ranges(0.05, seed) for seed in range(9)])[-1]  # anew
