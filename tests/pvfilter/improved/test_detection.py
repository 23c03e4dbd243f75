"""Detection: the tilted-plane gates, the down side, extension and spread claims, claim
scores."""

import dataclasses
import math

import numpy as np

from pvfilter.improved import ImprovedParams, segment_scan
from pvfilter.improved.detection import (
    best_claims,
    extension_claims,
    geometry_gates,
    spread_claims,
    up_side_weights,
)

from .conftest import HEIGHT_M

PARAMS = ImprovedParams(lidar_height_m=HEIGHT_M)


def line(x0, y0, x1, y1, count=40):
    return np.column_stack((np.linspace(x0, x1, count), np.linspace(y0, y1, count)))


def segments_of(*parts):
    points = np.concatenate(parts)
    return segment_scan(points, np.arange(len(points)), PARAMS)


def gates_of(*parts):
    segments = segments_of(*parts)
    _, roll = segments.implied_tilt_roll(HEIGHT_M)
    return geometry_gates(segments, roll, PARAMS)


def test_a_floor_line_across_the_direction_of_travel_passes():
    assert gates_of(line(1.5, -1.0, 1.5, 1.0)).tolist() == [True]


def test_a_wall_along_the_direction_of_travel_fails():
    assert gates_of(line(0.5, 1.2, 3.0, 1.2)).tolist() == [False]


def test_a_line_nearer_than_the_largest_tilt_allows_fails():
    near = PARAMS.min_line_distance_m * 0.8
    assert gates_of(line(near, -0.3, near, 0.3)).tolist() == [False]


def test_a_line_that_needs_more_roll_than_the_robot_has_fails():
    # 1.5 m away (tilt 9.6 deg), leaning 25 deg: a roll of about 4 deg
    lean = math.radians(25.0)
    points = line(0.0, -0.8, 0.0, 0.8) @ np.array(
        [[math.cos(lean), math.sin(lean)], [-math.sin(lean), math.cos(lean)]]
    ) + np.array([1.5 / math.cos(lean), 0.0])
    assert gates_of(points).tolist() == [False]


def test_extension_takes_the_points_on_the_line_up_to_the_corner():
    floor = line(1.5, -1.0, 1.5, 1.0)
    corner = line(1.5, 1.05, 1.5, 1.2, 4)  # still on the line
    wall = line(1.6, 1.2, 3.0, 1.2, 20)  # the side wall
    segments = segments_of(floor, corner, wall)
    lines = np.array([segments.labels[0]])
    points, owners = extension_claims(segments, lines, PARAMS)
    covered = set(np.flatnonzero(segments.labels == lines[0]).tolist()) | set(points.tolist())
    assert set(range(44)) <= covered  # the whole line, corner included
    assert not set(range(44, 64)) & covered  # no wall point
    assert set(owners.tolist()) == {segments.labels[0]}


def test_spread_claims_fragments_on_the_line_on_its_side_only():
    main = line(2.0, -0.5, 2.0, 0.5)
    fragment = line(2.0, 1.0, 2.0, 1.1, 3)  # between furniture legs
    behind = line(-2.0, 1.0, -2.0, 1.1, 3)  # the mirror image behind: not on the line
    off = line(2.2, 1.3, 2.2, 1.4, 3)  # 0.2 m behind the line: structure
    segments = segments_of(main, fragment, behind, off)
    points, _ = spread_claims(segments, np.array([segments.labels[0]]), PARAMS)
    assert set(range(40, 43)) <= set(points.tolist())
    assert not set(range(43, 49)) & set(points.tolist())


def test_lines_on_the_far_side_of_the_strongest_line_are_weighted_down():
    floor = line(2.0, -1.0, 2.0, 1.0)  # the strongest line: the down side is +x
    behind = line(-1.5, -0.3, -1.5, 0.3, 12)  # furniture met higher up, behind
    aside = line(3.0, 1.5, 3.0, 1.9, 12)  # another line on the down side
    segments = segments_of(floor, behind, aside)
    new_counts = segments.sizes.astype(float)
    gates = np.ones(len(segments), dtype=bool)
    weights = up_side_weights(segments, new_counts, gates, PARAMS)
    at = lambda point: segments.labels[point]  # noqa: E731
    assert weights[at(0)] == 1.0 and weights[at(52)] == 1.0
    assert weights[at(40)] == PARAMS.up_side_weight
    # too few new points on the strongest line: no side is known, nothing is weighted
    assert (up_side_weights(segments, np.minimum(new_counts, 5.0), gates, PARAMS) == 1.0).all()
    no_side = dataclasses.replace(PARAMS, up_side_weight=1.0)
    assert (up_side_weights(segments, new_counts, gates, no_side) == 1.0).all()


def test_the_best_claim_wins():
    floor = line(1.5, -1.0, 1.5, 1.0)
    tail = line(1.5, 1.05, 1.5, 1.2, 4)
    segments = segments_of(floor, tail)
    score = np.zeros(len(segments))
    score[segments.labels[0]] = 0.8
    owner, best = best_claims(segments, score, PARAMS)
    assert (owner == segments.labels[0]).all() and (best == 0.8).all()
