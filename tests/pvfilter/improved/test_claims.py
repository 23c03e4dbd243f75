"""Claims: detected lines take in the points at their ends and along them; the best claim
wins."""

import dataclasses
import math

import numpy as np

from pvfilter.improved import ImprovedParams, segment_scan
from pvfilter.improved.claims import best_claims, extension_claims, spread_claims
from pvfilter.improved.geometry import floor_distance, implied_tilt

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


def test_extension_leaves_a_wall_the_line_runs_into_to_the_wall():
    # nose down in a corridor: the side wall is seen up to where the floor line meets it;
    # its last centimetres lie within the tolerance of the floor line too, but on the
    # wall's own line
    wall = line(0.0, -0.75, 0.495, -0.75, 100)  # 5 mm apart, as a 0.25° scanner sees it
    floor = line(0.5, -0.75, 0.5, 0.5, 250)
    segments = segments_of(wall, floor)
    floor_line = segments.labels[-1]
    points, _ = extension_claims(segments, np.array([floor_line]), PARAMS)
    taken = set(points.tolist()) | set(np.flatnonzero(segments.labels == floor_line).tolist())
    assert set(range(100, 350)) <= taken  # the floor line's own points at the corner too
    assert not taken & set(range(100)), sorted(taken & set(range(100)))  # before: 93-99


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


def test_a_claimed_point_that_is_not_new_takes_part_of_the_lines_score():
    # the scored middle of a floor line claims its ends; where an end is new (in space
    # the level view saw free) it takes the line's score, where it is not (on the view's
    # surface: the foot of the wall behind lies on the line as well) a part of it, and
    # the line's own points keep the whole score whether new or not
    middle = line(1.5, -0.2, 1.5, 0.2, 12)
    ends = (line(1.5, -1.2, 1.5, -0.6, 20), line(1.5, 0.6, 1.5, 1.2, 20))
    segments = segments_of(middle, *ends)
    score = np.zeros(len(segments))
    score[segments.labels[0]] = 0.8
    new = np.ones(len(segments.points), bool)
    new[12:32] = False  # one end on the view
    new[0:3] = False  # and three of the middle's own points
    owner, best = best_claims(segments, score, PARAMS, new_valid=new)
    assert (owner == segments.labels[0]).all()
    assert (best[:12] == 0.8).all()
    assert (best[12:32] == PARAMS.claimed_not_new_weight * 0.8).all()
    assert (best[32:] == 0.8).all()
    # an end's own segment that scores above the weighted claim keeps its points
    score[segments.labels[12]] = 0.5
    owner, best = best_claims(segments, score, PARAMS, new_valid=new)
    assert (owner[12:32] == segments.labels[12]).all() and (best[12:32] == 0.5).all()


def seam_scan(later_tilt_deg: float, ring: bool = True):
    """A full turn of 720 beams whose sweep starts and ends behind the sensor, on a floor
    line at 25 deg: the later half measured a turn later at ``later_tilt_deg``, a wall
    ahead between them. Segments: the earlier half, the wall, the later half."""
    increment = math.radians(0.5)
    earlier, later = np.arange(0, 60), np.arange(660, 720)
    wall = np.arange(300, 420)

    def on_line(beams, x):
        angles = -math.pi + beams * increment
        return np.column_stack((np.full(beams.size, x), x * np.tan(angles)))

    def floor_x(tilt_deg):
        return -float(floor_distance(math.radians(tilt_deg), PARAMS))

    points = np.concatenate(
        (
            on_line(earlier, floor_x(25.0)),
            on_line(wall, 3.0),
            on_line(later, floor_x(later_tilt_deg)),
        )
    )
    beams = np.concatenate((earlier, wall, later))
    return segment_scan(points, beams, increment, PARAMS, ring=ring)


def test_a_floor_line_cut_by_the_seam_of_a_full_turn_claims_its_later_half():
    # levelling at 0.3 rad/s, the later half lies 6 cm farther out than the earlier: out of
    # the spread's reach, and (in a scan) within the margin of the wall behind it
    segments = seam_scan(later_tilt_deg=22.4)
    assert segments.seam_joined and len(segments) == 3
    score = np.array([0.9, 0.0, 0.0])
    tilt = implied_tilt(segments.distances, PARAMS)
    sweep_increment_s = 0.1 / 720
    later = segments.labels == 2
    _, best = best_claims(segments, score, PARAMS, tilt, -1, sweep_increment_s)
    assert (best[later] == 0.9).all() and (best[segments.labels == 1] == 0.0).all()
    _, best = best_claims(segments, score, PARAMS, tilt, +1, sweep_increment_s)
    assert (best[later] == 0.0).all()  # the line on the up side: no floor line to follow
    _, best = best_claims(segments, score, PARAMS)  # no tilts: no seam claims
    assert (best[later] == 0.0).all()
    _, best = best_claims(seam_scan(22.4, ring=False), score, PARAMS, tilt, -1, 0.1 / 720)
    assert (best[later] == 0.0).all()


def test_a_jump_at_the_seam_the_pitch_cannot_make_is_not_the_line():
    # the same halves measured 1 ms apart: the pitch moves less than 0.2 deg meanwhile,
    # so the later half is structure behind the line
    segments = seam_scan(later_tilt_deg=22.4)
    score = np.array([0.9, 0.0, 0.0])
    tilt = implied_tilt(segments.distances, PARAMS)
    _, best = best_claims(segments, score, PARAMS, tilt, -1, 0.001 / 720)
    assert (best[segments.labels == 2] == 0.0).all()
