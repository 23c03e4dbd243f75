"""Following a floor line into the scans after a strong one (pvfilter.improved.follow)."""

from __future__ import annotations

import dataclasses
import math
import types

import numpy as np
import pytest

from pvfilter.improved import BeamLayout, ImprovedParams, ImprovedPitchVariationFilter
from pvfilter.improved.evidence import STATIC_TOLERANCE_M, WorldStatic
from pvfilter.improved.follow import (
    FOLLOW_S,
    TURN_TOLERANCE,
    FloorFollower,
    LinePlace,
    StrongLine,
    travelling_line,
)
from pvfilter.improved.geometry import line_lean
from pvfilter.improved.motion import Motion
from pvfilter.improved.scoring import HeldLine, strongest_confident

from .conftest import HEIGHT_M, line, room_scan, scored, tilted_scan

POSE = (-2.3, 0.0, 0.0)  # m, rad: the wall behind 1.7 m off, the wall ahead 6.3 m
PARAMS = ImprovedParams(lidar_height_m=HEIGHT_M, axle_height_m=HEIGHT_M)


def _nose_up_event(params: ImprovedParams, faint_second_scan: bool):
    """Level scans, a scan pitched 12 deg nose up (its floor line 1.2 m behind: strong),
    then one pitched 9.6 deg (the line 1.5 m behind, 0.2 m in front of the wall); with
    ``faint_second_scan`` that scan returns only 16 beams of its floor line (behind, to
    the left), too few for a strong line. Returns the filter, its last result, the last
    scan, what its beams hit, and the faint scan's floor beams."""
    pvf = ImprovedPitchVariationFilter(params)
    kept = np.zeros(0, dtype=int)
    for k, pitch_deg in enumerate([0.0] * 10 + [-12.0, -9.6]):
        scan, hit = tilted_scan(POSE, math.radians(pitch_deg), stamp=0.1 * k)
        if k == 11 and faint_second_scan:
            angles = scan.angles()
            behind = (angles > math.radians(160.0)) & (angles < math.radians(168.0))
            kept = np.flatnonzero((hit == 2) & behind)
            faint = (hit == 2) & ~behind
            scan = dataclasses.replace(scan, ranges=np.where(faint, np.nan, scan.ranges))
        result = pvf.process(scan)
    return pvf, result, scan, hit, kept


def _follower_with(*lines: StrongLine) -> FloorFollower:
    follower = FloorFollower(PARAMS)
    follower.lines = list(lines)
    return follower


def test_a_floor_line_is_followed_on_its_side_within_the_pitch_rate_s_reach_if_it_moved():
    _, result, scan, hit, _ = _nose_up_event(PARAMS, faint_second_scan=False)
    detection = result.lines
    on_floor = hit == 2
    before, still = scan.stamp - 0.1, Motion()
    line = StrongLine(-1, math.radians(12.0), 1.2, 0.0, before, still)  # 0.3 m nearer
    followed = _follower_with(line).followed(detection, still)
    assert followed is not None and followed[on_floor].mean() > 0.9
    assert not followed[~on_floor].any()
    # the other side, a tilt beyond the reach, a line seen too long ago: not followed
    other_side = StrongLine(1, math.radians(12.0), 1.2, 0.0, before, still)
    far_tilt = StrongLine(-1, math.radians(40.0), 1.2, 0.0, before, still)
    old = StrongLine(-1, math.radians(12.0), 1.2, 0.0, scan.stamp - 1.5 * FOLLOW_S, still)
    for other in (other_side, far_tilt, old):
        assert _follower_with(other).followed(detection, still) is None
    # a line where the earlier one lies had it stayed put in the world: a wall, not
    # followed (the sensor standing: at its distance; the sensor 0.3 m farther forward
    # since, so 0.3 m farther from a line behind it)
    standing = StrongLine(-1, math.radians(12.0), 1.5, 0.0, before, still)
    drove_on = StrongLine(-1, math.radians(12.0), 1.2, 0.0, before, Motion(0.0, -0.3, 0.0))
    for wall in (standing, drove_on):
        assert _follower_with(wall).followed(detection, still) is None


def test_a_floor_line_held_through_a_turn_in_place_is_followed_and_a_turned_wall_is_not():
    # turning about the sensor leaves a line's distance as it was: only its direction in
    # the sensor frame tells a floor line that keeps its place there from a wall fixed in
    # the world, which turns the other way
    _, result, scan, hit, _ = _nose_up_event(PARAMS, faint_second_scan=False)
    detection, on_floor = result.lines, hit == 2
    before, turned = scan.stamp - 0.1, Motion(math.radians(12.0), 0.0, 0.0)
    held = StrongLine(-1, math.radians(12.0), 1.5, 0.0, before, Motion())
    followed = _follower_with(held).followed(detection, turned)
    assert followed is not None and followed[on_floor].mean() > 0.9
    assert not followed[~on_floor].any()
    # the line seen 12 deg the other way before the turn: a wall the turn brought here
    wall = StrongLine(-1, math.radians(12.0), 1.5, math.radians(12.0), before, Motion())
    assert _follower_with(wall).followed(detection, turned) is None
    # within the tolerance of a line that stayed put, the line is not taken as turned
    slight = Motion(0.5 * TURN_TOLERANCE, 0.0, 0.0)
    assert _follower_with(held).followed(detection, slight) is None


def test_line_directions_fold_a_normal_and_its_opposite_into_one():
    normals = np.array([[1.0, 0.0], [-1.0, 0.0], [-1.0, -1e-9], [0.6, 0.8], [-0.6, -0.8]])
    directions = line_lean(normals[:, 1], normals[:, 0])
    np.testing.assert_allclose(directions, [0.0, 0.0, 1e-9, 0.9273, 0.9273], atol=1e-4)
    assert (directions >= -0.5 * math.pi).all() and (directions < 0.5 * math.pi).all()


def test_the_view_does_not_come_closer_behind_a_faint_continuation_of_a_floor_line():
    # the faint scan shows too little of the line to count as tilted, so it teaches the
    # level view; the line it shows continues the strong one of the scan before, and the
    # view stays on the wall behind it. Without holding, the view comes closer behind
    # it, by line_shrink_mps times the scan time plus the drive the match reads (the
    # standing robot's fit, pulled by the line, held to the steady doubt: 3.5 cm), and
    # onto it where lines may come as fast as the rest
    pvf, result, scan, _, kept = _nose_up_event(PARAMS, faint_second_scan=True)
    assert kept.size >= 10 and not result.lines.tilted
    held = pvf._memory.state.ranges[kept]
    assert (held > scan.ranges[kept] + 0.1).all()
    loose = dataclasses.replace(PARAMS, hold_behind_lines=False)
    pvf, result, scan, _, kept = _nose_up_event(loose, faint_second_scan=True)
    assert (pvf._memory.state.ranges[kept] < held - PARAMS.line_shrink_mps * 0.1 + 0.005).all()
    fast = dataclasses.replace(loose, line_shrink_mps=PARAMS.memory_shrink_mps)
    pvf, result, scan, _, kept = _nose_up_event(fast, faint_second_scan=True)
    np.testing.assert_allclose(pvf._memory.state.ranges[kept], scan.ranges[kept], atol=0.02)


def test_a_held_line_is_the_strong_lines_once_the_sensor_turned_enough_from_the_earliest():
    line = StrongLine(1, math.radians(8.0), 1.8, 0.01, 1.0, Motion())
    follower = _follower_with(line)
    turned = Motion(3.0 * TURN_TOLERANCE, 0.0, 0.0)
    assert follower.held(1.1, turned) == HeldLine(1, math.radians(8.0), pytest.approx(0.01))
    # too little turn to tell the line from a wall fixed in the world; too long ago
    assert follower.held(1.1, Motion(1.5 * TURN_TOLERANCE, 0.0, 0.0)) is None
    assert follower.held(1.0 + 1.5 * FOLLOW_S, turned) is None
    # the turn is counted from the earliest line within FOLLOW_S (each scan turns little)
    later = StrongLine(1, math.radians(8.0), 1.8, 0.02, 1.1, Motion(1.5 * TURN_TOLERANCE, 0.0, 0.0))
    held = _follower_with(line, later).held(1.2, turned)
    assert held is not None and held.tilt_rad == line.tilt_rad


def test_a_held_lines_direction_is_the_median_of_the_strong_lines():
    # one of three strong lines is a floor line run into a wall at a small angle, one
    # segment leaning between them: it does not set the held line's direction
    leans = (math.radians(-2.0), math.radians(1.0), math.radians(-2.2))
    lines = [
        StrongLine(1, math.radians(8.0), 1.8, lean, 1.0 + 0.1 * k, Motion())
        for k, lean in enumerate(leans)
    ]
    held = _follower_with(*lines).held(1.25, Motion(3.0 * TURN_TOLERANCE, 0.0, 0.0))
    assert held is not None
    assert held.lean_rad == pytest.approx(math.radians(-2.0))
    # across the fold at +-90 deg the median is taken of the folded differences
    leans_across = (math.radians(89.0), math.radians(-89.5), math.radians(88.0))
    across = [
        dataclasses.replace(line, lean_rad=lean)
        for line, lean in zip(lines, leans_across, strict=True)
    ]
    held = _follower_with(*across).held(1.25, Motion(3.0 * TURN_TOLERANCE, 0.0, 0.0))
    assert held is not None and held.lean_rad == pytest.approx(math.radians(89.0))


def test_a_scans_strong_line_is_its_longest_of_the_most_new_points():
    # two gated segments on the down side with as many new points: the longer one
    # measures the line's direction better and is the scan's strong line
    _, result, _, _, _ = _nose_up_event(PARAMS, faint_second_scan=False)
    detection = result.lines
    scores, segments = detection.segment_scores, detection.segments
    behind = scores.gates & (segments.centroids[:, 0] < 0.0)
    assert np.count_nonzero(behind) >= 1
    capped = np.where(behind, 1.0, scores.new_counts)  # every one on the side ties
    tied_scores = dataclasses.replace(scores, new_counts=capped)
    tied = dataclasses.replace(detection, segment_scores=tied_scores)
    line = StrongLine.of(tied, Motion())
    longest = int(np.argmax(np.where(behind, segments.sizes, -1)))
    assert line is not None and line.distance_m == float(segments.distances[longest])


def _round_alcove(radius_m: float, open_radius_m: float) -> np.ndarray:
    """Walls on a circle of ``radius_m`` around the origin, but ``open_radius_m`` for the
    80 deg ahead (a robot that stopped at furniture all around, the way ahead open)."""
    angles = np.linspace(-math.pi, math.pi, 145)
    radii = np.where(np.abs(angles) < math.radians(40.0), open_radius_m, radius_m)
    corners = np.column_stack((radii * np.cos(angles), radii * np.sin(angles)))
    return np.stack((corners[:-1], corners[1:]), axis=1)


def test_a_floor_line_held_through_a_turn_in_place_stays_removed():
    # an 8 deg nose-down tilt held while the robot turns in place at 0.7 rad/s: its floor
    # line (1.8 m out) was new ahead, and turns onto furniture 1.88 m away, within the
    # free-space margin; the line keeps its place in the sensor frame while the structure
    # turns past (the wheels measure the turn: a round alcove hides it from the scans)
    walls = _round_alcove(1.88, 2.4)
    pvf = ImprovedPitchVariationFilter(PARAMS)
    removed_share, wall_removed, yaw = [], [], 0.0
    for k, pitch_deg in enumerate([0.0] * 10 + [4.0, 8.0, 8.0] + [8.0] * 25):
        yaw += 0.07 if k >= 13 else 0.0
        scan, hit = tilted_scan((0.0, 0.0, yaw), math.radians(pitch_deg), walls=walls,
                                stamp=0.1 * k)  # fmt: skip
        removed = pvf.process(scan, pose_sensor_in_odom=(0.0, 0.0, yaw)).removed
        if k >= 13:
            removed_share.append(removed[hit == 2].mean())
            wall_removed.append(np.count_nonzero(removed[hit == 1]))
    assert np.mean(removed_share) > 0.85
    # the furniture within the line's tolerance where the line meets it goes with it
    assert max(wall_removed) <= 25


def _held_tilt_drive(scans: int):
    """A filter, and per scan (its index, the scan, its floor beams): level for 1 s, then
    8 deg nose down held (``max_event_s`` is 2 s) while the robot drives at 0.4 m/s."""
    pvf = ImprovedPitchVariationFilter(ImprovedParams(lidar_height_m=HEIGHT_M))
    frames = []
    for k in range(scans):
        pitch = math.radians(8.0) if k >= 10 else 0.0
        pose = (-3.0 + 0.04 * k, 0.0, 0.0)  # the wall ahead 5-7 m off
        frames.append((k, *room_scan(pose, pitch, stamp=0.1 * k, seed=k)))
    return pvf, frames


def test_a_tilt_held_while_driving_stays_removed_past_an_events_length():
    # the floor line keeps its distance, 1.8 m ahead, while the robot drives 1.4 m in the
    # 3.5 s of the tilt: no wall does that
    pvf, frames = _held_tilt_drive(45)
    recall = []
    for k, scan, on_floor in frames:
        removed = pvf.process(scan).removed
        if k >= 10:
            recall.append(float(removed[on_floor].mean()))
    assert min(recall) > 0.9, np.round(recall, 2)


def _held_line():
    """The scan 1.5 s into the held tilt of :func:`_held_tilt_drive`, its strong line 1.8
    m ahead: the filter, the scan's line detection, its layout, its ranges (NaN where
    invalid), its floor beams, the strongest confident segment, that segment's normal,
    and per beam the line's direction (rad), for a world-static test to be built on."""
    pvf, frames = _held_tilt_drive(26)
    for _, scan, _ in frames:
        detection = pvf.process(scan).lines
    _, scan, on_floor = frames[-1]
    segments = detection.segments
    strongest = strongest_confident(segments, detection.segment_scores, pvf.params)
    normal_x, normal_y = segments.normals[strongest]
    return types.SimpleNamespace(
        pvf=pvf,
        detection=detection,
        layout=BeamLayout.of(scan),
        ranges=np.where(scan.valid_mask(), scan.ranges, np.nan),
        on_floor=on_floor,
        strongest=strongest,
        normal=(normal_x, normal_y),
        directions=np.full(len(scan), math.atan2(-normal_x, normal_y)),  # along the line
    )


def test_a_line_travels_with_the_sensor_where_its_travel_tells_and_a_wall_does_not():
    # the earlier scan of the world-static test saw the line where it is now (it
    # travelled), or where a wall would have stood (it stayed), or the sensor stood
    # (nothing tells)
    held = _held_line()
    detection, params, ranges = held.detection, held.pvf.params, held.ranges
    drove = Motion(tx_m=-0.12)  # the sensor 0.12 m on since the earlier scan
    moving, place = travelling_line(detection, _world_static(held, ranges, drove), params)
    on_floor = held.on_floor
    assert moving is not None and moving[on_floor].mean() > 0.9 and not moving[~on_floor].any()
    assert place == LinePlace.of(detection.segments, held.strongest)
    # a wall 0.12 m farther off in the earlier scan, as the line's place predicts it
    stayed = _world_static(held, ranges + 0.12 / _facing(held), drove)
    assert travelling_line(detection, stayed, params) == (None, None)
    standing = _world_static(held, ranges, Motion())
    assert travelling_line(detection, standing, params) == (None, None)
    assert travelling_line(detection, None, params) == (None, None)


def _world_static(
    held, earlier_m: np.ndarray, since: Motion, noise_m: float = 0.0, span_s: float = 0.3
):
    """A world-static test of the held line's scan against an earlier scan that saw
    ``earlier_m`` per beam ``span_s`` before, the sensor moved by ``since`` between them;
    with ``noise_m`` of range noise (seeded) on both scans' ranges."""
    rng = np.random.default_rng(0)
    return WorldStatic(
        held.ranges + rng.normal(0.0, noise_m, len(held.ranges)),
        earlier_m + rng.normal(0.0, noise_m, len(held.ranges)),
        held.directions,
        held.layout,
        since,
        STATIC_TOLERANCE_M,
        span_s=span_s,
    )


def _facing(held) -> np.ndarray:
    """Per beam, the cosine between the beam and the held line's normal."""
    normal_x, normal_y = held.normal
    return np.abs(held.layout.cos * normal_x + held.layout.sin * normal_y)


def test_a_noisy_scanner_s_wall_does_not_travel():
    # the strong line taken as a wall 1.8 m ahead that the sensor drove 0.12 m towards;
    # 6 cm of range noise on both scans: more than half of the wall's returns lie beyond
    # the test's tolerance (5 cm at 1.8 m), their median within a centimetre or two
    held = _held_line()
    detection, params = held.detection, held.pvf.params
    earlier = held.ranges + 0.12 / _facing(held)
    noisy = _world_static(held, earlier, Motion(tx_m=-0.12), noise_m=0.06)
    segments = detection.segments
    offsets = noisy.offsets(segments.beams[segments.labels == held.strongest])
    static, telling = offsets.stayed, offsets.telling
    assert 0.5 < 1.0 - static[telling].mean() < 0.7  # counted, the returns would say "moved"
    assert travelling_line(detection, noisy, params) == (None, None)


def test_a_travelling_line_goes_on_travelling_where_nothing_tells_while_it_keeps_its_place():
    # the world-static test tells nothing (the sensor moved too little along the beams
    # since its earlier scan, as a slow drive past a far line leaves it on some scans), or
    # tells that the line stayed put
    held = _held_line()
    detection, params, ranges = held.detection, held.pvf.params, held.ranges
    here = LinePlace.of(detection.segments, held.strongest)
    untold = _world_static(held, ranges, Motion())
    # the test last told it travelled where this line lies: it goes on, and the place it
    # hands on is that one, not this scan's, so that a slow drift adds up
    moving, place = travelling_line(detection, untold, params, here)
    assert moving is not None and moving[held.on_floor].mean() > 0.9 and place == here
    # within twice the test's tolerance of it at its distance (0.096 m at 1.8 m), and no
    # farther
    near = dataclasses.replace(here, distance_m=here.distance_m + 0.09)
    moving_on, place = travelling_line(detection, untold, params, near)
    assert moving_on is not None and place == near
    for elsewhere in (
        dataclasses.replace(here, distance_m=here.distance_m + 0.11),
        dataclasses.replace(here, side=-here.side),
        dataclasses.replace(here, lean_rad=here.lean_rad + 2.0 * TURN_TOLERANCE),
    ):
        assert travelling_line(detection, untold, params, elsewhere) == (None, None)
    # a test that tells the line stayed put ends it, whatever travelled before
    stayed = _world_static(held, ranges + 0.12 / _facing(held), Motion(tx_m=-0.12))
    assert travelling_line(detection, stayed, params, here) == (None, None)
    # returns the earlier scan did not see tell nothing: a travel that "tells" on beams
    # where the earlier scan saw nothing at all, but for three, is no verdict either way
    blind = np.full(len(ranges), np.nan)
    blind[np.flatnonzero(held.on_floor)[:3]] = ranges[held.on_floor][:3]
    unseen = _world_static(held, blind, Motion(tx_m=-0.12))
    assert travelling_line(detection, unseen, params) == (None, None)
    assert travelling_line(detection, unseen, params, here)[1] == here


def test_the_filter_asks_in_time_and_carries_the_verdict_only_from_a_scan_it_asked():
    # the held line's scan, its filter 1.6 s into the tilt; the view's clocks are made up:
    # a beam that passes max_event_s (2 s) with this step would settle
    held = _held_line()
    pvf, ranges = held.pvf, held.ranges
    drove = Motion(tx_m=-0.12)

    def asked(tilted_s: float, clock_s: float, static: WorldStatic, tilted: bool = True):
        pvf._tilted_s = tilted_s
        view = types.SimpleNamespace(ahead_s=np.full(len(ranges), clock_s))
        found = types.SimpleNamespace(detection=held.detection, static=static, view=view)
        return pvf._travelling(found, tilted, 0.1)

    travelled = _world_static(held, ranges, drove)
    untold = _world_static(held, ranges, Motion())
    # no beam settles and the event has not run its length: not asked
    assert asked(1.0, 1.0, travelled) is None and pvf._travelled is None
    # a beam would settle: asked, as past the event's length
    assert asked(1.0, 1.95, travelled)[held.on_floor].mean() > 0.9
    assert asked(2.0, 0.0, travelled) is not None
    # carried while nothing tells, from a scan asked
    assert asked(1.0, 1.95, untold) is not None
    # a scan not asked (level) ends it
    assert asked(1.0, 1.95, travelled, tilted=False) is None and pvf._travelled is None
    assert asked(1.0, 1.95, untold) is None
    # the test's earlier scan before the event (its last level scan, 0.3 s back where the
    # scans have been tilted for 0.2 s): a line not there then left its place as one that
    # travels does; not asked before the event's length
    early = _world_static(held, ranges, drove, span_s=0.3)
    assert asked(0.2, 1.95, early) is None
    assert asked(0.3, 1.95, early) is not None  # (the earlier scan the event's first)
    # a re-baseline forgets it
    pvf._rebaseline()
    pvf._tilted_s = 1.0
    assert asked(1.0, 1.95, untold) is None


def test_a_strong_line_is_the_floor_line_that_chose_the_side_not_a_face_beside_it():
    # nose down 8 deg: a box's face 0.7 m ahead (new, more points than the floor line)
    # and the floor line 1.8 m ahead on both sides of it, beyond the face's ends. The
    # face has returns beyond it and no say in where the floor is; the followed line is
    # the floor line, at its distance
    ahead = HEIGHT_M / math.sin(math.radians(8.0))
    edge = ahead * math.tan(math.atan2(0.2, 0.7))  # where the face's ends hide the floor
    parts = (
        line(ahead, -1.0, ahead, -edge, 26),
        line(0.7, -0.2, 0.7, 0.2, 66),
        line(ahead, edge, ahead, 1.0, 26),
    )
    segments, scores = scored(*parts)
    face = segments.labels[26 + 33]
    assert scores.new_counts[face] == max(scores.new_counts)
    assert scores.down_side == 1 and not scores.voters[face]
    detection = types.SimpleNamespace(
        tilted=True,
        down_side=scores.down_side,
        plane_tilt_rad=scores.down_tilt_rad,
        segment_scores=scores,
        segments=segments,
        scan=types.SimpleNamespace(stamp=1.0),
    )
    strong = StrongLine.of(detection, Motion())
    assert strong.distance_m == pytest.approx(ahead, abs=0.02)
