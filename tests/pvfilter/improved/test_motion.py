"""Ego-motion from two scans: the turn to the nearest beam, then a point-to-line fit."""

import math

import numpy as np
import pytest

from pvfilter.improved import BeamLayout, ImprovedParams, Motion, estimate_motion, segment_scan
from pvfilter.improved.motion import coarse_turn

from .conftest import room_scan

CLUTTER = np.array(  # furniture in the room, world frame, m
    [[[1.5, 1.0], [2.0, 1.2]], [[-2.0, -1.0], [-1.2, -1.6]], [[0.5, -2.0], [1.5, -1.4]]]
)


def inputs(scan):
    layout = BeamLayout.of(scan)
    valid = scan.valid_mask()
    points = layout.points(np.where(valid, scan.ranges, np.nan))
    beams = np.flatnonzero(valid)
    directions = np.full(len(scan), np.nan)
    directions[beams] = segment_scan(points[beams], beams, ImprovedParams()).directions
    return layout, points, directions


@pytest.mark.parametrize(
    "pose",
    [(0.0, 0.0, 0.0), (0.08, 0.0, 0.0), (0.05, 0.02, 0.04), (-0.06, 0.01, -0.07)],
    ids=["still", "forward", "forward-left-turning", "backward-turning-right"],
)
def test_estimate_recovers_the_sensor_motion(pose):
    before, _ = room_scan((0.0, 0.0, 0.0), extra=CLUTTER, seed=1)
    after, _ = room_scan(pose, extra=CLUTTER, seed=2)
    layout, previous, _ = inputs(before)
    _, points, directions = inputs(after)
    motion = estimate_motion(points, directions, previous, layout, 20, 0.3)
    # a static point q of the first frame is at R(theta) q + t in the second
    x, y, yaw = pose
    c, s = math.cos(-yaw), math.sin(-yaw)
    expected_t = (-(c * x - s * y), -(s * x + c * y))
    assert motion.theta_rad == pytest.approx(-yaw, abs=math.radians(0.3))
    assert (motion.tx_m, motion.ty_m) == pytest.approx(expected_t, abs=0.015)
    assert motion.pairs > 100


def test_coarse_turn_finds_the_shift_of_a_turned_scan():
    before, _ = room_scan((0.0, 0.0, 0.0), extra=CLUTTER, noise_m=0.0)
    after, _ = room_scan((0.0, 0.0, math.radians(-5.0)), extra=CLUTTER, noise_m=0.0)
    layout = BeamLayout.of(before)
    shift = coarse_turn(after.ranges, before.ranges, 20, layout, expected=0)
    assert shift == 10  # 5 deg at 2 beams per degree: the world turns the other way


def test_motion_moves_points_between_frames():
    motion = Motion(theta_rad=math.pi / 2, tx_m=1.0, ty_m=0.0)
    np.testing.assert_allclose(motion.apply(np.array([[1.0, 0.0]])), [[1.0, 1.0]], atol=1e-12)


def test_too_few_pairs_keep_the_coarse_turn_only():
    before, _ = room_scan()
    layout, previous, _ = inputs(before)
    nothing = np.full_like(previous, np.nan)
    motion = estimate_motion(previous, np.full(len(before), np.nan), nothing, layout, 5, 0.3)
    assert motion.pairs == 0 and (motion.tx_m, motion.ty_m) == (0.0, 0.0)
