"""Re-anchoring: a drifted level view is put back on the walls; a floor line is not drift."""

import dataclasses
import math

import numpy as np
import pytest

from pvfilter.improved import (
    BeamLayout,
    ImprovedParams,
    ImprovedPitchVariationFilter,
    LevelMemory,
    Motion,
)
from pvfilter.improved.anchor import (
    REFINE_ASSOCIATION_M,
    explains_both_ends,
    explains_view_error,
    offset_along_x,
    on_crossing_surfaces,
    register_view,
    within_margin,
)
from pvfilter.improved.evidence import free_space_gaps
from pvfilter.improved.motion import MIN_PAIRS, STILL

from .conftest import HEIGHT_M, room_scan
from .test_evidence import directions_of, ranges_of

PARAMS = ImprovedParams(lidar_height_m=HEIGHT_M)
DRIFT = (0.25, 0.05, math.radians(2.0))  # m, m, rad: where the view thinks the sensor is


def view_of(scan, motion=STILL):
    """The level view of ``scan`` moved by ``motion``, as the filter's memory gives it."""
    memory = LevelMemory()
    memory.update(ranges_of(scan), np.isposinf(scan.ranges), None, 0.0, PARAMS, True)
    return memory.view(BeamLayout.of(scan), scan.range_max, motion, Motion(), 0.0, PARAMS)


def margin_of(scan):
    return PARAMS.free_margin_m + PARAMS.free_margin_rel * ranges_of(scan)


def test_the_view_registered_against_the_scan_recovers_its_drift():
    # the view was taken from DRIFT; the scan is from the origin. A point q of the view's
    # frame is at R(yaw) q + (x, y) in the scan's (the world frame here)
    drifted, _ = room_scan(DRIFT, noise_m=0.0)
    scan, _ = room_scan(noise_m=0.005, seed=1)
    layout = BeamLayout.of(scan)
    correction = register_view(
        ranges_of(scan), directions_of(scan), view_of(drifted).ranges, layout
    )
    x, y, yaw = DRIFT
    assert correction is not None
    assert math.degrees(abs(correction.theta_rad - yaw)) < 0.1
    assert abs(correction.tx_m - x) < 0.01 and abs(correction.ty_m - y) < 0.01


@pytest.mark.parametrize(
    ("tx_m", "turn_deg", "within"),
    [(0.0, 0.0, True), (0.07, 0.8, True), (0.09, 0.0, False), (0.0, 0.9, False)],
)
def test_a_correction_within_the_free_space_margin_leaves_the_view_where_it_is(
    tx_m, turn_deg, within
):
    # the margin is 0.08 m + 0.015 r: a correction moves a point at r by |t| + |theta| r
    correction = Motion(math.radians(turn_deg), tx_m, 0.0)
    assert within_margin(correction, PARAMS) is within


def test_the_filter_tries_nothing_more_where_the_view_registers_within_the_margin(monkeypatch):
    # a view 3 cm off: the registration finds it where the scan says; the view is not
    # moved, and not searched along x
    searched = []
    monkeypatch.setattr("pvfilter.improved.filter.offset_along_x", lambda *args: searched.append(1))
    pvf = ImprovedPitchVariationFilter(PARAMS)
    layout_scan, _ = room_scan(noise_m=0.005, seed=1)
    layout = BeamLayout.of(layout_scan)
    view = view_of(room_scan((0.03, 0.0, 0.0), noise_m=0.0)[0])
    gaps = free_space_gaps(ranges_of(layout_scan), view.ranges, layout, layout_scan.range_max)
    pvf._start(layout_scan)
    echoes = np.isposinf(layout_scan.ranges), layout_scan.valid_mask()
    anchored = pvf._reanchor(
        layout_scan, ranges_of(layout_scan), echoes, ranges_of(layout_scan),
        directions_of(layout_scan), view, gaps, STILL, Motion(), True,
    )  # fmt: skip
    assert anchored is None and not searched


def test_a_drifted_view_is_corrected_where_returns_are_seen_through_it():
    drifted, _ = room_scan(DRIFT, noise_m=0.0)
    scan, _ = room_scan(noise_m=0.005, seed=1)
    layout = BeamLayout.of(scan)
    ranges, view = ranges_of(scan), view_of(drifted)
    correction = register_view(ranges, directions_of(scan), view.ranges, layout)
    before = free_space_gaps(ranges, view.ranges, layout, scan.range_max)
    after = free_space_gaps(ranges, view_of(drifted, correction).ranges, layout, scan.range_max)
    margin = margin_of(scan)
    assert (before < -margin).sum() > 50  # the walls behind lie beyond the view
    assert explains_view_error(before, after, margin, directions_of(scan))
    assert (np.abs(after) <= margin).mean() > 0.95 * np.isfinite(after).mean()


def test_a_floor_line_in_front_of_a_parallel_wall_is_not_taken_for_drift():
    # a 3.8 deg tilt puts the floor line 3.77 m ahead, 0.23 m in front of the wall at 4 m.
    # With a view of what lies ahead only, the registration moves the wall onto the line
    # and puts twice as many returns on the view; but it explains no return seen through
    # the view (a tilted plane puts returns in front of the structure, never beyond it)
    level, _ = room_scan(noise_m=0.0)
    ahead = level.with_ranges(np.where(np.cos(level.angles()) > 0.0, level.ranges, np.nan))
    pitched, on_floor = room_scan(pitch_rad=math.radians(3.8), noise_m=0.005, seed=2)
    layout = BeamLayout.of(pitched)
    ranges, view = ranges_of(pitched), view_of(ahead)
    correction = register_view(ranges, directions_of(pitched), view.ranges, layout)
    assert on_floor.sum() > 50 and correction is not None
    assert abs(correction.tx_m - (HEIGHT_M / math.sin(math.radians(3.8)) - 4.0)) < 0.02
    before = free_space_gaps(ranges, view.ranges, layout, pitched.range_max)
    after = free_space_gaps(ranges, view_of(ahead, correction).ranges, layout, pitched.range_max)
    margin = margin_of(pitched)
    assert (np.abs(after) <= margin).sum() > 2 * (np.abs(before) <= margin).sum()
    # the returns it puts on the view are the floor line's: one straight line
    assert not explains_view_error(before, after, margin, directions_of(pitched))


def test_a_drifted_view_with_nothing_behind_is_corrected_where_it_explains_a_corner():
    # seen ahead and to the left only (a hall: nothing else within range), the view is
    # left behind the sensor and to its right by travel the scans did not see: the wall
    # ahead and the wall on the left stand in front of it, and no return lies beyond it.
    # The returns the registration brings back lie on both walls: surfaces that cross,
    # which no floor line is
    drifted, _ = room_scan((-0.25, -0.3, 0.0), noise_m=0.0)
    scan, _ = room_scan(noise_m=0.005, seed=1)
    seen = (np.cos(scan.angles()) > 0.0) & (np.sin(scan.angles()) > 0.0)
    scan = scan.with_ranges(np.where(seen, scan.ranges, np.inf))
    drifted = drifted.with_ranges(np.where(seen, drifted.ranges, np.nan))
    layout = BeamLayout.of(scan)
    ranges, directions, view = ranges_of(scan), directions_of(scan), view_of(drifted)
    correction = register_view(ranges, directions, view.ranges, layout)
    assert correction is not None
    before = free_space_gaps(ranges, view.ranges, layout, scan.range_max)
    after = free_space_gaps(ranges, view_of(drifted, correction).ranges, layout, scan.range_max)
    margin = margin_of(scan)
    assert (before > margin).sum() > 100 and (after > margin).sum() < 10  # new, then on it
    assert (before < -margin).sum() == 0  # nothing seen through the view to explain
    assert explains_view_error(before, after, margin, directions)


def test_returns_on_one_line_are_not_on_crossing_surfaces():
    rng = np.random.default_rng(0)
    line = math.radians(80.0) + rng.normal(0.0, math.radians(5.0), 200)
    assert not on_crossing_surfaces(line)
    corner = np.concatenate([line, line[: MIN_PAIRS // 2] - math.pi / 2])
    assert on_crossing_surfaces(corner)
    assert not on_crossing_surfaces(corner[-MIN_PAIRS + 1 :])  # too few to tell
    # a direction and its opposite are one line; NaN (no direction) is left out
    assert not on_crossing_surfaces(np.concatenate([line, line + math.pi, [np.nan] * 50]))


def drifted_filter(reanchor_view: bool) -> tuple[ImprovedPitchVariationFilter, np.ndarray]:
    """A filter whose level view drifted (set from a scan at DRIFT, as a pitch event's
    dead reckoning can leave it) that then sees a level scan; and that scan's ranges."""
    pvf = ImprovedPitchVariationFilter(dataclasses.replace(PARAMS, reanchor_view=reanchor_view))
    for k in range(5):
        pvf.process(room_scan(stamp=0.1 * k, seed=k)[0])
    drifted = view_of(room_scan(DRIFT, noise_m=0.0)[0])
    pvf._memory.state = dataclasses.replace(pvf._memory.state, ranges=drifted.ranges)
    scan, _ = room_scan(stamp=0.5, seed=5)
    pvf.process(scan)
    return pvf, ranges_of(scan)


def test_the_filter_puts_a_drifted_view_back_on_the_walls():
    for reanchor_view, expected_on_walls in ((False, False), (True, True)):
        pvf, ranges = drifted_filter(reanchor_view)
        view = pvf._memory.state.ranges
        known = np.isfinite(view) & np.isfinite(ranges)
        on_walls = np.mean(np.abs(view[known] - ranges[known]) < 0.05) > 0.9
        assert on_walls == expected_on_walls, reanchor_view


FAR_DRIFT = (0.7, 0.0, 0.0)  # m, m, rad: travel along x the scans did not see (> 0.5 m)


def test_a_view_off_along_x_beyond_the_registrations_reach_is_found_by_the_search():
    drifted, _ = room_scan(FAR_DRIFT, noise_m=0.0)
    scan, _ = room_scan(noise_m=0.005, seed=1)
    layout = BeamLayout.of(scan)
    ranges, directions, view = ranges_of(scan), directions_of(scan), view_of(drifted)
    margin = margin_of(scan)
    before = free_space_gaps(ranges, view.ranges, layout, scan.range_max)
    # from no correction the registration does not get there
    near = register_view(ranges, directions, view.ranges, layout)
    assert near is None or abs(near.tx_m - FAR_DRIFT[0]) > 0.1
    shift = offset_along_x(ranges, view.ranges, layout)
    assert shift is not None and abs(shift.tx_m - FAR_DRIFT[0]) <= 0.05
    correction = register_view(ranges, directions, view.ranges, layout, shift, REFINE_ASSOCIATION_M)
    assert correction is not None and abs(correction.tx_m - FAR_DRIFT[0]) < 0.01
    after = free_space_gaps(ranges, view_of(drifted, correction).ranges, layout, scan.range_max)
    assert explains_view_error(before, after, margin, directions)
    assert explains_both_ends(before, after, margin, layout)
    # with no drift there is nothing to search for
    level = view_of(room_scan(noise_m=0.0)[0])
    assert offset_along_x(ranges, level.ranges, layout) is None


def test_a_shift_that_moves_the_wall_ahead_onto_a_floor_line_helps_on_one_side_only():
    # the floor line 0.6 m in front of the wall ahead (at 4 m): shifting the view 0.6 m
    # puts the line on the view's wall, and takes the wall behind off the view
    floor_at = 3.4  # m
    pitched, on_floor = room_scan(pitch_rad=math.asin(HEIGHT_M / floor_at), noise_m=0.005, seed=2)
    layout = BeamLayout.of(pitched)
    level = room_scan(noise_m=0.0)[0]
    ranges, view = ranges_of(pitched), view_of(level)
    onto_line = Motion(0.0, floor_at - 4.0, 0.0)
    before = free_space_gaps(ranges, view.ranges, layout, pitched.range_max)
    after = free_space_gaps(ranges, view_of(level, onto_line).ranges, layout, pitched.range_max)
    margin = margin_of(pitched)
    ahead = layout.cos > 0.5
    assert on_floor.sum() > 50
    assert (np.abs(after[ahead]) <= margin[ahead]).sum() > (
        np.abs(before[ahead]) <= margin[ahead]
    ).sum()
    assert not explains_both_ends(before, after, margin, layout)


@pytest.mark.parametrize(("odometry", "corrected"), [(False, True), (True, False)])
def test_the_filter_searches_along_x_only_where_the_travel_went_unmeasured(odometry, corrected):
    # the view drifted 0.7 m along x; without odometry the travel went unseen and the
    # search puts the view back; with odometry the travel was measured, and the view
    # stands (the re-anchoring's own reach is 0.5 m)
    pvf = ImprovedPitchVariationFilter(PARAMS)
    pose = (0.0, 0.0, 0.0) if odometry else None
    for k in range(5):
        pvf.process(room_scan(stamp=0.1 * k, seed=k)[0], pose_sensor_in_odom=pose)
    drifted = view_of(room_scan(FAR_DRIFT, noise_m=0.0)[0])
    pvf._memory.state = dataclasses.replace(pvf._memory.state, ranges=drifted.ranges)
    scan, _ = room_scan(stamp=0.5, seed=5)
    pvf.process(scan, pose_sensor_in_odom=pose)
    view, ranges = pvf._memory.state.ranges, ranges_of(scan)
    known = np.isfinite(view) & np.isfinite(ranges)
    on_walls = np.mean(np.abs(view[known] - ranges[known]) < 0.05) > 0.9
    assert on_walls == corrected
