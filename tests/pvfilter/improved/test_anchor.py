"""Re-anchoring: a drifted level view is put back on the walls; a floor line is not drift."""

import dataclasses
import math

import numpy as np

from pvfilter.improved import (
    BeamLayout,
    ImprovedParams,
    ImprovedPitchVariationFilter,
    LevelMemory,
    Motion,
)
from pvfilter.improved.anchor import explains_view_error, register_view
from pvfilter.improved.evidence import free_space_gaps
from pvfilter.improved.motion import STILL

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
    assert explains_view_error(before, after, margin)
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
    assert not explains_view_error(before, after, margin)


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
