"""The tilted scan plane against closed form: where it meets floor, ceiling and walls."""

import dataclasses
import math

import numpy as np
import pytest

from pvfilter.improved import ImprovedParams, segment_scan
from pvfilter.improved.geometry import (
    axle_distances,
    ceiling_min_distance,
    floor_distance,
    floor_shift,
    implied_tilt,
    lean_ok,
    seen_beyond,
)
from pvfilter.improved.scoring import geometry_gates
from pvfilter.improved.sweep import unstretch
from pvfilter.synthetic import room_segments

from .conftest import HEIGHT_M, tilted_scan

LEVEL_SENSOR = ImprovedParams(lidar_height_m=HEIGHT_M, axle_height_m=HEIGHT_M)  # h fixed


def segments_of(scan, params=LEVEL_SENSOR):
    beams = np.flatnonzero(scan.valid_mask())
    return segment_scan(scan.points()[beams], beams, scan.angle_increment, params), beams


@pytest.mark.parametrize("tilt_deg", [5.0, 12.0, 30.0])
def test_nose_down_meets_the_floor_h_over_sin_tilt_ahead(tilt_deg):
    tilt = math.radians(tilt_deg)
    scan, hit = tilted_scan(pitch_rad=tilt, walls=room_segments(9.0, 4.0, 6.0, 6.0))
    floor = scan.points()[hit == 2]
    assert len(floor) > 50
    np.testing.assert_allclose(floor[:, 0], HEIGHT_M / math.sin(tilt), atol=1e-9)
    assert floor_distance(tilt, LEVEL_SENSOR) == pytest.approx(HEIGHT_M / math.sin(tilt))
    segments, _ = segments_of(scan)
    main = np.argmax(segments.sizes * segments.across)
    # the line's fit takes in the corner where it meets the side walls: 0.1 deg
    assert implied_tilt(segments.distances[main : main + 1], LEVEL_SENSOR)[0] == pytest.approx(
        tilt, abs=math.radians(0.1)
    )


def test_nose_up_meets_the_floor_behind_and_the_ceiling_ahead():
    tilt, ceiling = math.radians(25.0), 2.2
    walls = room_segments(8.0, 8.0, 4.0, 4.0)
    scan, hit = tilted_scan(pitch_rad=-tilt, ceiling_m=ceiling, walls=walls)
    points = scan.points()
    np.testing.assert_allclose(points[hit == 2][:, 0], -HEIGHT_M / math.sin(tilt), atol=1e-9)
    np.testing.assert_allclose(points[hit == 3][:, 0], (ceiling - HEIGHT_M) / math.sin(tilt))
    # the nearest a ceiling at min_ceiling_m can be at this tilt
    params = dataclasses.replace(LEVEL_SENSOR, min_ceiling_m=ceiling)
    assert ceiling_min_distance(tilt, params) == pytest.approx(
        (ceiling - HEIGHT_M) / math.sin(tilt)
    )


def test_a_robot_tilting_about_its_axle_brings_the_floor_line_nearer():
    params = ImprovedParams(lidar_height_m=0.3, axle_height_m=0.1)
    for tilt in np.radians([3.0, 10.0, 25.0, 40.0]):
        scanner = 0.1 + 0.2 * math.cos(tilt)  # the scanner's height, tilted about the axle
        assert floor_distance(tilt, params) == pytest.approx(scanner / math.sin(tilt))
        assert implied_tilt(np.array([floor_distance(tilt, params)]), params)[0] == pytest.approx(
            tilt
        )
    assert params.min_line_distance_m == pytest.approx(floor_distance(math.radians(45.0), params))


@pytest.mark.parametrize("tilt_deg", [2.0, 5.0, 15.0, 40.0])
def test_the_floor_line_moves_as_the_derivative_of_its_distance(tilt_deg):
    params = ImprovedParams(lidar_height_m=0.3, axle_height_m=0.1)
    tilt, change = math.radians(tilt_deg), 1e-6
    numeric = (floor_distance(tilt - change, params) - floor_distance(tilt + change, params)) / 2
    assert floor_shift(tilt, change, params) == pytest.approx(numeric, rel=1e-5)


def test_walls_ahead_look_farther_by_one_over_cos_and_unstretch_undoes_it():
    tilt = math.radians(20.0)
    walls = room_segments(3.0, 2.0, 6.0, 6.0)  # the floor line (0.73 m) is nearer: no wall
    level, _ = tilted_scan(walls=walls, pitch_rad=0.0, beams=720)
    tilted, hit = tilted_scan(walls=walls, pitch_rad=-math.radians(5.0), beams=720)
    ahead = (hit == 1) & (np.abs(tilted.angles()) < math.radians(20.0))
    stretched = tilted.points()[ahead]
    np.testing.assert_allclose(stretched[:, 0], 3.0 / math.cos(math.radians(5.0)), atol=1e-9)
    np.testing.assert_allclose(unstretch(stretched, math.radians(5.0))[:, 0], 3.0, atol=1e-9)
    assert level.points()[ahead][:, 0] == pytest.approx(3.0)
    assert unstretch(stretched, 0.0) is stretched  # nothing to undo
    del tilt


def test_a_rolled_floor_line_leans_by_the_roll_over_the_tilt_and_passes():
    pitch, roll = math.radians(8.0), math.radians(2.0)
    walls = room_segments(9.0, 4.0, 6.0, 6.0)
    scan, hit = tilted_scan(pitch_rad=pitch, roll_rad=roll, walls=walls)
    segments, beams = segments_of(scan)
    main = np.bincount(segments.labels[hit[beams] == 2]).argmax()
    lean = math.asin(abs(segments.normals[main, 1]))
    # x sin p - y cos p sin r = h: the normal leans by atan(sin r / tan p) from the x axis
    assert lean == pytest.approx(math.atan(math.sin(roll) / math.tan(pitch)), abs=3e-3)
    args = (
        np.abs(segments.normals[:, 1]),
        implied_tilt(segments.distances, LEVEL_SENSOR),
        segments.distances,
        segments.spread_along,
        segments.spread_across,
        segments.sizes,
        np.zeros(len(segments)),
    )
    assert lean_ok(*args, LEVEL_SENSOR)[main]
    no_roll = dataclasses.replace(LEVEL_SENSOR, max_roll_deg=0.5)
    assert not lean_ok(*args, no_roll)[main]


def test_a_rotating_scan_bends_a_line_within_the_pitch_rate_allowance():
    # the far end of a line measured 20 ms later, the pitch 2 deg higher by then
    y = np.linspace(-1.0, 1.0, 80)
    tilt = math.radians(12.0) + math.radians(2.0) * (y + 1.0) / 2.0
    points = np.column_stack((HEIGHT_M / np.sin(tilt), y))
    segments = segment_scan(points, np.arange(80), math.radians(0.5), LEVEL_SENSOR)
    args = (
        np.abs(segments.normals[:, 1]),
        implied_tilt(segments.distances, LEVEL_SENSOR),
        segments.distances,
        segments.spread_along,
        segments.spread_across,
        segments.sizes,
    )
    still = dataclasses.replace(LEVEL_SENSOR, max_roll_deg=0.1, max_pitch_rate_rad_s=0.0)
    assert not lean_ok(*args, np.array([0.02]), still)[0]
    assert lean_ok(*args, np.array([0.02]), LEVEL_SENSOR)[0]  # 3 rad/s covers 1.7 rad/s


def test_a_sweep_that_starts_ahead_splits_a_levelling_floor_line_and_proves_nothing():
    # a scanner whose sweep starts straight ahead (angle_min 0, as many do) while the
    # plane levels from 18 to 4 deg within the sweep: the left half of the floor line
    # ahead comes first, 0.81 m out; the right half last, 3.6 m out. A return of the
    # later half lies beyond the earlier half, yet a plane levelling that fast meets the
    # floor there: it proves nothing. With the pitch held still, it would
    beams, sweep_s = 720, 0.1
    increment, time_increment = 2.0 * math.pi / beams, sweep_s / beams
    index = np.arange(beams)
    angle = index * increment
    pitch = math.radians(18.0) - math.radians(14.0) * index / beams  # 2.4 rad/s
    ahead = np.cos(angle) > 0.5
    ranges = HEIGHT_M / (np.sin(pitch) * np.cos(angle))
    points = np.column_stack((ranges * np.cos(angle), ranges * np.sin(angle)))[ahead]
    segments = segment_scan(points, index[ahead], increment, LEVEL_SENSOR)
    early = segments.labels[0]  # the segment of beam 0
    scored = np.zeros(len(segments), dtype=bool)
    scored[early] = True
    tilts = implied_tilt(segments.distances, LEVEL_SENSOR)
    assert math.degrees(tilts[early]) > 15.0  # the early half: the steep plane's line
    assert not seen_beyond(segments, scored, tilts, time_increment, LEVEL_SENSOR)[early]
    still = dataclasses.replace(LEVEL_SENSOR, max_pitch_rate_rad_s=0.0)
    assert seen_beyond(segments, scored, tilts, time_increment, still)[early]


def test_nothing_lies_beyond_a_floor_line_but_open_space_beside_a_wall_shows():
    tilt = math.radians(10.0)
    walls = room_segments(6.0, 4.0, 3.0, 3.0)
    scan, hit = tilted_scan(pitch_rad=tilt, walls=walls)
    segments, beams = segments_of(scan)
    floor = np.bincount(segments.labels[hit[beams] == 2]).argmax()
    scored = np.zeros(len(segments), dtype=bool)
    scored[floor] = True
    tilts = implied_tilt(segments.distances, LEVEL_SENSOR)
    assert not seen_beyond(segments, scored, tilts, 0.0, LEVEL_SENSOR)[floor]
    # a short wall 1.4 m ahead in a level scan of a big room: the room goes on beside it
    box = np.array([[[1.44, -0.3], [1.44, 0.3]]])
    level, hit = tilted_scan(walls=np.concatenate((walls, box)))
    segments, beams = segments_of(level)
    ahead = level.points()[beams]
    front = segments.labels[np.flatnonzero((ahead[:, 0] > 0.0) & (np.abs(ahead[:, 1]) < 0.2))[0]]
    scored = np.zeros(len(segments), dtype=bool)
    scored[front] = True
    tilts = implied_tilt(segments.distances, LEVEL_SENSOR)
    assert seen_beyond(segments, scored, tilts, 0.0, LEVEL_SENSOR)[front]


AHEAD = ImprovedParams(lidar_height_m=0.25, axle_height_m=0.08, lidar_ahead_m=0.15)


def ahead_scan(pitch_rad):
    """A scanner 0.15 m ahead of the axle, pitched about it: nose down lowers it."""
    arm = AHEAD.lidar_height_m - AHEAD.axle_height_m
    height = (
        AHEAD.axle_height_m + arm * math.cos(pitch_rad) - AHEAD.lidar_ahead_m * math.sin(pitch_rad)
    )
    scan, hit = tilted_scan(
        pitch_rad=pitch_rad, height_m=height, walls=room_segments(9.0, 9.0, 6.0, 6.0)
    )
    segments, _ = segments_of(scan, AHEAD)
    return segments, int(np.argmax(segments.sizes * segments.across)), scan, hit


@pytest.mark.parametrize("pitch_deg", [-30.0, -12.0, 12.0, 30.0])
def test_a_scanner_ahead_of_the_axle_meets_the_floor_its_offset_nearer_ahead_farther_behind(
    pitch_deg,
):
    pitch = math.radians(pitch_deg)
    segments, main, scan, hit = ahead_scan(pitch)
    side = math.copysign(1.0, pitch)  # the floor ahead when nose down
    over_axle = float(floor_distance(abs(pitch), AHEAD))  # (axle + arm cos p) / sin p
    floor_x = scan.points()[hit == 2][:, 0]
    np.testing.assert_allclose(floor_x, side * (over_axle - side * AHEAD.lidar_ahead_m), atol=1e-9)
    distances = axle_distances(segments, AHEAD)
    assert distances[main] == pytest.approx(over_axle, abs=2e-3)
    assert implied_tilt(distances[main : main + 1], AHEAD)[0] == pytest.approx(
        abs(pitch), abs=math.radians(0.1)
    )
    centred = dataclasses.replace(AHEAD, lidar_ahead_m=0.0)
    np.testing.assert_array_equal(axle_distances(segments, centred), segments.distances)


def test_the_steepest_floor_line_of_a_scanner_ahead_of_the_axle_passes_the_nearest_gate():
    # nose down 40 deg lowers the scanner to 0.11 m: its floor line lies 0.18 m ahead,
    # nearer than a scanner over the axle ever sees one (0.28 m at 45 deg)
    segments, main, _, _ = ahead_scan(math.radians(40.0))
    for params, passes in ((AHEAD, True), (dataclasses.replace(AHEAD, lidar_ahead_m=0.0), False)):
        distances = axle_distances(segments, params)
        tilt = implied_tilt(distances, params)
        assert geometry_gates(segments, tilt, distances, 0.0, params)[main] == passes
