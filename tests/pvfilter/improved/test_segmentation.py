"""Segmentation: a floor line is cut from the wall it runs into; chords of a fixed length."""

import math

import numpy as np
import pytest

from pvfilter.improved import ImprovedParams, segment_scan
from pvfilter.improved.segmentation import (
    BRIDGE_INCIDENCE_DEG,
    BRIDGE_MAX_DEG,
    MAX_HALF_WIDTH,
    across_travel,
    break_distances,
    chord_half_widths,
    local_directions,
    single_flips_smoothed,
)
from pvfilter.synthetic import room_segments

from .conftest import HEIGHT_M, room_scan, tilted_scan

INCREMENT = math.radians(0.5)


def segments_of(scan, params=None):
    params = params if params is not None else ImprovedParams()
    beams = np.flatnonzero(scan.valid_mask())
    return segment_scan(scan.points()[beams], beams, scan.angle_increment, params), beams


def test_local_direction_of_a_straight_line_is_its_direction():
    points = np.column_stack((np.linspace(0.0, 2.0, 40), 0.5 * np.linspace(0.0, 2.0, 40)))
    np.testing.assert_allclose(local_directions(points, 4), math.atan(0.5), atol=1e-9)
    per_point = np.full(40, 6)  # one half-width per point gives the same on a line
    np.testing.assert_allclose(local_directions(points, per_point), math.atan(0.5), atol=1e-9)


def test_the_chord_spans_more_beams_near_the_sensor():
    widths = chord_half_widths(np.array([0.3, 1.0, 3.0, 20.0]), INCREMENT, 0.3)
    # half of 0.3 m over the beam spacing r * increment, within [3, MAX_HALF_WIDTH]
    assert widths.tolist() == [MAX_HALF_WIDTH, 18, 6, 3]


def test_floor_line_and_the_side_walls_it_runs_into_are_different_segments():
    scan, on_floor = room_scan(pitch_rad=math.radians(8.0), noise_m=0.0)
    segments, beams = segments_of(scan)
    floor_labels = set(segments.labels[on_floor[beams]].tolist())
    # one segment holds (nearly) the whole floor line, and at most the corner of the wall
    main = max(floor_labels, key=lambda s: np.count_nonzero(segments.labels == s))
    members = segments.labels == main
    assert np.count_nonzero(on_floor[beams][members]) >= 0.9 * np.count_nonzero(on_floor)
    assert np.count_nonzero(~on_floor[beams][members]) <= 4
    assert segments.across[main]


def main_floor_segment(scan, hit, noise_m, seed):
    """The segment holding most of the floor line once ``noise_m`` of range noise is
    added: its share of the floor beams, and whether it lies across the travel."""
    rng = np.random.default_rng(seed)
    noisy = scan.with_ranges(scan.ranges + rng.normal(0.0, noise_m, len(scan)))
    segments, beams = segments_of(noisy)
    on_floor = segments.labels[hit[beams] == 2]
    main = np.bincount(on_floor).argmax()
    return np.count_nonzero(on_floor == main) / on_floor.size, segments.across[main]


@pytest.mark.parametrize("tilt_deg", [20.0, 30.0])
def test_a_steep_floor_line_near_the_sensor_stays_one_segment_in_range_noise(tilt_deg):
    # 0.5 m ahead, 2 cm noise against beam spacings of 4 mm: a chord of a few beams would
    # read noise as direction and break the line into pieces
    scan, hit = tilted_scan(pitch_rad=math.radians(tilt_deg), walls=room_segments(6, 4, 3, 3))
    share, across = main_floor_segment(scan, hit, 0.02, seed=3)
    assert share >= 0.85
    assert across


@pytest.mark.parametrize("seed", range(5))
def test_a_floor_line_leaning_with_the_roll_stays_one_segment_in_range_noise(seed):
    # 3 deg of roll at 6 deg of pitch lean the floor line 27 deg from the y axis, near the
    # 40 deg bound of "across": 3 cm of noise tip lone points over it, and without the
    # majority of three they cut the line into pieces (the main one then holds 0.68-0.98)
    scan, hit = tilted_scan(
        pitch_rad=math.radians(6.0), roll_rad=math.radians(3.0), walls=room_segments(8, 6, 4, 3)
    )
    share, across = main_floor_segment(scan, hit, 0.03, seed)
    assert share >= 0.95
    assert across


def test_a_lone_point_takes_the_side_of_its_two_neighbours():
    across = np.array([1, 1, 0, 1, 1, 0, 0, 1, 0], dtype=bool)
    # runs of two stay (a turn of direction spans several points); the ends keep theirs
    expected = np.array([1, 1, 1, 1, 1, 0, 0, 0, 0], dtype=bool)
    np.testing.assert_array_equal(single_flips_smoothed(across.copy()), expected)
    assert single_flips_smoothed(np.array([False, True])).tolist() == [False, True]
    assert single_flips_smoothed(np.zeros(0, dtype=bool)).size == 0


def test_the_fitted_line_of_a_floor_line_lies_h_over_sin_tilt_away():
    pitch = math.radians(6.0)
    scan, on_floor = room_scan(pitch_rad=pitch, noise_m=0.0)
    segments, beams = segments_of(scan)
    main = np.bincount(segments.labels[on_floor[beams]]).argmax()
    assert segments.distances[main] == pytest.approx(HEIGHT_M / math.sin(pitch), abs=1e-6)
    assert abs(segments.normals[main, 1]) < 1e-6
    # its spread along the line is the variance of the points' y; across it, none
    members = segments.points[segments.labels == main]
    assert segments.spread_along[main] == pytest.approx(np.var(members[:, 1]), rel=1e-6)
    assert segments.spread_across[main] == pytest.approx(0.0, abs=1e-9)


def test_range_jumps_split_segments():
    points = np.array([[1.0, y] for y in np.linspace(-0.3, 0.3, 10)]
                      + [[3.0, y] for y in np.linspace(0.4, 1.0, 10)])  # fmt: skip
    segments = segment_scan(points, np.arange(20), INCREMENT, ImprovedParams())
    assert len(segments) == 2 and segments.sizes.tolist() == [10, 10]


def test_beams_without_a_return_between_two_points_widen_the_gap_that_cuts():
    ranges = np.full(5, 3.0)
    beams = np.array([0, 1, 3, 7, 100, 101])  # 0, 1, 3, 92 and 0 beams missing between
    increment = math.radians(1.0)
    cut = break_distances(ranges, beams, increment, 0.15)
    per_missing = 3.0 * increment / math.cos(math.radians(BRIDGE_INCIDENCE_DEG))
    assert 3 < BRIDGE_MAX_DEG < 92  # (beams of 1 deg)
    expected = 0.15 + 0.02 * 3.0 + per_missing * np.array([0, 1, 3, 0, 0])
    np.testing.assert_allclose(cut, expected, rtol=1e-12)
    assert cut[0] == 0.15 + 0.02 * 3.0  # neighbours: the gap is as it always was


def test_a_floor_line_that_returns_no_echo_on_most_beams_stays_one_segment():
    # a 1 deg scanner, the floor line 3 m ahead; at grazing incidence only every fifth
    # beam returns (4 missing between): 26-45 cm apart, beyond the neighbours' break distance
    increment = math.radians(1.0)
    beams = np.arange(-40, 41, 5) + 180
    angles = (beams - 180) * increment
    points = np.column_stack((np.full(len(beams), 3.0), 3.0 * np.tan(angles)))
    gaps = np.hypot(*np.diff(points, axis=0).T)
    assert np.all(gaps > 0.15 + 0.02 * 3.0)  # each point alone, without the bridge
    no_echo = np.ones(360, bool)  # every beam between returned nothing (+inf)
    segments = segment_scan(points, beams, increment, ImprovedParams(), no_echo=no_echo)
    assert len(segments) == 1 and segments.across[0]
    assert segments.distances[0] == pytest.approx(3.0)
    # beams that returned something invalid (NaN) between are no echo of a line: a gap
    no_echo[beams[0] + 1 : beams[1]] = False
    segments = segment_scan(points, beams, increment, ImprovedParams(), no_echo=no_echo)
    assert segments.sizes[0] == 1 and len(segments) >= 2


def test_a_range_jump_across_missing_beams_still_cuts():
    increment = math.radians(1.0)
    near = [[1.0, 1.0 * math.tan((b - 180) * increment)] for b in range(170, 180)]
    far = [[3.0, 3.0 * math.tan((b - 180) * increment)] for b in range(184, 194)]
    beams = np.concatenate((np.arange(170, 180), np.arange(184, 194)))
    segments = segment_scan(np.array(near + far), beams, increment, ImprovedParams())
    assert segments.sizes.tolist() == [10, 10]


@pytest.mark.parametrize(
    ("ring", "behind_m", "joined"), [(True, 1.0, True), (False, 1.0, False), (True, 2.0, False)]
)
def test_on_a_full_turn_the_last_segment_continues_the_first_across_the_seam(
    ring, behind_m, joined
):
    # a wall behind the sensor through the seam at 180 deg, a wall ahead between; the
    # sweep's last stretch of wall at behind_m, its first at 1 m
    angles = -math.pi + np.arange(720) * INCREMENT
    beams = np.concatenate((np.arange(0, 40), np.arange(330, 390), np.arange(680, 720)))
    x = np.where(beams < 300, -1.0, np.where(beams < 600, 2.0, -behind_m))
    points = np.column_stack((x, x * np.tan(angles[beams])))
    segments = segment_scan(points, beams, INCREMENT, ImprovedParams(), ring=ring)
    assert len(segments) == 3 and segments.seam_joined is joined


def test_no_points_give_no_segments():
    segments = segment_scan(np.zeros((0, 2)), np.zeros(0, dtype=int), INCREMENT, ImprovedParams())
    assert len(segments) == 0


@pytest.mark.parametrize("line_angle_deg", [0.0, 1e-7, 10.0, 40.0, 89.9, 90.0])
def test_across_travel_decides_as_the_sine_does_next_to_the_bound(line_angle_deg):
    bound = math.asin(math.cos(math.radians(line_angle_deg)))
    rng = np.random.default_rng(7)
    near = bound + np.concatenate((np.arange(-40, 41) * 1e-16, rng.normal(0.0, 1e-6, 200)))
    directions = np.concatenate((rng.uniform(-0.5 * np.pi, 0.5 * np.pi, 500), near, -near))
    directions = np.clip(directions, -0.5 * np.pi, 0.5 * np.pi)
    expected = np.abs(np.sin(directions)) > np.cos(np.radians(line_angle_deg))
    np.testing.assert_array_equal(across_travel(directions, line_angle_deg), expected)
