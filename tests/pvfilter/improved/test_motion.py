"""Motion: the scan match, composing motions, a rotating scan's skew, unstretching."""

import dataclasses
import math

import numpy as np
import pytest

from pvfilter.improved import BeamLayout, ImprovedParams, Motion, estimate_motion, segment_scan
from pvfilter.improved.motion import (
    coarse_turn,
    motion_of,
    nearer_than,
    odometry_motion,
    weak_direction,
)
from pvfilter.improved.sweep import deskew, move_scan, skew

from .conftest import room_scan

CLUTTER = np.array(  # furniture in the room, world frame, m
    [[[1.5, 1.0], [2.0, 1.2]], [[-2.0, -1.0], [-1.2, -1.6]], [[0.5, -2.0], [1.5, -1.4]]]
)
SPREAD = (0.01, 0.03)  # a weak prior: (turn rad, translation m)


def inputs(scan):
    layout = BeamLayout.of(scan)
    valid = scan.valid_mask()
    points = layout.points(np.where(valid, scan.ranges, np.nan))
    beams = np.flatnonzero(valid)
    directions = np.full(len(scan), np.nan)
    segments = segment_scan(points[beams], beams, layout.increment, ImprovedParams())
    directions[beams] = segments.directions
    return layout, points, directions


STILL = Motion()


def segment_scan_of(walls, pose, seed):
    """A noisy scan of ``walls`` (world frame) from ``pose``."""
    from pvfilter.synthetic import segment_scan as cast

    from .conftest import to_sensor

    rng = np.random.default_rng(seed)
    return cast(to_sensor(walls, pose), noise_m=0.005, rng=rng)


def match(before, after, prior=STILL):
    layout, reference, _ = inputs(before)
    _, points, directions = inputs(after)
    ranges, reference_ranges = np.hypot(*points.T), np.hypot(*reference.T)
    shift = coarse_turn(ranges, reference_ranges, 20, layout, expected=0)
    return estimate_motion(points, directions, reference, layout, shift, 0.3, prior, SPREAD)


def expected_motion(pose):
    """A static point q of the first frame is at R(theta) q + t in the second."""
    x, y, yaw = pose
    c, s = math.cos(-yaw), math.sin(-yaw)
    return Motion(-yaw, -(c * x - s * y), -(s * x + c * y))


@pytest.mark.parametrize(
    "pose",
    [(0.0, 0.0, 0.0), (0.08, 0.0, 0.0), (0.05, 0.02, 0.04), (-0.06, 0.01, -0.07)],
    ids=["still", "forward", "forward-left-turning", "backward-turning-right"],
)
def test_estimate_recovers_the_sensor_motion(pose):
    before, _ = room_scan((0.0, 0.0, 0.0), extra=CLUTTER, seed=1)
    after, _ = room_scan(pose, extra=CLUTTER, seed=2)
    motion, expected = match(before, after), expected_motion(pose)
    assert motion.theta_rad == pytest.approx(expected.theta_rad, abs=math.radians(0.3))
    assert (motion.tx_m, motion.ty_m) == pytest.approx((expected.tx_m, expected.ty_m), abs=0.015)
    assert motion.pairs > 100 and motion.residual_m < 0.02


def test_a_fit_on_parallel_walls_is_weak_along_them():
    # side walls only (a corridor, or what a pitched plane still meets): the drive along
    # them rests on no row; a room's four walls constrain both directions
    corridor = np.array([[[-20.0, 1.2], [20.0, 1.2]], [[-20.0, -1.2], [20.0, -1.2]]])
    for walls, weak_below, strong_above in ((corridor, 1.0, None), (None, None, 50.0)):
        if walls is None:
            before, _ = room_scan(seed=1)
            after, _ = room_scan((0.05, 0.0, 0.0), seed=2)
        else:
            before = segment_scan_of(walls, (0.0, 0.0, 0.0), seed=1)
            after = segment_scan_of(walls, (0.05, 0.0, 0.0), seed=2)
        motion = match(before, after)
        assert motion.pairs > 100
        if weak_below is not None:
            assert motion.weak_rows < weak_below
            assert abs(math.sin(motion.weak_axis_rad)) < 0.05  # along x
        else:
            assert motion.weak_rows > strong_above


def test_the_weak_direction_takes_the_turn_out():
    # 100 rows on a wall across x, and 100 on a piece of wall along x, all 3 m ahead: a
    # turn moves that piece along y as a shift does, so y rests on no row once the turn
    # is free (its translation alone would seem measured by 100 rows either way)
    design = np.array([[0.0, 1.0, 0.0]] * 100 + [[3.0, 0.0, 1.0]] * 100)
    rows, axis, strong = weak_direction(design.T.dot(design).tolist())
    assert rows == pytest.approx(0.0, abs=1e-9) and strong == pytest.approx(100.0)
    assert abs(math.cos(axis)) < 1e-9  # along y
    design[100:, 0] = 0.0  # the piece at the sensor's side: the turn does not move it
    rows, _, strong = weak_direction(design.T.dot(design).tolist())
    assert rows == pytest.approx(100.0) and strong == pytest.approx(100.0)


def test_coarse_turn_finds_the_shift_of_a_turned_scan():
    before, _ = room_scan((0.0, 0.0, 0.0), extra=CLUTTER, noise_m=0.0)
    after, _ = room_scan((0.0, 0.0, math.radians(-5.0)), extra=CLUTTER, noise_m=0.0)
    layout = BeamLayout.of(before)
    shift = coarse_turn(after.ranges, before.ranges, 20, layout, expected=0)
    assert shift == 10  # 5 deg at 2 beams per degree: the world turns the other way


def test_motions_compose_and_invert():
    a, b = Motion(0.3, 1.0, -0.5), Motion(-0.1, 0.2, 0.4)
    q = np.array([[1.0, 2.0], [-3.0, 0.5]])
    np.testing.assert_allclose(a.then(b).apply(q), b.apply(a.apply(q)), atol=1e-12)
    np.testing.assert_allclose(a.inverse().apply(a.apply(q)), q, atol=1e-12)
    np.testing.assert_allclose(Motion(math.pi / 2, 1.0, 0.0).apply(np.array([[1.0, 0.0]])),
                               [[1.0, 1.0]], atol=1e-12)  # fmt: skip
    assert a.scaled(0.5).theta_rad == 0.15 and a.translation_m == pytest.approx(math.hypot(1, 0.5))


def test_odometry_poses_give_the_motion_of_static_points():
    # the sensor drives 1 m along its x axis after turning to 90 deg in the odom frame
    before, after = np.array([2.0, 1.0, math.pi / 2]), np.array([2.0, 2.0, math.pi / 2])
    motion = odometry_motion(before, after)
    assert (motion.theta_rad, motion.tx_m, motion.ty_m) == pytest.approx((0.0, -1.0, 0.0))


def test_odometry_yaw_wrapping_through_pi_reads_the_small_turn_it_was():
    # REP-105 odometry reports yaw in (-pi, pi]: turning 0.1 rad left through pi jumps
    # from pi - 0.05 to -pi + 0.05, the same turn as the unwrapped pi + 0.05
    before = np.array([1.0, -2.0, math.pi - 0.05])
    wrapped = before + np.array([0.1, 0.2, 0.1 - math.tau])
    unwrapped = before + np.array([0.1, 0.2, 0.1])
    motion = odometry_motion(before, wrapped)
    expected = odometry_motion(before, unwrapped)
    assert motion.theta_rad == pytest.approx(-0.1)
    assert (motion.tx_m, motion.ty_m) == pytest.approx((expected.tx_m, expected.ty_m))


def test_a_shift_past_every_beam_leaves_none_of_a_partial_scan():
    # a 90-beam, 90 deg scan turned by more than its field of view sees none of its beams
    # again (a ring would wrap instead)
    angles = np.radians(np.arange(90.0))
    layout = BeamLayout(90, 0.0, math.radians(1.0), np.cos(angles), np.sin(angles), False)
    values = np.arange(90.0)
    for shift in (90, 100, 179, -90, -100, -179):
        assert np.isnan(layout.shifted(values, shift)).all(), shift
    assert layout.shifted(values, 89)[89] == 0.0 and np.isnan(layout.shifted(values, 89)[:89]).all()


def test_too_few_pairs_return_the_prior():
    before, _ = room_scan()
    layout, previous, _ = inputs(before)
    nothing = np.full_like(previous, np.nan)
    prior = Motion(0.01, 0.05, 0.0)
    directions = np.full(len(before), np.nan)
    motion = estimate_motion(previous, directions, nothing, layout, 0, 0.3, prior, SPREAD)
    assert motion == prior and motion.pairs == 0


def rotating_layout(beams=720):
    scan, _ = room_scan()
    return BeamLayout.of(scan), 0.1 / beams


def test_deskew_undoes_the_skew_of_a_turning_and_driving_sensor():
    layout, increment = rotating_layout()
    velocity = Motion(-1.2, -0.8, 0.1)  # per second: turning left, driving forward
    mid = layout.points(np.random.default_rng(0).uniform(0.5, 8.0, layout.count))
    seen = skew(mid, layout, increment, velocity)
    # away from the seam behind the sensor (a point there is seen a scan period apart)
    inner = np.abs(np.arange(layout.count) - 359.5) < 300
    assert np.abs(seen - mid).max() > 0.05  # the skew is not small
    back = deskew(seen, layout, increment, velocity)
    np.testing.assert_allclose(back[inner], mid[inner], atol=2e-3)


def test_no_time_increment_or_no_motion_leaves_the_points():
    layout, increment = rotating_layout()
    points = layout.points(np.full(layout.count, 2.0))
    assert deskew(points, layout, 0.0, Motion(-1.0, -1.0, 0.0)) is points
    assert deskew(points, layout, increment, Motion()) is points


def test_move_scan_is_deskew_motion_and_skew_in_one_pass():
    layout, increment = rotating_layout()
    rng = np.random.default_rng(1)
    points = layout.points(rng.uniform(0.5, 8.0, layout.count))
    before, after = (increment, Motion(-1.0, -0.8, 0.05)), (increment, Motion(-1.3, -1.0, 0.0))
    motion = Motion(-0.1, -0.09, 0.01)
    three = skew(motion.apply(deskew(points, layout, *before)), layout, *after)
    one = move_scan(points, np.arange(layout.count), layout, motion, before, after)
    inner = np.abs(np.arange(layout.count) - 359.5) < 300  # not across the seam
    assert np.median(np.abs(three - one)[inner]) < 0.005
    assert np.percentile(np.abs(three - one)[inner], 95) < 0.02
    global_shutter = move_scan(points, np.arange(layout.count), layout, motion, (0.0, Motion()),
                               (0.0, Motion()))  # fmt: skip
    np.testing.assert_allclose(global_shutter, motion.apply(points), atol=1e-12)


@pytest.mark.parametrize("limit", [1e-120, 1e-3, 0.25, 7.0, 1e120])
def test_nearer_than_decides_as_hypot_does_next_to_the_limit(limit):
    rng = np.random.default_rng(11)
    angle = rng.uniform(-np.pi, np.pi, 5000)
    at_limit = limit * (1.0 + rng.integers(-4, 5, 5000) * 1.1e-16)  # within ulps of it
    x = np.concatenate((rng.normal(0.0, limit, 400), at_limit * np.cos(angle), [np.nan, np.inf]))
    y = np.concatenate((rng.normal(0.0, limit, 400), at_limit * np.sin(angle), [1.0, np.nan]))
    expected = np.hypot(x, y) < limit
    np.testing.assert_array_equal(nearer_than(x, y, limit), expected)
    if 1e-100 < limit < 1e100:  # where the squares are exact enough, they are not enough
        assert np.count_nonzero((x * x + y * y < limit * limit) != expected) > 0


def test_motion_of_makes_the_same_frozen_motion():
    made, built = motion_of(0.1, -0.2, 0.3, 7, 0.01), Motion(0.1, -0.2, 0.3, 7, 0.01)
    assert made == built and hash(made) == hash(built) and repr(made) == repr(built)
    assert motion_of(0.1, -0.2, 0.3) == Motion(0.1, -0.2, 0.3)
    with pytest.raises(dataclasses.FrozenInstanceError):
        made.tx_m = 1.0  # type: ignore[misc]
