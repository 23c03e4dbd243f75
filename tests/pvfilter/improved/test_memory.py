"""The level-view memory: moved with the sensor, shrinking at a bounded rate, forgetting."""

import math

import numpy as np

from pvfilter.improved import (
    BeamLayout,
    ImprovedParams,
    LevelMemory,
    Motion,
    free_space_gaps,
    new_points,
)

from .conftest import room_scan

PARAMS = ImprovedParams()


def remembered(scan, params=PARAMS):
    memory = LevelMemory()
    memory.update(ranges_of(scan), np.isposinf(scan.ranges), None, 0.0, params)
    return memory


def ranges_of(scan):
    return np.where(scan.valid_mask(), scan.ranges, np.nan)


def test_the_view_follows_the_sensor_forward():
    before, _ = room_scan(noise_m=0.0)
    after, _ = room_scan((0.3, 0.0, 0.0), noise_m=0.0)
    layout = BeamLayout.of(before)
    # the sensor moved 0.3 m forward: static points move 0.3 m back in its frame
    view = remembered(before).view(layout, 12.0, Motion(tx_m=-0.3), PARAMS)
    ahead = np.abs(before.angles()) < math.radians(20.0)
    np.testing.assert_allclose(view.ranges[ahead], after.ranges[ahead], atol=0.01)


def test_the_view_follows_the_sensor_turning():
    before, _ = room_scan(noise_m=0.0)
    after, _ = room_scan((0.0, 0.0, math.radians(10.0)), noise_m=0.0)
    view = remembered(before).view(BeamLayout.of(before), 12.0, Motion(math.radians(-10.0)), PARAMS)
    both = np.isfinite(view.ranges) & np.isfinite(ranges_of(after))
    assert np.count_nonzero(both) > 400
    assert np.median(np.abs(view.ranges[both] - after.ranges[both])) < 0.01


def test_a_floor_line_in_front_of_the_walls_is_new_and_the_walls_are_not():
    level, _ = room_scan(noise_m=0.0)
    pitched, on_floor = room_scan(pitch_rad=math.radians(6.0), noise_m=0.0)
    layout = BeamLayout.of(level)
    view = remembered(level).view(layout, 12.0, Motion(), PARAMS)
    gaps = free_space_gaps(ranges_of(pitched), view.ranges, layout, PARAMS)
    new = new_points(gaps, ranges_of(pitched), PARAMS.free_margin_m, PARAMS.free_margin_rel)
    assert on_floor.sum() > 50
    assert new[on_floor].mean() > 0.9 and not new[~on_floor].any()


def test_the_view_comes_closer_at_most_at_the_shrink_rate():
    level, _ = room_scan(noise_m=0.0)
    pitched, on_floor = room_scan(pitch_rad=math.radians(6.0), noise_m=0.0)
    memory = remembered(level)
    layout = BeamLayout.of(level)
    view = memory.view(layout, 12.0, Motion(), PARAMS)
    memory.update(ranges_of(pitched), np.isposinf(pitched.ranges), view, 0.1, PARAMS)
    shrunk = view.ranges[on_floor] - memory.state.ranges[on_floor]
    step = PARAMS.memory_shrink_mps * 0.1
    assert (shrunk <= step + 1e-9).all()
    assert np.mean(np.abs(shrunk - step) < 1e-9) > 0.95  # all but where the line meets a wall


def test_the_view_holds_behind_a_possible_floor_line():
    level, _ = room_scan(noise_m=0.0)
    pitched, on_floor = room_scan(pitch_rad=math.radians(6.0), noise_m=0.0)
    memory, layout = remembered(level), BeamLayout.of(level)
    view = memory.view(layout, 12.0, Motion(), PARAMS)
    memory.update(ranges_of(pitched), np.isposinf(pitched.ranges), view, 0.1, PARAMS, on_floor)
    np.testing.assert_array_equal(memory.state.ranges[on_floor], view.ranges[on_floor])
    assert (memory.state.ahead_s[on_floor] == 0.1).all()  # it still settles after an event


def test_a_return_in_front_for_longer_than_an_event_replaces_the_view():
    params = ImprovedParams(max_event_s=0.3)
    level, _ = room_scan(noise_m=0.0)
    pitched, on_floor = room_scan(pitch_rad=math.radians(6.0), noise_m=0.0)
    memory, layout = remembered(level, params), BeamLayout.of(level)
    for _ in range(4):  # 0.4 s in front of the view
        view = memory.view(layout, 12.0, Motion(), params)
        memory.update(ranges_of(pitched), np.isposinf(pitched.ranges), view, 0.1, params)
    np.testing.assert_allclose(memory.state.ranges[on_floor], pitched.ranges[on_floor])


def test_a_view_without_a_return_for_too_long_is_forgotten():
    params = ImprovedParams(memory_timeout_s=0.25)
    level, _ = room_scan(noise_m=0.0)
    blind = np.full(len(level), np.nan)
    memory, layout = remembered(level, params), BeamLayout.of(level)
    for _ in range(3):
        view = memory.view(layout, 12.0, Motion(), params)
        memory.update(blind, np.zeros(len(level), bool), view, 0.1, params)
    assert np.isnan(memory.view(layout, 12.0, Motion(), params).ranges).all()


def test_no_return_remembers_free_space():
    level, _ = room_scan(noise_m=0.0)
    ranges = np.full(len(level), np.inf)
    memory = LevelMemory()
    memory.update(np.full(len(level), np.nan), np.isposinf(ranges), None, 0.0, PARAMS)
    view = memory.view(BeamLayout.of(level), 12.0, Motion(), PARAMS)
    assert np.isposinf(view.ranges).all()
    gaps = free_space_gaps(ranges_of(level), view.ranges, BeamLayout.of(level), PARAMS)
    assert new_points(gaps, ranges_of(level), 0.15, 0.03)[level.valid_mask()].all()
