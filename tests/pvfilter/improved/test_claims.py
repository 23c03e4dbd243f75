"""Claims: detected lines take in the points at their ends and along them; the best claim
wins."""

import dataclasses
import math

import numpy as np

from pvfilter.improved import ImprovedParams, segment_scan
from pvfilter.improved.claims import best_claims, extension_claims, spread_claims

from .conftest import HEIGHT_M

PARAMS = ImprovedParams(lidar_height_m=HEIGHT_M)


def line(x0, y0, x1, y1, count=40):
    return np.column_stack((np.linspace(x0, x1, count), np.linspace(y0, y1, count)))


def segments_of(*parts):
    points = np.concatenate(parts)
    return segment_scan(points, np.arange(len(points)), math.radians(0.5), PARAMS)


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


def test_the_best_claim_wins():
    floor = line(1.5, -1.0, 1.5, 1.0)
    tail = line(1.5, 1.05, 1.5, 1.2, 4)
    segments = segments_of(floor, tail)
    score = np.zeros(len(segments))
    score[segments.labels[0]] = 0.8
    owner, best = best_claims(segments, score, PARAMS)
    assert (owner == segments.labels[0]).all() and (best == 0.8).all()


def test_a_scored_piece_of_a_floor_line_claims_the_rest_of_it_at_its_own_score():
    # a floor line 1.5 m ahead whose middle alone is new (the rest settles in front of
    # the wall behind it): the scored middle takes in the stretches along the same line,
    # as far as its own score, and not a wall beside them that crosses the line
    middle = line(1.5, -0.2, 1.5, 0.2, 12)
    ends = (line(1.5, -1.2, 1.5, -0.6, 20), line(1.5, 0.6, 1.5, 1.2, 20))
    wall = line(1.0, 1.6, 2.0, 1.6, 20)  # beside them, across the line
    segments = segments_of(middle, *ends, wall)
    score = np.zeros(len(segments))
    score[segments.labels[0]] = 0.7
    owner, best = best_claims(segments, score, PARAMS)
    on_line = np.abs(segments.points[:, 0] - 1.5) < 0.01
    assert (best[on_line] == 0.7).all() and (owner[on_line] == segments.labels[0]).all()
    assert (best[~on_line] == 0.0).all()
    no_spread = dataclasses.replace(PARAMS, spread=False)
    _, best = best_claims(segments, score, no_spread)
    assert (best[on_line] == 0.7).sum() < on_line.sum() / 2
