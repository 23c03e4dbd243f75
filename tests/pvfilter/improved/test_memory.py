"""The level-view memory: moved with the sensor, taught by level scans only, forgetting."""

import copy
import dataclasses
import math
import warnings

import numpy as np

from pvfilter.improved import BeamLayout, ImprovedParams, LevelMemory, Motion
from pvfilter.improved.memory import LevelView, nearest_first
from pvfilter.scan import Scan
from pvfilter.synthetic import ray_cast, room_segments

from .conftest import room_scan, to_sensor

PARAMS = ImprovedParams()


def ranges_of(scan):
    return np.where(scan.valid_mask(), scan.ranges, np.nan)


def remembered(scan, params=PARAMS):
    memory = LevelMemory()
    memory.update(ranges_of(scan), np.isposinf(scan.ranges), None, 0.0, params, True)
    return memory


STILL = Motion()


def view_of(memory, scan, motion=STILL, params=PARAMS):
    return memory.view(BeamLayout.of(scan), 12.0, motion, STILL, 0.0, params)


def step(memory, scan, dt=0.1, params=PARAMS, level=True, hold=None, across=None, velocity=None):
    view = view_of(memory, scan, params=params)
    back = view.surfaces_back(ranges_of(scan), params)  # as the filter finds it
    memory.update(
        ranges_of(scan), np.isposinf(scan.ranges), view, dt, params, level, hold, velocity,
        across=across, back=back,
    )  # fmt: skip
    return view


def test_the_view_follows_the_sensor_forward():
    before, _ = room_scan(noise_m=0.0)
    after, _ = room_scan((0.3, 0.0, 0.0), noise_m=0.0)
    # the sensor moved 0.3 m forward: static points move 0.3 m back in its frame
    view = view_of(remembered(before), before, Motion(tx_m=-0.3))
    ahead = np.abs(before.angles()) < math.radians(20.0)
    np.testing.assert_allclose(view.ranges[ahead], after.ranges[ahead], atol=0.01)


def test_the_view_follows_the_sensor_turning():
    before, _ = room_scan(noise_m=0.0)
    after, _ = room_scan((0.0, 0.0, math.radians(10.0)), noise_m=0.0)
    view = view_of(remembered(before), before, Motion(math.radians(-10.0)))
    both = np.isfinite(view.ranges) & np.isfinite(ranges_of(after))
    assert np.count_nonzero(both) > 400
    assert np.median(np.abs(view.ranges[both] - after.ranges[both])) < 0.01


def test_a_tilted_scan_does_not_teach_the_view():
    level, _ = room_scan(noise_m=0.0)
    pitched, on_floor = room_scan(pitch_rad=math.radians(6.0), noise_m=0.0)
    memory = remembered(level)
    view = step(memory, pitched, level=False)
    np.testing.assert_array_equal(memory.state.ranges, view.ranges)
    np.testing.assert_array_equal(memory.state.ages, view.ages)  # its clock stands still
    # but it still settles, where the line is in front by more than a shrink step
    deep = on_floor & (level.ranges - pitched.ranges > PARAMS.memory_shrink_mps * 0.1)
    assert deep.sum() > 100 and (memory.state.ahead_s[deep] == 0.1).all()


def test_a_level_return_in_front_comes_closer_at_most_at_the_shrink_rate():
    level, _ = room_scan(noise_m=0.0)
    pitched, on_floor = room_scan(pitch_rad=math.radians(6.0), noise_m=0.0)
    memory = remembered(level)
    view = step(memory, pitched)  # taken as level: e.g. a person stepping in
    shrunk = view.ranges[on_floor] - memory.state.ranges[on_floor]
    assert np.mean(np.abs(shrunk - PARAMS.memory_shrink_mps * 0.1) < 1e-9) > 0.95


def test_the_view_holds_behind_a_possible_floor_line():
    level, _ = room_scan(noise_m=0.0)
    pitched, on_floor = room_scan(pitch_rad=math.radians(6.0), noise_m=0.0)
    memory = remembered(level)
    view = step(memory, pitched, hold=on_floor)
    np.testing.assert_array_equal(memory.state.ranges[on_floor], view.ranges[on_floor])


def test_behind_a_segment_across_the_travel_the_view_comes_closer_at_the_line_rate():
    level, _ = room_scan(noise_m=0.0)
    pitched, on_floor = room_scan(pitch_rad=math.radians(6.0), noise_m=0.0)
    memory = remembered(level)
    view = step(memory, pitched, across=on_floor)  # a floor line the scan did not detect
    deep = on_floor & (level.ranges - pitched.ranges > 0.2)  # in front by more than a step
    assert deep.sum() > 100
    shrunk = view.ranges[deep] - memory.state.ranges[deep]
    np.testing.assert_allclose(shrunk, PARAMS.line_shrink_mps * 0.1, atol=1e-9)


def test_the_line_rate_allows_for_the_sensor_travel():
    # the ego-motion's error along x shows on exactly these segments: up to the travel
    level, _ = room_scan(noise_m=0.0)
    pitched, on_floor = room_scan(pitch_rad=math.radians(6.0), noise_m=0.0)
    memory = remembered(level)
    view = step(memory, pitched, across=on_floor, velocity=Motion(tx_m=0.6, ty_m=-0.8))
    deep = on_floor & (level.ranges - pitched.ranges > 0.2)
    assert deep.sum() > 100
    shrunk = view.ranges[deep] - memory.state.ranges[deep]
    np.testing.assert_allclose(shrunk, PARAMS.line_shrink_mps * 0.1 + 0.1, atol=1e-9)


def test_with_neither_rate_limited_the_view_follows_every_return_at_once():
    params = dataclasses.replace(PARAMS, memory_shrink_mps=math.inf, line_shrink_mps=math.inf)
    level, _ = room_scan(noise_m=0.0)
    pitched, on_floor = room_scan(pitch_rad=math.radians(6.0), noise_m=0.0)
    open_door = np.abs(level.angles() - math.radians(90.0)) < math.radians(5.0)
    level = dataclasses.replace(level, ranges=np.where(open_door, np.inf, level.ranges))
    memory = remembered(level, params)  # free space (inf) through the door
    on_floor |= open_door  # a segment across the travel there too
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no inf - inf on the way
        step(memory, pitched, params=params, across=on_floor)
    np.testing.assert_allclose(memory.state.ranges[on_floor], pitched.ranges[on_floor])


BOX = np.array([[[1.0, -0.4], [1.0, 0.4]]])  # a low top the rocking plane passes over


def gave_up_the_box(gone_for):
    """A memory that saw the box, then the wall behind it for ``gone_for`` scans."""
    with_box, _ = room_scan(extra=BOX, noise_m=0.0)
    without, _ = room_scan(noise_m=0.0)
    memory = remembered(with_box)
    for _ in range(gone_for):
        step(memory, without)
    return memory, with_box, np.abs(without.angles()) < math.radians(5.0)


def test_a_surface_the_view_gave_up_takes_its_place_back_at_once():
    memory, with_box, ahead = gave_up_the_box(3)  # confirm_free_s = 0.25 s: 3 scans
    assert (memory.state.ranges[ahead] > 3.9).all()  # the view took the wall behind
    view = step(memory, with_box)
    assert view.surfaces_back(ranges_of(with_box), PARAMS)[ahead].all()
    np.testing.assert_allclose(
        memory.state.ranges[ahead], 1.0 / np.cos(with_box.angles()[ahead]), atol=1e-6
    )


def test_a_surface_given_up_long_ago_comes_back_at_the_shrink_rate():
    memory, with_box, ahead = gave_up_the_box(20)  # 2 s > memory_timeout_s
    view = step(memory, with_box)
    assert view.surfaces_back(ranges_of(with_box), PARAMS) is None
    shrunk = view.ranges[ahead] - memory.state.ranges[ahead]
    np.testing.assert_allclose(shrunk, PARAMS.memory_shrink_mps * 0.1, atol=1e-9)


def test_space_seen_free_joins_the_view_only_once_confirmed():
    # a box in front of the sensor goes away: the wall behind it is seen for 0.3 s
    box = np.array([[[1.0, -0.4], [1.0, 0.4]]])
    with_box, _ = room_scan(extra=box, noise_m=0.0)
    without, _ = room_scan(noise_m=0.0)
    ahead = np.abs(without.angles()) < math.radians(5.0)
    memory = remembered(with_box)
    for k, expected in enumerate((1.0, 1.0, 4.0)):  # confirm_free_s = 0.25 s: 3 scans
        step(memory, without)
        np.testing.assert_allclose(memory.state.ranges[ahead], expected / np.cos(
            without.angles()[ahead]), atol=1e-6, err_msg=f"scan {k}")  # fmt: skip


def test_a_return_in_front_for_longer_than_an_event_replaces_the_view():
    params = dataclasses.replace(PARAMS, max_event_s=0.3)
    level, _ = room_scan(noise_m=0.0)
    pitched, on_floor = room_scan(pitch_rad=math.radians(6.0), noise_m=0.0)
    memory = remembered(level, params)
    for _ in range(4):  # 0.4 s in front of the view, even while tilted
        step(memory, pitched, params=params, level=False)
    deep = on_floor & (level.ranges - pitched.ranges > params.memory_shrink_mps * 0.1)
    np.testing.assert_allclose(memory.state.ranges[deep], pitched.ranges[deep])


def test_a_surface_the_sensor_drives_through_leaves_the_view():
    # a ramp's slope that a level scan took for a low wall 0.3 m ahead, across the path:
    # driven 0.4 m on, it would lie 0.1 m behind the sensor, in front of the wall there
    ramp = np.array([[[0.3, -0.2], [0.3, 0.2]]])
    level, _ = room_scan(noise_m=0.0, extra=ramp)
    after, _ = room_scan((0.4, 0.0, 0.0), noise_m=0.0)
    layout = BeamLayout.of(level)
    view = remembered(level).view(
        layout, 12.0, Motion(tx_m=-0.4), STILL, 0.0, PARAMS, range_min=level.range_min
    )
    # the strip the sensor itself passed through (its housing wide) is clear: the wall
    # behind is the view there; beside it, under the robot's body, the surface stays
    behind = np.abs(level.angles()) > math.radians(160.0)
    seen = behind & np.isfinite(after.ranges)
    assert np.count_nonzero(seen) > 20
    np.testing.assert_allclose(view.ranges[seen], after.ranges[seen], atol=0.02)


def test_forgotten_beams_know_nothing_and_carry_nothing_onto_others():
    # the robot's body (0.2 m off, on beams 100-139) forgotten after a level scan taught
    # it: the view knows nothing there, and a drive of 0.2 m carries none of it onto the
    # beams beside it, which keep the room's walls
    level, _ = room_scan(noise_m=0.0)
    body = np.zeros(len(level), bool)
    body[100:140] = True
    with_body = level.with_ranges(np.where(body, 0.2, level.ranges))
    memory = remembered(with_body)
    memory.forget(body)
    state = memory.state
    assert np.isnan(state.ranges[body]).all() and np.isinf(state.ages[body]).all()
    np.testing.assert_array_equal(state.ranges[~body], ranges_of(level)[~body])
    moved = memory.view(BeamLayout.of(level), 12.0, Motion(tx_m=0.2), STILL, 0.0, PARAMS)
    assert not (moved.ranges < 0.5).any()


def test_forgotten_free_beams_are_no_longer_free():
    level, _ = room_scan(noise_m=0.0)
    open_space = level.with_ranges(np.full(len(level), np.inf))
    memory = remembered(open_space)
    step(memory, open_space)  # a second silent scan: free
    forgotten = np.arange(len(level)) < 10
    memory.forget(forgotten)
    assert np.isnan(memory.state.known_free_m()[forgotten]).all()
    view = view_of(memory, level)
    assert np.isnan(view.ranges[forgotten]).all()
    assert np.isposinf(view.ranges[~forgotten]).all()


def test_a_view_without_a_return_for_too_long_is_forgotten():
    params = dataclasses.replace(PARAMS, memory_timeout_s=0.25)
    level, _ = room_scan(noise_m=0.0)
    blind = level.with_ranges(np.full(len(level), np.nan))
    memory = remembered(level, params)
    for _ in range(3):
        step(memory, blind, params=params)
    assert np.isnan(view_of(memory, level, params=params).ranges).all()


def test_no_return_remembers_free_space_once_a_second_scan_agrees():
    level, _ = room_scan(noise_m=0.0)
    open_space = level.with_ranges(np.full(len(level), np.inf))
    memory = remembered(open_space)
    assert np.isnan(memory.state.ranges).all()  # one scan's silence: unknown
    step(memory, open_space)
    assert np.isposinf(view_of(memory, level).ranges).all()


def test_a_sequences_first_silent_scan_does_not_make_the_wall_behind_new():
    # the first scan of a sequence is blinded ahead (a person touching the sensor, a
    # dark wall): its silence there is unknown, not free space, and the wall the next
    # scan sees is not in front of the view
    level, _ = room_scan(noise_m=0.0)
    ahead = np.flatnonzero(np.abs(level.angles()) < math.radians(20.0))
    memory = remembered(silent_on(level, ahead))
    assert np.isnan(view_of(memory, level).ranges[ahead]).all()
    step(memory, level)
    assert np.isfinite(memory.state.ranges[ahead]).all()  # the wall, taken at once


def silent_on(scan, beams):
    """``scan`` with no echo (``+inf``) on ``beams``."""
    ranges = scan.ranges.copy()
    ranges[beams] = np.inf
    return scan.with_ranges(ranges)


def test_no_echo_beside_returns_on_the_view_does_not_free_it():
    level, _ = room_scan(noise_m=0.0)
    ahead = np.flatnonzero(np.abs(level.angles()) < math.radians(20.0))
    # a dark wall ahead: every other beam echoes (on one side), none does (on the other)
    left, right = ahead[ahead >= len(level) // 2], ahead[ahead < len(level) // 2]
    dark = silent_on(level, np.concatenate((left[::2], right)))
    memory = remembered(level)
    for _ in range(5):  # 0.5 s, twice confirm_free_s
        step(memory, dark)
    assert np.isfinite(memory.state.ranges[left]).all()  # dropouts: the wall stays
    assert (memory.state.ages[left] == 0.0).all()  # and each silent scan confirms it


def test_a_surface_gone_silent_is_kept_unconfirmed_until_it_times_out():
    # a whole run of beams without an echo where the view holds a wall: a floor met at a
    # grazing angle by a plane tilted too little to show a line hides the wall behind it
    level, _ = room_scan(noise_m=0.0)
    ahead = np.flatnonzero(np.abs(level.angles()) < math.radians(20.0))
    hidden = silent_on(level, ahead)
    memory = remembered(level)
    for _ in range(5):  # 0.5 s, twice confirm_free_s: not space seen free
        step(memory, hidden)
    np.testing.assert_allclose(memory.state.ranges[ahead], level.ranges[ahead])
    # unconfirmed (but the two beams beside the echoes around the run: dropouts there)
    np.testing.assert_allclose(memory.state.ages[ahead[1:-1]], 0.5)
    for _ in range(11):  # 1.6 s in all, past memory_timeout_s (1.5 s): unknown, then free
        step(memory, hidden)
    assert np.isposinf(memory.state.ranges[ahead[1:-1]]).all()
    # no echo where the view knew nothing frees it at once, as before
    fresh = LevelMemory()
    fresh.update(np.full(len(level), np.nan), np.zeros(len(level), bool), None, 0.0, PARAMS, True)
    step(fresh, hidden)
    assert np.isposinf(fresh.state.ranges[ahead[1:-1]]).all()


def test_a_dark_surface_in_front_of_the_view_settles_though_it_echoes_now_and_then():
    params = dataclasses.replace(PARAMS, max_event_s=0.3)
    level, _ = room_scan(noise_m=0.0)
    box = np.array([[[1.0, -0.4], [1.0, 0.4]]])
    with_box, _ = room_scan(extra=box, noise_m=0.0)
    ahead = np.abs(level.angles()) < math.radians(5.0)
    dark = silent_on(with_box, np.flatnonzero(ahead))
    memory = remembered(level, params)
    for scan in (with_box, dark, with_box, dark, with_box):  # echoes on every other scan
        step(memory, scan, params=params, hold=ahead)  # (held: no shrink towards it)
    np.testing.assert_allclose(memory.state.ranges[ahead], with_box.ranges[ahead])
    # a beam that never had a return in front starts no clock on silence
    open_space = level.with_ranges(np.full(len(level), np.inf))
    quiet = remembered(level, params)
    for _ in range(5):
        step(quiet, open_space, params=params)
    assert (quiet.state.ahead_s == 0.0).all()


def test_in_a_tilted_scan_a_floor_line_gone_silent_stops_the_clock():
    # a floor line moves with the pitch: a beam of it without an echo has moved on
    params = dataclasses.replace(PARAMS, max_event_s=0.3)
    level, _ = room_scan(noise_m=0.0)
    pitched, on_floor = room_scan(pitch_rad=math.radians(6.0), noise_m=0.0)
    grazing = silent_on(pitched, np.flatnonzero(on_floor))
    memory = remembered(level, params)
    for scan in (pitched, grazing, pitched, grazing, pitched):
        step(memory, scan, params=params, level=False)
    np.testing.assert_allclose(memory.state.ranges[on_floor], level.ranges[on_floor])


def written(beams, ranges, order, count):
    """Per beam, the range and the point index written last in ``order``."""
    values, owners = np.full(count, np.nan), np.full(count, -1)
    values[beams[order]], owners[beams[order]] = ranges[order], order
    return values, owners


def test_each_beam_takes_its_nearest_point_as_a_sort_by_range_gives_it():
    rng = np.random.default_rng(5)
    for ring in (True, False):
        layout = dataclasses.replace(BeamLayout.of(room_scan(noise_m=0.0)[0]), ring=ring)
        beams = rng.integers(0 if ring else -1, 40, 300)  # many points per beam
        ranges = rng.choice([1.0, 2.0, 3.0, 4.0], 300) + rng.uniform(0.0, 1e-3, 300)
        tied = ranges.copy()
        tied[:5] = tied[5:10] = 0.5  # equal nearest ranges: the sort's order decides
        tied[beams == beams[0]] = 0.5
        for values in (ranges, tied):
            by_sort = np.argsort(-values)
            by_sort = by_sort if ring else by_sort[beams[by_sort] >= 0]
            order = nearest_first(beams, values, layout)
            expected = written(beams, values, by_sort, layout.count)
            mine = written(beams, values, order, layout.count)
            np.testing.assert_array_equal(mine[0], expected[0])
            np.testing.assert_array_equal(mine[1], expected[1])


def sector(scan, low_deg, high_deg):
    """The beams of ``scan`` between two angles, deg."""
    angles = np.degrees(scan.angles())
    return np.flatnonzero((angles >= low_deg) & (angles <= high_deg))


def test_free_space_stays_free_through_the_motion():
    # free everywhere (two silent scans), then the sensor drives 0.2 m and turns: a free
    # point moved off range_max is still free space, not a surface a few cm inside it
    level, _ = room_scan(noise_m=0.0)
    open_space = level.with_ranges(np.full(len(level), np.inf))
    memory = remembered(open_space)
    step(memory, open_space)
    view = view_of(memory, level, Motion(math.radians(3.0), -0.2, 0.05))
    assert np.isposinf(view.ranges).all()


def test_silence_that_stays_on_its_beams_through_a_turn_is_not_carried_onto_walls():
    # a 120 deg sector reads no echo (the body, as some drivers report it): freed, and the
    # sensor turns by 5 deg. The free space the turn carries out of the sector lands on
    # beams that see the wall now, while the beams it came from are still silent: it is
    # fixed to the sensor, and those beams' view is unknown, not free
    level, _ = room_scan(noise_m=0.0)
    blocked = sector(level, -150.0, -30.0)
    body = silent_on(level, blocked)
    memory = remembered(body)
    step(memory, body)
    assert np.isposinf(memory.state.ranges[blocked[1:-1]]).all()  # freed, as any silence
    turned, _ = room_scan((0.0, 0.0, math.radians(5.0)), noise_m=0.0)
    turned = silent_on(turned, blocked)
    layout = BeamLayout.of(turned)
    no_echo, returned = np.isposinf(turned.ranges), turned.valid_mask()
    motion = Motion(math.radians(-5.0))
    view = memory.view(layout, 12.0, motion, STILL, 0.0, PARAMS, no_echo, returned)
    beside = np.setdiff1d(sector(turned, -160.0, -20.0), blocked)  # the walls beside it
    carried = beside[
        ~np.isfinite(memory.view(layout, 12.0, motion, STILL, 0.0, PARAMS).ranges[beside])
    ]
    assert carried.size >= 8  # without the scan's echoes: free space carried 5 deg (10 beams)
    assert np.isnan(view.ranges[carried]).all()
    assert np.isposinf(view.ranges[blocked[12:-12]]).all()  # the sector itself: as it was


def test_free_space_a_turn_carries_from_beams_that_return_now_stays_free():
    # open space in the world: it moves off its beams with the turn, and where it came
    # from the scan sees something now (here a floor line across it): still free there
    level, _ = room_scan(noise_m=0.0)
    ahead = sector(level, -30.0, 30.0)
    open_ahead = silent_on(level, ahead)
    memory = remembered(open_ahead)
    step(memory, open_ahead)
    turned, _ = room_scan((0.0, 0.0, math.radians(5.0)), noise_m=0.0)
    turned = turned.with_ranges(
        np.where(np.isin(np.arange(len(turned)), ahead), 2.0, turned.ranges)
    )
    layout = BeamLayout.of(turned)
    no_echo, returned = np.isposinf(turned.ranges), turned.valid_mask()
    view = memory.view(
        layout, 12.0, Motion(math.radians(-5.0)), STILL, 0.0, PARAMS, no_echo, returned
    )
    assert np.isposinf(view.ranges[ahead[15:-15]]).all()


def test_a_dropout_beside_a_beam_the_scanner_could_not_measure_frees_nothing():
    # a body at the edge of range_min reads now too close (NaN), now no echo: where the
    # view knows nothing, such a dropout is no sight of free space
    level, _ = room_scan(noise_m=0.0)
    body = sector(level, 80.0, 100.0)
    ranges = np.where(np.isin(np.arange(len(level)), body), np.nan, level.ranges)
    ranges[body[len(body) // 2]] = np.inf
    memory = remembered(level)
    memory.update(
        ranges_of(level.with_ranges(ranges)),
        np.isposinf(ranges),
        LevelView.empty(len(level)),
        0.1,
        PARAMS,
        True,
    )
    assert np.isnan(memory.state.ranges[body[len(body) // 2]])
    # the same dropout beside returns: as before (beside a surface, a dropout of it)
    assert not np.isposinf(memory.state.ranges).any()


def test_the_edges_of_a_field_of_view_short_of_a_full_turn_are_no_neighbours():
    # a 240 degree scanner, 1 degree beams, turning 5 degrees in place: the beams the turn
    # vacates at one edge know nothing. Filled from beam 0's ring neighbour, the other
    # edge 120 degrees away, the first beam had held a wall metres off the one it sees
    room = room_segments(3.0, 2.5, 1.5, 4.0)
    increment = math.radians(1.0)

    def scan_at(yaw_rad):
        angles = -math.radians(120.0) + increment * np.arange(241)
        ranges = ray_cast(to_sensor(room, (0.0, 0.0, yaw_rad)), angles)
        return Scan(ranges=ranges, angle_min=-math.radians(120.0), angle_increment=increment,
                    range_min=0.05, range_max=12.0)  # fmt: skip

    for turn_deg in (5.0, -5.0):
        before, after = scan_at(0.0), scan_at(math.radians(turn_deg))
        view = view_of(remembered(before), before, Motion(math.radians(-turn_deg)))
        known = np.isfinite(view.ranges)
        assert 200 < np.count_nonzero(known) < 241
        np.testing.assert_allclose(view.ranges[known], after.ranges[known], atol=0.05)


def test_free_space_is_known_as_far_as_range_max_from_where_it_was_seen():
    # a silent beam sees free space up to range_max, no farther: 0.3 m closer, the space
    # ahead is known free to 0.3 m less than range_max, and a return just beyond that (a
    # wall come into range) stands beyond the view, as space newly seen free does: taken
    # once it has stood there for confirm_free_s, and not in front of the view meanwhile
    far, _ = room_scan(noise_m=0.0)
    silent = far.with_ranges(np.where(np.abs(far.angles()) < 0.3, np.inf, far.ranges))
    memory = remembered(silent)  # the first silent scan leaves the beams unknown, the next
    step(memory, silent, params=dataclasses.replace(PARAMS, confirm_free_s=0.0))  # frees them
    ahead = np.abs(silent.angles()) < math.radians(5.0)
    memory.update(ranges_of(silent), np.isposinf(silent.ranges), view_of(memory, silent),
                  0.1, PARAMS, True, range_max=3.5)  # fmt: skip
    layout, nothing = BeamLayout.of(silent), np.zeros(len(silent), bool)
    view = memory.view(layout, 3.5, Motion(tx_m=-0.3), STILL, 0.0, PARAMS)
    assert np.all(view.ranges[ahead] == np.inf)
    np.testing.assert_allclose(view.known_free_m()[ahead], 3.2, atol=0.01)
    wall = np.where(ahead, 3.25, np.nan)  # beyond the known free space, within range
    held = copy.deepcopy(memory)
    memory.update(wall, nothing, view, 0.1, PARAMS, True, range_max=3.5)
    assert np.all(memory.state.ranges[ahead] == np.inf)
    assert np.all(memory.state.ahead_s[ahead] == 0.0)  # not in front of the view
    for _ in range(3):  # 0.4 s in all: confirmed
        view = memory.view(layout, 3.5, STILL, STILL, 0.0, PARAMS)
        memory.update(wall, nothing, view, 0.1, PARAMS, True, range_max=3.5)
    np.testing.assert_allclose(memory.state.ranges[ahead], 3.25)
    # but not where it may be a floor line (a candidate line held): the view holds there
    for _ in range(4):
        view = held.view(layout, 3.5, STILL, STILL, 0.0, PARAMS)
        held.update(wall, nothing, view, 0.1, PARAMS, True, hold=ahead, range_max=3.5)
    assert np.all(held.state.ranges[ahead] == np.inf)


def test_a_new_view_carries_its_ages_with_its_clocks_at_zero_and_nothing_given_up():
    ages = np.array([0.0, 0.5, np.inf])
    view = LevelView.seen(np.array([1.0, 2.0, np.nan]), ages)
    np.testing.assert_array_equal(view.ages, ages)
    np.testing.assert_array_equal(view.ahead_s, 0.0)
    np.testing.assert_array_equal(view.farther_s, 0.0)
    np.testing.assert_array_equal(view.dropped_s, np.inf)
    assert np.isnan(view.dropped_m).all()
    ages[0] = 9.0  # the view keeps its own copy
    assert view.ages[0] == 0.0


def test_teaching_the_memory_leaves_the_view_it_was_given_as_it_was():
    scan, _ = room_scan(noise_m=0.0)
    memory = remembered(scan)
    view = view_of(memory, scan)
    before = copy.deepcopy(view)
    tilted = copy.deepcopy(memory)
    memory.update(ranges_of(scan) - 0.5, np.isposinf(scan.ranges), view, 0.1, PARAMS, True)
    tilted.update(ranges_of(scan) - 0.5, np.isposinf(scan.ranges), view, 0.1, PARAMS, False)
    np.testing.assert_array_equal(view.ranges, before.ranges)
    np.testing.assert_array_equal(view.carried, before.carried)
    # each scan runs the clocks on by its time step, in a level and in a tilted scan
    assert memory.state.ahead_s.max() > 0.0 and tilted.state.ahead_s.max() > 0.0
    assert not np.shares_memory(memory.state.carried, view.carried)
