"""Corners: a segment that is two lines at an angle is cut where they meet
(pvfilter.improved.corners)."""

import math

import numpy as np

from pvfilter.improved import ImprovedParams, ImprovedPitchVariationFilter
from pvfilter.improved.corners import CORNER_TURN_DEG, corner, split_at_corners
from pvfilter.improved.segmentation import segment_scan

from .conftest import HEIGHT_M, ROOM, tilted_scan
from .test_segmentation import segments_of

PARAMS = ImprovedParams()
# a wall 26.6 deg off the y axis (within the band of lines across the direction of travel)
# that the floor line of a 10 deg nose-down pitch (1.44 m ahead) runs into at y = 0.32 m
OBLIQUE_WALL = np.array([[[1.6, 0.0], [0.6, 2.0]]])


def _bent_line(turn_deg: float, noise_m: float = 0.005, seed: int = 0) -> np.ndarray:
    """40 points along y at x = 2 m, then 40 more turning ``turn_deg`` towards +x."""
    rng = np.random.default_rng(seed)
    first = np.column_stack((np.full(40, 2.0), np.linspace(-1.0, 0.0, 40, endpoint=False)))
    turn = math.radians(turn_deg)
    run = np.linspace(0.0, 1.0, 40)
    second = np.column_stack((2.0 + run * math.sin(turn), run * math.cos(turn)))
    return np.concatenate((first, second)) + rng.normal(0.0, noise_m, (80, 2))


def test_the_corner_is_where_two_lines_at_an_angle_meet():
    at = corner(_bent_line(30.0), PARAMS.min_points)
    assert at is not None and abs(at - 40) <= 2


def test_a_straight_line_and_a_slight_bend_are_not_cut():
    assert corner(_bent_line(0.0), PARAMS.min_points) is None
    assert corner(_bent_line(0.5 * CORNER_TURN_DEG), PARAMS.min_points) is None
    # noise as large as a far return's does not make a corner of a straight line
    assert corner(_bent_line(0.0, noise_m=0.03, seed=1), PARAMS.min_points) is None


def test_a_floor_line_running_into_an_oblique_wall_becomes_a_segment_of_its_own():
    walls = np.concatenate((ROOM, OBLIQUE_WALL))
    scan, hit = tilted_scan(pitch_rad=math.radians(10.0), walls=walls)
    segments, beams = segments_of(scan)
    floor = hit[beams] == 2

    def floor_segment(segs):
        """The segment holding most floor points: its floor and wall point counts."""
        floor_counts = np.bincount(segs.labels, floor, len(segs))
        wall_counts = np.bincount(segs.labels, hit[beams] == 1, len(segs))
        best = int(np.argmax(floor_counts))
        return floor_counts[best], wall_counts[best]

    joined_floor, joined_wall = floor_segment(segments)
    assert joined_wall >= 10  # the segmentation alone joins the line and the wall
    cut = split_at_corners(segments, PARAMS)
    cut_floor, cut_wall = floor_segment(cut)
    assert cut_wall <= 2 and cut_floor >= 0.9 * joined_floor
    np.testing.assert_array_equal(cut.points, segments.points)  # the points stay in order


def test_every_bent_segment_is_cut_at_once_and_only_those_tried():
    # two bent lines, far apart, in one scan: each is cut at its own corner
    pieces = (_bent_line(30.0), _bent_line(-25.0, seed=2) + np.array([0.0, 3.0]))
    points = np.concatenate(pieces)
    corners = [corner(piece, PARAMS.min_points) for piece in pieces]
    segments = segments_of_points(points)
    assert len(segments) == 2
    cut = split_at_corners(segments, PARAMS)
    np.testing.assert_array_equal(cut.bounds, [0, corners[0], 80, 80 + corners[1], 160])
    # a segment that may not score (no new point, no IMU) is left whole
    only_second = split_at_corners(segments, PARAMS, np.array([False, True]))
    np.testing.assert_array_equal(only_second.bounds, [0, 80, 80 + corners[1], 160])


def segments_of_points(points: np.ndarray):
    """The segments of points given in scan order, one beam each (0.25 deg apart)."""
    return segment_scan(points, np.arange(len(points)), math.radians(0.25), PARAMS)


def test_a_scan_of_straight_walls_keeps_its_segments():
    scan, _ = tilted_scan()
    segments, _ = segments_of(scan)
    assert split_at_corners(segments, PARAMS) is segments


def test_the_filter_removes_a_floor_line_that_runs_into_an_oblique_wall():
    # without the cut, the line and the wall are one segment, mostly wall, and the line of
    # the 10 deg scans is kept whole; with it, only the wall beams within the line's
    # tolerance of the corner go with the line
    walls = np.concatenate((ROOM, OBLIQUE_WALL))
    params = ImprovedParams(lidar_height_m=HEIGHT_M, axle_height_m=HEIGHT_M)
    pvf = ImprovedPitchVariationFilter(params)
    for k, pitch_deg in enumerate([0.0] * 10 + [6.0, 10.0, 10.0]):
        scan, hit = tilted_scan(pitch_rad=math.radians(pitch_deg), walls=walls, stamp=0.1 * k)
        removed = pvf.process(scan).removed
    assert removed[hit == 2].mean() > 0.95
    assert np.count_nonzero(removed[hit == 1]) <= 10
