"""Evidence: returns in front of the level view, and returns that stayed put in the world."""

import math

import numpy as np
import pytest
from scipy.ndimage import minimum_filter1d

from pvfilter import Scan
from pvfilter.improved import BeamLayout, ImprovedParams, LevelMemory, Motion, segment_scan
from pvfilter.improved.evidence import (
    STANDING_FALL_SHARE,
    STANDING_PITCH_CHANGE,
    RecentScans,
    WorldStatic,
    free_space_gaps,
    new_points,
    standing_pitch_change,
    window_minimum,
)
from pvfilter.improved.geometry import floor_shift

from .conftest import HEIGHT_M, room_scan

PARAMS = ImprovedParams()


def verdict(offsets):
    """The world-static test's verdict per beam asked about: (stayed put, the test tells)."""
    return offsets.stayed, offsets.telling


def ranges_of(scan):
    return np.where(scan.valid_mask(), scan.ranges, np.nan)


def gaps_against(view_scan, scan, range_max=12.0):
    """Gaps of ``scan`` against the view of two level scans ``view_scan`` (a sequence's
    first scan leaves its silent beams unknown; the second frees them)."""
    memory = LevelMemory()
    layout = BeamLayout.of(view_scan)
    ranges, silent = ranges_of(view_scan), np.isposinf(view_scan.ranges)
    memory.update(ranges, silent, None, 0.0, PARAMS, True)
    view = memory.view(layout, range_max, Motion(), Motion(), 0.0, PARAMS)
    memory.update(ranges, silent, view, 0.1, PARAMS, True)
    view = memory.view(layout, range_max, Motion(), Motion(), 0.0, PARAMS)
    return free_space_gaps(ranges_of(scan), view.ranges, layout, range_max)


def test_a_floor_line_in_front_of_the_walls_is_new_and_the_walls_are_not():
    level, _ = room_scan(noise_m=0.0)
    pitched, on_floor = room_scan(pitch_rad=math.radians(6.0), noise_m=0.0)
    new = new_points(gaps_against(level, pitched), ranges_of(pitched), 0.08, 0.015)
    assert on_floor.sum() > 50
    assert new[on_floor].mean() > 0.9 and not new[~on_floor].any()


def test_free_space_reaches_range_max_and_no_farther():
    # nothing within a 4 m range limit, then the wall 3.95 m ahead comes into range: a wall
    # at the edge of the range is not new (it was beyond the range, not in free space)
    level, _ = room_scan(noise_m=0.0)
    out_of_range = level.with_ranges(np.full(len(level), np.inf))
    near = level.with_ranges(np.where(np.isfinite(level.ranges), 3.95, np.nan))
    gaps = gaps_against(out_of_range, near, range_max=4.0)
    new = new_points(gaps, ranges_of(near), 0.08, 0.015)
    np.testing.assert_allclose(gaps[near.valid_mask()], 0.05)
    assert not new.any()


def test_unknown_view_gives_no_gap():
    level, _ = room_scan(noise_m=0.0)
    unknown = level.with_ranges(np.full(len(level), np.nan))
    assert np.isnan(gaps_against(unknown, level)).all()


def directions_of(scan):
    valid = scan.valid_mask()
    beams = np.flatnonzero(valid)
    directions = np.full(len(scan), np.nan)
    segments = segment_scan(scan.points()[beams], beams, scan.angle_increment, PARAMS)
    directions[beams] = segments.directions
    return directions


def test_a_wall_stays_put_in_the_world_and_a_floor_line_moves_with_the_sensor():
    # the sensor drives 0.3 m forward; the floor line keeps its 1.44 m, the walls stay: the
    # range along a beam to a wall changes by t . n / (u . n), side walls included
    pitch = math.radians(10.0)
    before, _ = room_scan((0.0, 0.0, 0.0), pitch, noise_m=0.0)
    after, on_floor = room_scan((0.3, 0.0, 0.0), pitch, noise_m=0.0)
    layout = BeamLayout.of(before)
    test = WorldStatic(
        ranges_of(after), ranges_of(before), directions_of(after), layout, Motion(tx_m=-0.3), 0.03
    )
    static, telling = verdict(test.offsets(np.arange(len(after))))
    walls, floor = telling & ~on_floor & after.valid_mask(), telling & on_floor
    assert walls.sum() > 100 and floor.sum() > 50  # the sensor moved along their beams
    assert static[walls].mean() > 0.9 and not static[floor].any()  # (corners aside)
    # standing still, nothing tells a wall from a line
    directions = directions_of(before)
    test = WorldStatic(ranges_of(before), ranges_of(before), directions, layout, Motion(), 0.03)
    _, telling = verdict(test.offsets(np.arange(len(before))))
    assert not telling.any()


def test_standing_a_shallow_line_that_stayed_put_is_a_wall_and_one_that_moved_is_floor():
    # the sensor stands; 0.5 deg of pitch would move a floor line at 3 deg by 0.85 m, one
    # at 20 deg by 1.4 cm: only the shallow one tells
    level, _ = room_scan(noise_m=0.0)
    layout = BeamLayout.of(level)
    beams = np.flatnonzero(level.valid_mask())
    ranges = ranges_of(level)
    shallow = floor_shift(math.radians(3.0), STANDING_PITCH_CHANGE, PARAMS)
    steep = floor_shift(math.radians(20.0), STANDING_PITCH_CHANGE, PARAMS)
    assert shallow > 0.5 and steep < 0.02
    test = WorldStatic(ranges, ranges, directions_of(level), layout, Motion(), 0.03)
    static, telling = verdict(test.offsets(beams, np.full(beams.size, shallow)))
    assert telling.all() and static.all()  # it stayed put: a wall
    _, telling = verdict(test.offsets(beams, np.full(beams.size, steep)))
    assert not telling.any()  # a steep line barely moves: nothing told
    moved = WorldStatic(ranges + 0.4, ranges, directions_of(level), layout, Motion(), 0.03)
    static, telling = verdict(moved.offsets(beams, np.full(beams.size, shallow)))
    assert telling.all() and not static.any()  # it moved while the sensor stood: floor
    # a sensor that moved along the beams is judged by its own motion, as before
    driven = WorldStatic(ranges, ranges, directions_of(level), layout, Motion(tx_m=0.3), 0.03)
    with_shift = driven.offsets(beams, np.full(beams.size, shallow)).telling
    assert np.array_equal(with_shift, driven.offsets(beams).telling)


def test_a_standing_body_cannot_hold_a_steep_tilt_so_a_steep_line_that_stayed_put_is_a_wall():
    # holding a tilt takes an acceleration of g tan p: an axle whose first step of 0.1 s
    # was still and that ended within the test's reach (2 x 3 cm) 0.3 s on decelerated at
    # most 2 x 0.06 / (0.3 x 0.2) = 2 m/s^2: 11.5 deg, beyond which the body falls or is
    # caught. A face 1.4 m behind a LiDAR 0.69 m up implies a 27 deg tilt: the least
    # change of pitch then moves that line by decimetres where 0.5 deg moved it by 3 cm
    params = ImprovedParams(lidar_height_m=0.69, axle_height_m=0.14)
    level, _ = room_scan(noise_m=0.0)
    layout = BeamLayout.of(level)
    beams = np.flatnonzero(level.valid_mask())
    ranges = ranges_of(level)

    def stood(first_speed_mps, seen=True, first_step_s=0.1, since=None):
        since = Motion() if since is None else since
        return WorldStatic(ranges, ranges, directions_of(level), layout, since, 0.03,
                           seen, 0.3, first_step_s, first_speed_mps)  # fmt: skip

    assert math.degrees(stood(0.0).hold_tilt_rad) == pytest.approx(11.53, abs=0.01)
    # a first step at 0.4 m/s: it may have braked hard all the way and come back
    assert math.degrees(stood(0.4).hold_tilt_rad) == pytest.approx(31.45, abs=0.01)
    # the sensor's measured motion widens the reach: 4 cm more
    moved = stood(0.0, since=Motion(tx_m=0.04)).hold_tilt_rad
    assert math.tan(moved) * 9.81 == pytest.approx(2.0 * 0.10 / (0.3 * 0.2))
    # unknown: a first step over the whole baseline (one scan kept), or no speed
    assert stood(0.0, first_step_s=0.3).hold_tilt_rad == pytest.approx(math.pi / 2)
    assert stood(math.inf).hold_tilt_rad == pytest.approx(math.pi / 2)
    assert WorldStatic(ranges, ranges, directions_of(level), layout, Motion(),
                       0.03).hold_tilt_rad == pytest.approx(math.pi / 2)  # fmt: skip
    steep = np.array([math.radians(27.0), -math.radians(27.0)])
    hold = stood(0.0).hold_tilt_rad
    change = standing_pitch_change(steep, hold)
    assert change[0] == pytest.approx(STANDING_FALL_SHARE * (steep[0] - hold))
    assert change[1] == change[0]  # nose up alike
    assert standing_pitch_change(np.array([math.radians(5.0)]), hold)[0] == STANDING_PITCH_CHANGE
    assert floor_shift(steep[0], STANDING_PITCH_CHANGE, params) < 0.06  # no telling before
    shift = floor_shift(steep[0], change[0], params)
    assert shift > 0.1  # well beyond twice the tolerance: it tells
    static, telling = verdict(stood(0.0).offsets(beams, np.full(beams.size, shift)))
    assert telling.all() and static.all()  # it stayed put while the sensor stood: a wall
    # a robot whose matches could not see its drive (a corridor) may have driven on with
    # its floor line: it is not known to have stood, and the line tells nothing
    assert not stood(0.0, seen=False).offsets(beams, np.full(beams.size, shift)).telling.any()


def test_a_floor_line_held_through_a_turn_in_place_never_counts_as_staying_put():
    # the sensor stands and turns 10 deg while it holds a 7 deg tilt: the floor line keeps
    # its place in the sensor frame. Near the foot of its perpendicular the turn changes
    # its range along a beam by less than the tolerance, as it would a wall's: there
    # nothing tells, and the walls, which turned, still count as staying put
    pitch = math.radians(7.0)
    before, _ = room_scan((0.0, 0.0, 0.0), pitch, noise_m=0.0)
    after, on_floor = room_scan((0.0, 0.0, math.radians(10.0)), pitch, noise_m=0.0)
    beams = np.flatnonzero(after.valid_mask())
    turned = Motion(theta_rad=-math.radians(10.0))
    layout = BeamLayout.of(after)
    test = WorldStatic(
        ranges_of(after), ranges_of(before), directions_of(after), layout, turned, 0.03
    )
    static, telling = verdict(
        test.offsets(beams, np.full(beams.size, floor_shift(pitch, STANDING_PITCH_CHANGE, PARAMS)))
    )
    floor = on_floor[beams]
    assert telling[floor].sum() > 50 and not static[floor].any()
    assert telling[~floor].sum() > 100 and static[~floor & telling].all()


def test_a_far_wall_the_baseline_cannot_tell_is_told_against_an_older_scan():
    # over the baseline the sensor drove 5 cm: within twice the tolerance (3 cm plus 1 %
    # of the range) at any range, so nothing tells; over the older scan's span it drove
    # 0.5 m, and the walls ahead and behind tell: they stayed put in the world. A floor
    # line held 2.5 m ahead travels with the sensor, and the older scan tells that too.
    pitch = math.atan2(HEIGHT_M, 2.5)
    now, on_floor = room_scan((0.5, 0.0, 0.0), pitch, noise_m=0.0)
    recent, _ = room_scan((0.45, 0.0, 0.0), pitch, noise_m=0.0)
    older, _ = room_scan((0.0, 0.0, 0.0), pitch, noise_m=0.0)
    layout, directions = BeamLayout.of(now), directions_of(now)
    beams = np.flatnonzero(now.valid_mask())

    def test_against(earlier, drive_m, farther=None):
        return WorldStatic(ranges_of(now), ranges_of(earlier), directions, layout,
                           Motion(tx_m=-drive_m), 0.03, farther=farther)  # fmt: skip

    short = test_against(recent, 0.05)
    assert not short.offsets(beams).telling.any()
    both = test_against(recent, 0.05, farther=test_against(older, 0.5))
    static, telling = verdict(both.offsets_or_farther(beams))
    floor, walls = on_floor[beams], ~on_floor[beams]
    assert telling[walls].sum() > 100 and telling[floor].sum() > 50
    assert static[walls & telling].mean() > 0.9 and not static[floor].any()
    # where the baseline's own scan tells, its verdict stands; without an older scan it
    # is all there is
    driven = test_against(room_scan((0.2, 0.0, 0.0), pitch, noise_m=0.0)[0], 0.3,
                          farther=test_against(older, 0.5))  # fmt: skip
    alone, merged = driven.offsets(beams), driven.offsets_or_farther(beams)
    assert alone.telling.sum() > 100
    np.testing.assert_array_equal(merged.world_m[alone.telling], alone.world_m[alone.telling])
    assert np.array_equal(short.offsets_or_farther(beams).telling, short.offsets(beams).telling)


def test_the_older_scan_tells_only_where_it_saw_a_return():
    # the older scan saw nothing on the beams ahead (a wall beyond its reach then, or a
    # dark one that echoed on other scans only): there it tells nothing either way
    now, _ = room_scan((0.5, 0.0, 0.0), noise_m=0.0)
    older, _ = room_scan((0.0, 0.0, 0.0), noise_m=0.0)
    ahead = np.abs(older.angles()) < math.radians(30.0)
    silent = older.with_ranges(np.where(ahead, np.inf, older.ranges))
    layout, directions = BeamLayout.of(now), directions_of(now)
    beams = np.flatnonzero(now.valid_mask())
    farther = WorldStatic(ranges_of(now), ranges_of(silent), directions, layout,
                          Motion(tx_m=-0.5), 0.03)  # fmt: skip
    test = WorldStatic(ranges_of(now), ranges_of(now), directions, layout, Motion(), 0.03,
                       farther=farther)  # fmt: skip
    told = test.offsets_or_farther(beams).telling
    assert not told[ahead[beams]].any() and told[~ahead[beams]].sum() > 50


def test_recent_scans_keep_an_older_scan_for_the_far_returns():
    recent, alone = RecentScans(0.25, 1.0), RecentScans(0.25)
    for k in range(16):  # 10 Hz, 0.1 m a scan
        for kept in (recent, alone):
            kept.advance(Motion(tx_m=-0.1))
        earlier, farther = recent.oldest(0.1 * k), recent.oldest_farther(0.1 * k)
        baseline = alone.oldest(0.1 * k)
        for kept in (recent, alone):
            kept.add(0.1 * k, np.full(3, float(k)))
    assert earlier.ranges[0] == baseline.ranges[0] == 12.0  # the baseline's, as before
    assert earlier.since.tx_m == pytest.approx(baseline.since.tx_m)
    assert farther.ranges[0] == 4.0 and farther.span_s == pytest.approx(1.1)
    assert farther.since.tx_m == pytest.approx(-1.1) and farther.first_step_s == pytest.approx(0.1)
    assert alone.oldest_farther(1.6) is None  # nothing kept beyond the baseline
    recent.clear()
    assert recent.oldest_farther(1.6) is None and recent.oldest(1.6) is None


def test_recent_scans_keep_the_last_baseline_and_the_motion_since():
    recent = RecentScans(0.25)
    for k in range(6):
        recent.advance(Motion(tx_m=-0.1 * (k + 1)), seen=k != 2)  # speeding up
        earlier = recent.oldest(0.1 * k)
        recent.add(0.1 * k, np.full(3, float(k)))
    assert earlier.ranges[0] == 2.0  # 0.3 s before the last
    assert earlier.since.tx_m == pytest.approx(-0.4 - 0.5 - 0.6)
    assert earlier.span_s == pytest.approx(0.3) and earlier.first_step_s == pytest.approx(0.1)
    assert earlier.first_speed_mps == pytest.approx(4.0)  # the step after it: 0.4 m
    assert earlier.travel_seen  # the step the matches did not see came before that scan
    assert [round(kept.stamp, 6) for kept in recent.scans] == [0.3, 0.4, 0.5]
    recent.advance(Motion(tx_m=-0.1), seen=False)
    assert not recent.oldest(0.6).travel_seen
    recent.clear()
    recent.advance(Motion())
    assert recent.oldest(0.7) is None
    # at 2 Hz one scan is kept: its first step is the whole baseline
    slow = RecentScans(0.3)
    slow.add(0.0, np.ones(3))
    slow.advance(Motion(tx_m=-0.05))
    assert slow.oldest(0.5).first_step_s == pytest.approx(0.5) == slow.oldest(0.5).span_s


@pytest.mark.parametrize("ring", [True, False])
@pytest.mark.parametrize("half", [0, 1, 2, 4, 5, 11])
def test_window_minimum_is_scipys_minimum_filter_of_the_capped_values(ring, half):
    count = 11  # (a half window up to the whole scan and beyond)
    increment = 2.0 * math.pi / count if ring else 0.1
    scan = Scan(ranges=np.ones(count), angle_min=-math.pi, angle_increment=increment,
                range_min=0.05, range_max=12.0)  # fmt: skip
    layout = BeamLayout.of(scan)
    assert layout.ring == ring
    values = np.random.default_rng(half).uniform(0.5, 8.0, count)
    values[[2, 3]] = np.nan, np.inf  # NaN counts as the cap
    cap = 6.0
    expected = minimum_filter1d(
        np.fmin(values, cap), 2 * half + 1, mode="wrap" if ring else "nearest"
    )
    least = window_minimum(values, half, layout, cap)
    np.testing.assert_array_equal(least, expected)
    assert least is not values and not np.shares_memory(least, values)
