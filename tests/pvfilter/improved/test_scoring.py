"""Scoring: the geometry gates, the two sides of a tilted plane, the IMU, the length, the
world-static veto."""

import dataclasses
import math

import numpy as np
import pytest

from pvfilter.improved import ImprovedParams, ImprovedPitchVariationFilter, segment_scan
from pvfilter.improved.evidence import STATIC_TOLERANCE_M, Offsets
from pvfilter.improved.imu import Attitude
from pvfilter.improved.scoring import (
    COINCIDENT_WEIGHT,
    CONFIDENT_SCORE,
    HELD_ON_VIEW,
    HELD_TILT_TOLERANCE,
    IMU_SUPPORT,
    STRONG_LINE_M,
    HeldLine,
    line_pitch,
    score_segments,
)
from pvfilter.synthetic import room_segments

from .conftest import HEIGHT_M, INCREMENT, PARAMS, ROOM, line, scored, tilted_scan


def at(segments, point):
    return segments.labels[point]


def test_a_new_floor_line_across_the_direction_of_travel_scores_its_share_of_new_points():
    _, result = scored(line(1.5, -1.0, 1.5, 1.0))
    assert result.gates.tolist() == [True] and result.scores[0] == pytest.approx(1.0)
    half = np.arange(40) < 20
    # the other half seen through the level view: each counts fully against the line
    _, result = scored(line(1.5, -1.0, 1.5, 1.0), new=half, through=~half)
    assert result.scores[0] == pytest.approx(0.5)
    # the other half on the view (a line settling in front of a wall): ambiguous, each
    # counts COINCIDENT_WEIGHT
    _, result = scored(line(1.5, -1.0, 1.5, 1.0), new=half)
    assert result.scores[0] == pytest.approx(20 / (20 + COINCIDENT_WEIGHT * 20))
    assert result.scores[0] > 0.5


def test_lines_along_the_direction_of_travel_or_too_near_fail_the_gates():
    _, along = scored(line(0.5, 1.2, 3.0, 1.2))
    assert not along.gates.any() and not along.scores.any()
    near = PARAMS.min_line_distance_m * 0.8
    _, close = scored(line(near, -0.3, near, 0.3))
    assert not close.gates.any()


def test_a_short_line_scores_in_proportion_to_its_length():
    # 0.4 m of a line 0.8 m long (line_length_m) scores half
    _, result = scored(line(2.0, -0.2, 2.0, 0.2, 40))
    length = math.sqrt(12.0 * np.var(np.linspace(-0.2, 0.2, 40)))
    assert result.scores[0] == pytest.approx(length / PARAMS.line_length_m, rel=1e-6)


def test_a_strong_short_piece_takes_the_length_of_the_line_its_collinear_fragments_make():
    # 0.3 m of new floor line, and 0.8 m of the same line (not new: it runs along the wall
    # behind it) beyond a gap: one floor line, 1.4 m long, that scores the new piece's share
    piece = line(2.0, -0.6, 2.0, -0.3, 30)
    rest = line(2.0, 0.0, 2.0, 0.8, 60)
    new = np.arange(90) < 30
    segments, result = scored(piece, rest, new=new)
    assert segments.labels[0] != segments.labels[30]
    assert result.scores[at(segments, 0)] == pytest.approx(1.0)
    assert result.scores[at(segments, 30)] == 0.0
    # alone (or beside a wall that crosses it) it is a short line
    wall = line(1.8, 0.0, 2.6, 0.0, 60)
    for parts in ((piece,), (piece, wall)):
        segments, result = scored(*parts, new=new[: sum(len(p) for p in parts)])
        assert result.scores[at(segments, 0)] < 0.6


def test_a_floor_line_cut_into_pieces_shows_the_pitch_event_with_their_new_points_together():
    # a floor line 2 m ahead that two chair legs cut into three pieces of 12 new points:
    # no piece alone has down_side_min_new (20), the line has 36
    pieces = [line(2.0, y0, 2.0, y0 + 0.3, 12) for y0 in (-0.8, -0.2, 0.4)]
    legs = [line(1.0, y, 1.0, y + 0.02, 3) for y in (-0.4, 0.2)]
    parts = (pieces[0], legs[0], pieces[1], legs[1], pieces[2])
    new = np.concatenate([np.full(len(p), len(p) == 12) for p in parts])
    segments, result = scored(*parts, new=new)
    assert len({at(segments, i) for i in (0, 15, 30)}) == 3  # three segments
    assert result.down_side == 1
    assert result.scores[at(segments, 15)] == pytest.approx(1.0)
    assert result.new_counts[at(segments, 15)] == 36
    # one piece alone shows no pitch event: its score is weighted as in clutter
    segments, alone = scored(pieces[1])
    assert alone.down_side == 0
    assert alone.scores[0] <= PARAMS.up_side_weight


def test_a_line_on_the_up_side_nearer_than_a_ceiling_can_be_is_weighted_down():
    floor = line(1.44, -1.5, 1.44, 1.5, 60)  # the strongest line: 10 deg, floor ahead
    furniture = line(-1.0, -0.5, -1.0, 0.5, 30)  # behind, 1 m: no ceiling that low
    ceiling = line(-10.0, -1.5, -10.0, 1.5, 30)  # behind, beyond (1.9 - 0.25) / sin 10 deg
    segments, result = scored(floor, furniture)
    assert result.down_side == 1
    assert result.down_tilt_rad == pytest.approx(math.radians(10.0), abs=1e-3)
    assert result.scores[at(segments, 0)] == pytest.approx(1.0)
    assert result.scores[at(segments, 60)] == pytest.approx(PARAMS.up_side_weight)
    segments, result = scored(floor, ceiling)
    assert result.scores[at(segments, 60)] == pytest.approx(1.0)  # a ceiling: kept
    no_side = dataclasses.replace(PARAMS, up_side_weight=1.0)
    segments, flat = scored(floor, furniture, params=no_side)
    assert flat.scores[at(segments, 60)] == pytest.approx(1.0)


def test_where_the_strongest_line_leaves_no_room_for_a_ceiling_behind_the_floor_is_behind():
    # nose up: the floor 1.3 m behind (11 deg), the ceiling ahead at 9 m with more new
    # points; taken for the floor, the line ahead (1.6 deg) would leave no ceiling nearer
    # than tens of metres behind, while 11 deg puts a ceiling ahead from 8.6 m on
    floor = line(-1.3, -0.7, -1.3, 0.7, 60)
    ceiling = line(9.0, -3.0, 9.0, 3.0, 100)
    assert 8.0 < (PARAMS.min_ceiling_m - HEIGHT_M) / (HEIGHT_M / 1.3) < 9.0
    segments, result = scored(floor, ceiling)
    assert result.down_side == -1
    assert result.down_tilt_rad == pytest.approx(math.asin(HEIGHT_M / 1.3), abs=1e-3)
    assert result.scores[at(segments, 0)] == pytest.approx(1.0)  # the floor
    assert result.scores[at(segments, 60)] == pytest.approx(1.0)  # the ceiling
    # furniture behind that a ceiling ahead cannot explain leaves the floor ahead
    furniture = line(-1.0, -0.5, -1.0, 0.5, 30)
    floor_ahead = line(1.44, -1.5, 1.44, 1.5, 60)
    segments, result = scored(floor_ahead, furniture)
    assert result.down_side == 1


def test_a_ceiling_may_lie_as_near_as_the_steepest_strong_floor_line_allows():
    # a rotating scan measured the floor behind at two tilts, 12 deg and (its strongest
    # line) 7.2 deg; a ceiling 10 m ahead is too near for 7.2 deg (13.2 m), not for 12
    steep = line(-1.2, 0.2, -1.2, 1.0, 40)
    shallow = line(-2.0, -2.0, -2.0, -0.2, 80)
    ceiling = line(10.0, -2.0, 10.0, 2.0, 50)
    segments, result = scored(steep, shallow, ceiling)
    assert result.down_side == -1
    assert result.down_tilt_rad == pytest.approx(math.asin(HEIGHT_M / 2.0), abs=1e-3)
    assert result.scores[at(segments, 120)] == pytest.approx(1.0)


def test_the_imu_supports_a_line_where_it_puts_the_floor_and_weighs_down_one_it_cannot():
    tilt = math.radians(10.0)
    floor = line(HEIGHT_M / math.sin(tilt), -1.5, HEIGHT_M / math.sin(tilt), 1.5, 60)
    none_new = np.zeros(60, bool)
    agreeing = Attitude(tilt, 0.0, math.radians(2.0))
    _, result = scored(floor, new=none_new, attitude=agreeing)
    assert result.scores[0] == pytest.approx(IMU_SUPPORT)  # alone: below the default p_th
    half = np.arange(60) < 30
    _, result = scored(floor, new=half, attitude=agreeing, through=~half)
    assert result.scores[0] == pytest.approx(1.0 - 0.5 * (1.0 - IMU_SUPPORT))
    level = Attitude(0.0, 0.0, math.radians(2.0))  # the robot is level: no floor at 1.44 m
    _, result = scored(floor, attitude=level)
    assert result.scores[0] == pytest.approx(PARAMS.up_side_weight)
    # the IMU shows the plane tilted nose down by 5 deg, the line needs 10: the floor is
    # ahead and only its distance is in doubt (a lagging estimate): neither cue
    lagging = Attitude(math.radians(5.0), 0.0, math.radians(2.0))
    _, result = scored(floor, attitude=lagging)
    assert result.scores[0] == pytest.approx(1.0)
    assert result.scan_scores[0] == pytest.approx(1.0)


def test_a_lagging_imu_vetoes_no_line_the_body_could_have_tilted_to_since_its_estimate():
    # the onset of a shove: the estimate still reads level, the scan already shows the
    # floor 10 deg down; the body can reach 17 deg in the estimate's lag (reach_rad)
    level = Attitude(0.0, 0.0, math.radians(2.0), reach_rad=math.radians(17.0))
    for tilt_deg, vetoed in ((10.0, False), (22.0, True)):
        distance = HEIGHT_M / math.sin(math.radians(tilt_deg))
        _, result = scored(line(distance, -1.5, distance, 1.5, 60), attitude=level)
        assert result.scan_scores[0] == pytest.approx(1.0)
        assert result.scores[0] == pytest.approx(PARAMS.up_side_weight if vetoed else 1.0)
        assert result.imu_contradicted  # beyond the band either way: the next scan vetoes
    # a line the band explains is not contradicted
    tilted = Attitude(math.radians(10.0), 0.0, math.radians(2.0))
    distance = HEIGHT_M / math.sin(math.radians(10.0))
    _, result = scored(line(distance, -1.5, distance, 1.5, 60), attitude=tilted)
    assert not result.imu_contradicted


def test_a_line_on_the_imus_up_side_is_weighted_as_the_up_side_once():
    # the IMU shows the plane 6 deg nose up: the floor is behind; ahead, a new line at
    # 1.6 m is no floor, nor a ceiling (none nearer than 15.8 m at 6 deg), but a surface
    # above the scanner that the rising plane meets (a table's underside, 0.17 m above
    # it): weighted as the up side is, not vetoed as a floor line besides
    nose_up = Attitude(math.radians(-6.0), 0.0, math.radians(2.0))
    assert nose_up.tilted and nose_up.down_side == -1
    _, result = scored(line(1.6, -1.5, 1.6, 1.5, 60), attitude=nose_up)
    assert result.scan_scores[0] == pytest.approx(PARAMS.up_side_weight)
    assert result.scores[0] == pytest.approx(PARAMS.up_side_weight)
    # with the IMU level, the same line needs 9 deg nose down that the IMU cannot explain
    level = Attitude(0.0, 0.0, math.radians(2.0))
    _, result = scored(line(1.6, -1.5, 1.6, 1.5, 60), attitude=level)
    assert result.scores[0] == pytest.approx(PARAMS.up_side_weight)
    assert result.imu_contradicted


def test_an_imu_that_shows_the_plane_level_lends_no_line_its_support():
    # a band as wide as a lagging estimator earns (5 deg), the estimate level: the IMU
    # cannot tell a plane tilted 4 deg from a level one, so a wall ahead at the floor's
    # range for 4 deg gets no support from it, whatever side the estimate's sign names
    tilt = math.radians(4.0)
    wall = line(HEIGHT_M / math.sin(tilt), -1.5, HEIGHT_M / math.sin(tilt), 1.5, 60)
    half_new = np.arange(60) < 30  # reappearing after the robot levelled
    for pitch_deg in (0.2, -0.2):
        wide_level = Attitude(math.radians(pitch_deg), 0.0, math.radians(5.0))
        assert not wide_level.tilted
        _, result = scored(wall, new=half_new, attitude=wide_level)
        assert 0.0 < result.scores[0] == pytest.approx(result.scan_scores[0])


def test_the_imus_sign_counts_in_the_band_a_floor_line_must_lie_in():
    # a floor line ahead needs the plane 3 deg nose down; an estimate 1.5 deg nose up
    # (within a 2 deg band of level, so not "tilted") is 4.5 deg from it, one 1.5 deg
    # nose down only 1.5: the first cannot explain the line, the second can
    tilt = math.radians(3.0)
    distance = HEIGHT_M / math.sin(tilt)
    ahead = line(distance, -1.5, distance, 1.5, 60)
    for pitch_deg, explained in ((1.5, True), (-1.5, False)):
        estimate = Attitude(math.radians(pitch_deg), 0.0, math.radians(2.0))
        assert not estimate.tilted
        _, result = scored(ahead, attitude=estimate)
        assert result.scan_scores[0] == pytest.approx(1.0)  # the scan alone: the floor
        assert result.scores[0] == pytest.approx(1.0 if explained else PARAMS.up_side_weight)
        assert result.imu_contradicted is not explained
    # behind, the same: a nose-up estimate explains a floor line behind, a nose-down not
    behind = line(-distance, -1.5, -distance, 1.5, 60)
    for pitch_deg, explained in ((-1.5, True), (1.5, False)):
        estimate = Attitude(math.radians(pitch_deg), 0.0, math.radians(2.0))
        _, result = scored(behind, attitude=estimate)
        assert result.scores[0] == pytest.approx(1.0 if explained else PARAMS.up_side_weight)


def test_returns_beyond_a_line_weigh_down_the_imus_support_for_it():
    # the IMU puts the floor 1.44 m ahead, where a wall the level view knows stands (no
    # new point); returns 2.5 m farther out beside it show that the plane does not meet
    # the floor there: the IMU's support is weighted down as the scan's own score would be
    tilt = math.radians(10.0)
    distance = HEIGHT_M / math.sin(tilt)
    wall = line(distance, -0.5, distance, 0.5, 30)
    open_space = line(distance + 2.5, 0.8, distance + 2.5, 1.6, 30)
    agreeing = Attitude(tilt, 0.0, math.radians(2.0))
    none_new = np.zeros(60, bool)
    _, alone = scored(wall, new=none_new[:30], attitude=agreeing)
    assert alone.scores[0] == pytest.approx(IMU_SUPPORT)
    segments, beside = scored(wall, open_space, new=none_new, attitude=agreeing)
    assert beside.scores[at(segments, 0)] == pytest.approx(IMU_SUPPORT * PARAMS.up_side_weight)


def test_the_strongest_confident_line_gives_the_pitch_the_imu_is_checked_against():
    # h / sin(pitch) from the sensor: ahead for nose down, behind (negative) for nose up
    for pitch in (math.radians(10.0), math.radians(-6.0)):
        x = math.copysign(HEIGHT_M / math.sin(abs(pitch)), pitch)
        segments, result = scored(line(x, -1.5, x, 1.5, 60))
        assert line_pitch(segments, result, PARAMS) == pytest.approx(pitch, abs=1e-3)
    weak = line(2.0, -1.5, 2.0, 1.5, 60)
    segments, result = scored(weak, new=np.arange(60) < 30)  # half new: not confident
    assert line_pitch(segments, result, PARAMS) is None


class Told:
    """A stand-in world-static test: the earlier scan saw one beam in ``seen_every``, and
    those returns stayed put (or moved 0.5 m); the test tells (``tells``: for all beams,
    or a function of the beam indices) or not."""

    hold_tilt_rad = math.pi / 2  # no tilt a standing robot could not hold

    def __init__(self, tells, seen_every=1, stayed=True):
        self.tells, self.seen_every, self.stayed = tells, seen_every, stayed

    def offsets(self, beams, floor_shift_m=None):
        moved_m = 0.0 if self.stayed else 0.5
        world_m = np.where(beams % self.seen_every == 0, moved_m, np.nan)  # NaN: not seen
        tells = self.tells(beams) if callable(self.tells) else np.full(len(beams), self.tells)
        return Offsets(world_m, tells, np.full(len(beams), STATIC_TOLERANCE_M))

    offsets_or_farther = offsets  # no older scan kept


def test_a_line_that_stayed_put_in_the_world_while_the_sensor_moved_is_a_wall():
    wall = line(1.5, -1.0, 1.5, 1.0)
    _, result = scored(wall, static=Told(True))
    assert result.scores[0] == 0.0
    _, standing = scored(wall, static=Told(False))  # the sensor stood: nothing told
    assert standing.scores[0] == pytest.approx(1.0)


def test_a_wall_that_echoes_on_some_beams_only_is_told_by_the_beams_the_earlier_scan_saw():
    # a dark or glossy face returns on some beams only, a different set each scan: the
    # earlier scan saw one beam in three of it, and those stayed put. The beams it did not
    # see tell nothing either way, so the wall is a wall (counted as moved, they made it
    # one third static; where the sensor stood, too few told and it was not weighed)
    wall = line(1.5, -1.0, 1.5, 1.0)
    _, result = scored(wall, static=Told(True, seen_every=3))
    assert result.scores[0] == 0.0
    # one beam in five is a part of the line the earlier scan had in view, not a sample
    _, unseen = scored(wall, static=Told(True, seen_every=5))
    assert unseen.scores[0] == pytest.approx(1.0)
    # a floor line the earlier scan saw one beam in three of moved with the sensor there
    _, floor = scored(wall, static=Told(True, seen_every=3, stayed=False))
    assert floor.scores[0] == pytest.approx(1.0)


def test_the_world_static_share_counts_the_seen_points_that_tell():
    # every beam seen; the test tells on three in five of them, all of which stayed: the
    # whole share that told stayed put (a wall), not three fifths of the line
    wall = line(1.5, -1.0, 1.5, 1.0)
    _, most = scored(wall, static=Told(lambda beams: beams % 5 < 3))
    assert most.scores[0] == 0.0
    # ... on one in three: fewer than half of the seen points tell, and it is not weighed
    _, few = scored(wall, static=Told(lambda beams: beams % 3 == 0))
    assert few.scores[0] == pytest.approx(1.0)


def test_the_imu_supports_no_line_the_scan_shows_is_a_wall():
    # the IMU puts the floor 1.44 m ahead, where a wall is that the level view knows (no
    # new point): it may be the floor, so the IMU alone lends it IMU_SUPPORT; but a wall
    # that stayed put in the world while the sensor moved is not the floor, whatever the IMU
    tilt = math.radians(10.0)
    distance = HEIGHT_M / math.sin(tilt)
    wall = line(distance, -1.5, distance, 1.5, 60)
    agreeing = Attitude(tilt, 0.0, math.radians(2.0))
    none_new = np.zeros(60, bool)
    _, unknown = scored(wall, new=none_new, attitude=agreeing, static=Told(False))
    assert unknown.scores[0] == pytest.approx(IMU_SUPPORT)
    _, stayed = scored(wall, new=none_new, attitude=agreeing, static=Told(True))
    assert stayed.scores[0] == 0.0


def test_a_wall_seen_beside_open_space_is_not_the_floor():
    # a tilted plane meets the floor along the whole width; a wall 1.44 m ahead with the
    # room open beside it (returns 6 m out) is weighted like the up side
    floor_scan, _ = tilted_scan(pitch_rad=math.radians(10.0), walls=room_segments(6, 4, 3, 3))
    box = np.array([[[1.44, -0.3], [1.44, 0.3]]])
    walls = np.concatenate((room_segments(6, 4, 3, 3), box))
    box_scan, _ = tilted_scan(walls=walls)
    for scan, expected in ((floor_scan, 1.0), (box_scan, PARAMS.up_side_weight)):
        valid = scan.valid_mask()
        points, beams = scan.points()[valid], np.flatnonzero(valid)
        segments = segment_scan(points, beams, INCREMENT, PARAMS)
        ahead = np.flatnonzero((points[:, 0] > 1.0) & (np.abs(points[:, 1]) < 0.1))[0]
        new = np.abs(points[:, 0] - 1.44) < 0.05  # only the line is new
        result = score_segments(segments, new, 0.0, None, PARAMS)
        label = segments.labels[ahead]
        length = math.sqrt(12.0 * segments.spread_along[label]) / PARAMS.line_length_m
        share = result.share_new[label] * min(length, 1.0)
        assert result.scores[label] == pytest.approx(expected * share, rel=1e-6)


def test_a_weak_line_alone_shows_no_pitch_event():
    # 12 new points across the direction of travel on 1.2 m of line (shorter than
    # STRONG_LINE_M), nothing else: clutter, weighted down; with the IMU saying the plane
    # is tilted there, it is the floor line
    tilt = math.radians(10.0)
    weak = line(HEIGHT_M / math.sin(tilt), -0.6, HEIGHT_M / math.sin(tilt), 0.6, 12)
    _, alone = scored(weak)
    assert alone.down_side == 0 and alone.scores[0] == pytest.approx(PARAMS.up_side_weight)
    _, with_imu = scored(weak, attitude=Attitude(tilt, 0.0, math.radians(2.0)))
    assert with_imu.down_side == 1 and with_imu.scores[0] == pytest.approx(1.0)


def test_a_long_floor_line_far_out_is_strong_however_few_beams_it_spans():
    # a plane pitched by under a degree meets the floor 20 m ahead, across a 2.8 m hall:
    # 16 beams (fewer than down_side_min_new) but 2.8 m of new line, a pitch event
    assert 16 < PARAMS.down_side_min_new and 2.8 > STRONG_LINE_M
    _, far = scored(line(20.0, -1.4, 20.0, 1.4, 16))
    assert far.down_side == 1 and far.scores[0] == pytest.approx(1.0)
    # the same beams on 1 m of line (a face far out), or half of them new on the long
    # line (1.4 m of it): no pitch event
    _, short = scored(line(20.0, -0.5, 20.0, 0.5, 16))
    _, half_new = scored(line(20.0, -1.4, 20.0, 1.4, 16), new=np.arange(16) < 8)
    for result in (short, half_new):
        assert result.gates[0] and result.down_side == 0
    assert short.scores[0] == pytest.approx(PARAMS.up_side_weight)


def test_a_floor_line_that_echoes_on_every_other_beam_is_as_long_as_the_beams_it_spans():
    # a floor line 1.5 m behind a plane pitched 9.5 deg, met at a grazing angle: 12
    # echoes, every other beam silent, on 1.2 m of line (shorter than STRONG_LINE_M).
    # Over 12 beams it is clutter (12 new points, fewer than down_side_min_new); over 23
    # beams it is a floor line as long as 23 returns
    x = -HEIGHT_M / math.sin(math.radians(9.5))
    points = line(x, 0.6, x, -0.6, 12)
    for beams, down in ((np.arange(12), 0), (np.arange(0, 24, 2), -1)):
        segments = segment_scan(points, beams, INCREMENT, PARAMS)
        result = score_segments(segments, np.ones(12, bool), 0.0, None, PARAMS)
        assert len(segments) == 1 and result.gates[0]
        assert result.down_side == down
        assert result.scores[0] == pytest.approx(1.0 if down else PARAMS.up_side_weight)


def test_a_face_strewn_over_beams_without_returns_counts_at_most_twice_its_points():
    # 10 new returns 1 m ahead, 5 beams apart (the rest invalid or silent): over 46 beams
    # they would count as 46, a pitch event; bounded at twice their number (20), they
    # just make down_side_min_new, and 9 of them do not
    points = line(1.0, 0.2, 1.0, -0.2, 10)
    segments = segment_scan(points, np.arange(0, 50, 5), INCREMENT, PARAMS)
    result = score_segments(segments, np.ones(10, bool), 0.0, None, PARAMS)
    assert len(segments) == 1 and result.new_counts[0] == pytest.approx(20.0)
    assert result.down_side == 1
    segments = segment_scan(points[:9], np.arange(0, 45, 5), INCREMENT, PARAMS)
    result = score_segments(segments, np.ones(9, bool), 0.0, None, PARAMS)
    assert result.new_counts[0] == pytest.approx(18.0) and result.down_side == 0


def test_returns_strewn_over_silent_beams_make_no_long_line():
    # 8 new returns on every tenth beam, 2.5 m ahead, spread over 1.8 m: over 71 beams
    # they are no line, however long (MAX_ECHO_FILL bounds them at 16 new points); the
    # same 1.8 m on every other beam (15 returns over 29 beams) is a floor line far out
    x = 2.5
    for beams, down in ((np.arange(0, 80, 10), 0), (np.arange(0, 30, 2), 1)):
        points = line(x, 0.9, x, -0.9, len(beams))
        segments = segment_scan(points, beams, INCREMENT, PARAMS)
        result = score_segments(segments, np.ones(len(beams), bool), 0.0, None, PARAMS)
        assert len(segments) == 1 and result.gates[0]
        assert result.down_side == down


def test_a_line_that_keeps_a_held_floor_lines_place_scores_as_a_confident_strong_line():
    # a floor line 1.8 m ahead (8 deg at 0.25 m) with no new point: it settled within the
    # margin of what lies behind it, while the sensor turned in place
    x = HEIGHT_M / math.sin(math.radians(8.0))
    points = line(x, -1.0, x, 1.0)
    segments = segment_scan(points, np.arange(len(points)), INCREMENT, PARAMS)
    nothing_new = np.zeros(len(points), bool)

    def score(held):
        return score_segments(segments, nothing_new, 0.0, None, PARAMS, held=held)

    assert score(None).scores.max() == 0.0
    held = score(HeldLine(1, math.radians(8.0), 0.0))
    assert held.scores[0] >= CONFIDENT_SCORE and held.new_counts[0] >= PARAMS.down_side_min_new
    assert held.down_side == 1
    # another tilt, another direction or the other side: not the held line
    tilt = math.radians(8.0) + 2.0 * HELD_TILT_TOLERANCE
    for other in (HeldLine(1, tilt, 0.0), HeldLine(1, math.radians(8.0), 0.2),
                  HeldLine(-1, math.radians(8.0), 0.0)):  # fmt: skip
        assert score(other).scores.max() == 0.0


def test_a_held_lines_place_is_kept_only_where_the_imu_can_explain_the_line():
    # the held 8 deg tilt's floor line 1.8 m ahead, no new point: an estimate tilted
    # nose down by about that much explains it, a level one cannot (it would need the
    # plane 8 deg nose down, 6 past the level estimate's 2 deg band): not kept then
    x = HEIGHT_M / math.sin(math.radians(8.0))
    points = line(x, -1.0, x, 1.0)
    segments = segment_scan(points, np.arange(len(points)), INCREMENT, PARAMS)
    nothing_new = np.zeros(len(points), bool)
    held = HeldLine(1, math.radians(8.0), 0.0)
    for pitch_deg, kept in ((8.5, True), (0.0, False)):
        estimate = Attitude(math.radians(pitch_deg), 0.0, math.radians(2.0))
        result = score_segments(segments, nothing_new, 0.0, estimate, PARAMS, held=held)
        assert bool(result.scores[0] >= CONFIDENT_SCORE) == kept


def _wall_in_the_held_place(**kwargs):
    """Score a wall of no new points where a held 8 deg tilt puts its floor line ahead (the
    keyword arguments go to :func:`score_segments`); and the wall's points."""
    x = HEIGHT_M / math.sin(math.radians(8.0))
    points = line(x, -1.0, x, 1.0)
    segments = segment_scan(points, np.arange(len(points)), INCREMENT, PARAMS)
    nothing_new = np.zeros(len(points), bool)
    held = HeldLine(1, math.radians(8.0), 0.0)
    return score_segments(segments, nothing_new, 0.0, None, PARAMS, held=held, **kwargs), points


def test_a_wall_that_a_turn_sweeps_through_a_held_lines_place_does_not_keep_it():
    # while the sensor turns, a wall fixed in the world passes through the place of the
    # floor line held in the sensor frame: for a scan it keeps that place, but it stayed
    # put in the world (the world-static test under a turn)
    def score(static):
        return _wall_in_the_held_place(static=static)[0]

    assert score(Told(False)).scores[0] >= CONFIDENT_SCORE  # nothing told: held
    stayed = score(Told(True))
    assert stayed.scores[0] == 0.0 and stayed.new_counts[0] == 0
    assert stayed.down_side == 0


def test_a_wall_on_the_level_view_does_not_keep_a_held_lines_place():
    # the turn brings a wall into the held floor line's place, and the world-static test
    # cannot tell (the turn alone moves no return along its beam), but the wall stands
    # where the level view has it; a floor line held through the turn lies in front of
    # the view's surface
    _, points = _wall_in_the_held_place()
    ranges = np.hypot(points[:, 0], points[:, 1])

    def score(view_m):
        return _wall_in_the_held_place(static=Told(False), view_valid=view_m)[0]

    on_view = score(ranges + 0.5 * STATIC_TOLERANCE_M)
    assert on_view.scores[0] == 0.0 and on_view.down_side == 0
    furniture_behind = score(ranges + 0.3)
    assert furniture_behind.scores[0] >= CONFIDENT_SCORE
    unknown = score(np.full(len(points), np.nan))
    assert unknown.scores[0] >= CONFIDENT_SCORE
    # a line whose ends meet the view (furniture just behind its middle) keeps the place
    # while at most HELD_ON_VIEW of its points lie on it
    ends = np.abs(points[:, 1]) > 0.5
    assert HELD_ON_VIEW > np.mean(ends)
    assert score(np.where(ends, ranges, ranges + 0.3)).scores[0] >= CONFIDENT_SCORE


def test_an_imu_tilted_barely_beyond_its_band_lends_no_line_its_support():
    # at 4 deg +- 3 deg the floor may lie anywhere from 2 m to 14 m ahead: a wall 3.6 m
    # ahead (the floor's place at 4 deg) that the level view knows gets no support; with
    # a band of 1.5 deg the IMU puts the floor within a factor of three, and supports it
    tilt = math.radians(4.0)
    distance = HEIGHT_M / math.sin(tilt)
    wall = line(distance, -1.5, distance, 1.5, 60)
    none_new = np.zeros(60, bool)
    vague = Attitude(tilt, 0.0, math.radians(3.0))
    assert vague.tilted
    _, unsupported = scored(wall, new=none_new, attitude=vague, static=Told(False))
    assert unsupported.scores[0] == 0.0
    sure = Attitude(tilt, 0.0, math.radians(1.5))
    _, supported = scored(wall, new=none_new, attitude=sure, static=Told(False))
    assert supported.scores[0] == pytest.approx(IMU_SUPPORT)


def test_a_face_with_returns_beyond_it_has_no_say_in_where_the_floor_is():
    # nose up among tables: the plane meets a table's side 0.9 m ahead (new, 1 m wide, the
    # room's far wall seen beside it) and the floor 1.4 m behind, most of whose line the
    # chairs hide. The face holds more new points, but returns beyond it prove it is not
    # where the plane meets the floor: the floor is behind, and its line is removed
    pose = (-2.3, 0.0, 0.0)  # the wall behind 1.7 m off, the wall ahead 6.3 m
    table = np.array([[[-1.4, -0.5], [-1.4, 0.5]]])  # world, m: 0.9 m ahead of the sensor
    pvf = ImprovedPitchVariationFilter(ImprovedParams(lidar_height_m=HEIGHT_M))
    for k in range(10):
        pvf.process(tilted_scan(pose, 0.0, stamp=0.1 * k)[0])
    walls = np.concatenate((ROOM, table))
    scan, hit = tilted_scan(pose, math.radians(-10.0), walls=walls, stamp=1.0)
    angles = scan.angles()
    chairs = (np.abs(angles) > math.radians(90.0)) & (np.abs(angles) < math.radians(160.0))
    scan = scan.with_ranges(np.where(chairs, np.nan, scan.ranges))  # the floor line hidden
    floor = (hit == 2) & ~chairs
    face = (hit == 1) & (np.abs(angles) < math.radians(30.0))
    assert face.sum() > floor.sum() > 20
    result = pvf.process(scan)
    assert result.lines.segment_scores.down_side == -1
    assert result.removed[floor].mean() > 0.9
    assert not result.removed[face].any()


def _table_face_nose_up(floor_behind: bool):
    """Nose up 10 deg, as the IMU says: a table's face 0.9 m ahead with the room's far
    wall seen beside it, and (or not) the floor line behind, cut by the seam."""
    behind = HEIGHT_M / math.sin(math.radians(10.0))
    floor_halves = (
        line(-behind, 0.0, -behind, -0.6, 25)[1:],
        line(-behind, 0.6, -behind, 0.0, 25),
    )
    room = (
        line(6.0, -5.0, 6.0, -3.4, 20),
        line(0.9, -0.5, 0.9, 0.5, 60),
        line(6.0, 3.4, 6.0, 5.0, 20),
    )
    parts = (floor_halves[0], *room, floor_halves[1]) if floor_behind else room
    new = np.concatenate([np.full(len(part), len(part) != 20) for part in parts])
    imu = Attitude(math.radians(-10.0), 0.0, math.radians(1.0))
    segments, result = scored(*parts, new=new, attitude=imu)
    face = at(segments, (24 if floor_behind else 0) + 20 + 30)
    assert result.new_counts[face] == max(result.new_counts)
    assert result.down_side == imu.down_side == -1
    return result, face


def test_a_face_with_returns_beyond_it_does_not_contradict_a_correct_imu():
    # every gated line votes in the IMU's sign check, and the face holds the most new
    # points; too near to be a ceiling, it "can only be the floor". But it has returns
    # beyond it, and without it the floor line behind agrees with the IMU: the scan
    # abstains (six such scans disowned a correct IMU among tables)
    result, face = _table_face_nose_up(floor_behind=True)
    assert result.scan_down_side == 0
    assert not result.voters[face]


def test_a_face_with_returns_beyond_it_still_contradicts_where_no_other_line_agrees():
    # no other line shows a side: the face's vote counts (abstaining there kept an IMU
    # of the wrong sign in use longer)
    result, _ = _table_face_nose_up(floor_behind=False)
    assert result.scan_down_side == 1
