"""Ego-motion over a sequence: unstretching tilted scans, the odometry prior, trust."""

import math

import numpy as np
import pytest

from pvfilter.improved import ImprovedParams, Motion, egomotion
from pvfilter.improved.egomotion import (
    MAX_NOISE_RESIDUAL_M,
    MAX_RESIDUAL_M,
    EgoMotion,
    fit_trusted,
)
from pvfilter.improved.noise import range_noise_m
from pvfilter.synthetic import room_segments

from .conftest import prepared, room_scan, tilted_scan

PARAMS = ImprovedParams()
DT = 0.1  # s


def matched(
    reference, scan, pose_before=None, pose_after=None, tilt=None, tilted=False, line_tilt=0.0
):
    """EgoMotion given ``reference`` (its floor line's tilt ``line_tilt``, rad: level by
    default), then matching ``scan`` (``tilt``, ``tilted``: the IMU's, if given)."""
    ego = EgoMotion(PARAMS)
    layout, points, _ = prepared(reference)
    ego.commit(points, np.zeros(len(reference), bool), ego.match(layout, points, None, DT,
               ego.prior(DT, None), False, None), line_tilt, DT, pose_before)  # fmt: skip
    layout, points, segments = prepared(scan)
    prior = ego.prior(DT, pose_after)
    odometry = pose_after is not None
    return ego.match(layout, points, segments, DT, prior, odometry, tilt, tilted), prior


def started(room):
    """EgoMotion with one level scan of ``room`` from the origin as its reference."""
    ego = EgoMotion(PARAMS)
    scan, _ = tilted_scan(walls=room)
    layout, points, segments = prepared(scan)
    first = ego.match(layout, points, segments, DT, ego.prior(DT, None), False, None)
    ego.commit(points, np.zeros(len(scan), bool), first, 0.0, DT, None)
    return ego, layout, points, segments


def test_a_tilted_scan_unstretched_by_its_tilt_matches_its_level_view():
    # nose up 15 deg at the same place: the wall ahead looks 1 / cos(15 deg) farther (4.14
    # instead of 4 m), the wall behind is hidden by the floor line
    walls = room_segments(4.0, 3.0, 2.0, 2.0)
    level, _ = tilted_scan(walls=walls)
    tilted, hit = tilted_scan(walls=walls, pitch_rad=math.radians(-15.0))
    assert (hit == 2).sum() > 50
    unstretched, _ = matched(level, tilted, tilt=math.radians(15.0))
    assert unstretched.trusted and unstretched.step.translation_m < 0.01
    as_is, _ = matched(level, tilted, tilt=0.0)
    assert as_is.step.tx_m > 0.05  # a drive backwards that did not happen


def test_the_odometry_prior_keeps_the_motion_where_the_walls_do_not_show_it():
    # a corridor whose ends are out of range: the side walls fix the turn and y, not x
    corridor = room_segments(20.0, 20.0, 1.0, 1.0)
    before, _ = tilted_scan(pose=(0.0, 0.0, 0.0), walls=corridor)
    after, _ = tilted_scan(pose=(0.12, 0.0, 0.0), walls=corridor)
    assert np.isinf(before.ranges[np.abs(before.angles()) < 0.02]).all()
    with_odometry, _ = matched(before, after, np.zeros(3), np.array([0.12, 0.0, 0.0]))
    assert with_odometry.trusted
    assert with_odometry.step.tx_m == pytest.approx(-0.12, abs=0.005)
    scans_only, _ = matched(before, after)
    assert scans_only.step.tx_m == pytest.approx(0.0, abs=0.005)  # constant velocity: 0


def test_slipping_odometry_is_corrected_by_the_walls():
    room = room_segments(3.0, 3.0, 2.0, 2.0)
    before, _ = tilted_scan(walls=room)
    after, _ = tilted_scan(pose=(0.1, 0.0, 0.0), walls=room)
    # the wheels locked on a hard stop: they read 7 cm of the 10 cm
    found, prior = matched(before, after, np.zeros(3), np.array([0.07, 0.0, 0.0]))
    assert found.trusted and found.step.tx_m == pytest.approx(-0.1, abs=0.005)
    assert prior[1][1] > 0.01  # the spread grows with the step (slip)


def test_an_odometry_step_no_robot_can_make_is_slip_and_no_prior():
    # a shove spins one wheel: the odometry reads a turn of a radian in a tenth of a
    # second (10 rad/s; the robot turns at most max_yaw_rate_rad_s), or a 1 m drive
    ego, _, _, _ = started(room_segments(3.0, 3.0, 2.0, 2.0))
    ego.pose = np.zeros(3)
    assert ego.plausible_pose(np.array([0.05, 0.0, 0.1]), DT) is not None  # 1 rad/s
    for slipped in (np.array([0.05, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])):
        assert ego.plausible_pose(slipped, DT) is None
    # why the filter drops such a step: a match made around it (the odometry taken at its
    # word) loses every pair, and a filter would coast on the slip
    room = room_segments(3.0, 3.0, 2.0, 2.0)
    before, _ = tilted_scan(walls=room)
    after, _ = tilted_scan(pose=(0.05, 0.0, 0.0), walls=room)
    found, _ = matched(before, after, np.zeros(3), np.array([0.05, 0.0, 1.0]))
    assert not found.trusted


@pytest.mark.parametrize(
    ("velocity", "scans_turn", "wheels_turn", "slipped"),
    [("fresh", 0.0, 0.22, True), ("fresh", 0.22, 0.22, False), ("fresh", 0.22, 0.0, False),
     ("coasted since", 0.0, 0.22, False), ("not between level scans", 0.0, 0.22, False)],
)  # fmt: skip
def test_wheels_slipped_when_both_other_witnesses_disagree_with_them(
    velocity, scans_turn, wheels_turn, slipped
):
    # driving straight at 0.5 m/s (the velocity measured between two level scans); a
    # match without the wheels and the wheels' step, each turning or not in one step. A
    # velocity carried over a coasted event, or measured on a tilted scan, is no witness
    # (a hard stop or a spin moves the wheels off it rightly)
    ego = EgoMotion(PARAMS)
    ego.velocity, ego.steady = Motion(0.0, -0.5, 0.0), velocity != "not between level scans"
    ego.coasted_s = 0.3 if velocity == "coasted since" else 0.0
    ego.pose = np.zeros(3)
    wheels, spread = ego.prior(DT, np.array([0.05, 0.0, wheels_turn]))
    alone = egomotion.Match(Motion(scans_turn, -0.05, 0.0), True)
    assert ego.wheels_slipped(wheels, spread, DT, alone) is slipped
    assert not ego.wheels_slipped(wheels, spread, DT, egomotion.Match(alone.step, False))


def test_the_step_after_a_slip_is_no_prior_and_starts_from_the_slipped_pose():
    # a wheel spun in the step to the pose kept (1 rad in 0.1 s): the next step, from that
    # pose, is one a robot can make (0.2 rad), but the wheel may still be spinning: no
    # prior. A slip no robot makes is judged from the slipped pose too; the step after a
    # plausible one is the wheels' word again
    ego, _, _, _ = started(room_segments(3.0, 3.0, 2.0, 2.0))
    ego.coast(egomotion.Match(Motion(), False), 0.0, DT, np.array([0.05, 0.0, 1.0]), True)
    assert ego.plausible_step(np.array([0.10, 0.0, 1.2]), DT)
    assert ego.plausible_pose(np.array([0.10, 0.0, 1.2]), DT) is None
    assert not ego.plausible_step(np.array([0.10, 0.0, 2.0]), DT)
    ego.coast(egomotion.Match(Motion(), False), 0.0, DT, np.array([0.10, 0.0, 1.2]), False)
    assert ego.plausible_pose(np.array([0.15, 0.0, 1.2]), DT) is not None


def test_a_match_far_from_the_odometry_or_without_pairs_is_not_trusted():
    room = room_segments(3.0, 3.0, 2.0, 2.0)
    before, _ = tilted_scan(walls=room)
    after, _ = tilted_scan(pose=(0.1, 0.0, 0.0), walls=room)
    far, prior = matched(before, after, np.zeros(3), np.array([0.6, 0.0, 0.0]))
    assert not far.trusted and far.step == prior[0]  # the prior, to coast on
    empty = after.with_ranges(np.full(len(after), np.nan))
    assert not matched(before, empty)[0].trusted


def test_coasting_keeps_the_reference_and_carries_the_prior():
    room = room_segments(3.0, 3.0, 2.0, 2.0)
    ego, layout, points, segments = started(room)
    reference = ego.reference
    failed = ego.match(layout, np.full_like(points, np.nan), segments, DT,
                       (Motion(0.0, -0.05, 0.0), (0.01, 0.03)), False, None)  # fmt: skip
    coasted = ego.coast(failed, 0.0, 0.1, None)
    assert coasted.trusted and coasted.step == Motion(0.0, -0.05, 0.0)
    assert ego.reference is reference and ego.since_reference.tx_m == -0.05
    # the next scan, 5 cm on again, is matched against the old reference: 10 cm
    after, _ = tilted_scan(pose=(0.1, 0.0, 0.0), walls=room)
    layout, points, segments = prepared(after)
    found = ego.match(layout, points, segments, DT, (Motion(0.0, -0.05, 0.0), (0.01, 0.03)),
                      False, None)  # fmt: skip
    assert found.trusted and found.step.tx_m == pytest.approx(-0.05, abs=0.005)


def test_coasting_on_the_odometry_takes_each_step_once():
    # the odometry prior is the step from the pose at the previous scan: coasting on it
    # moves that pose on, or the next prior would hold the coasted steps a second time
    room = room_segments(3.0, 3.0, 2.0, 2.0)
    ego, layout, points, segments = started(room)
    ego.pose = np.zeros(3)
    turning = [np.array([0.0, 0.0, math.radians(6.0) * k]) for k in range(1, 4)]
    for pose in turning[:2]:
        prior = ego.prior(DT, pose)
        assert math.degrees(prior[0].theta_rad) == pytest.approx(-6.0)
        failed = ego.match(layout, np.full_like(points, np.nan), segments, DT, prior, True, None)
        ego.coast(failed, 0.0, DT, pose)
    assert math.degrees(ego.since_reference.theta_rad) == pytest.approx(-12.0)
    assert math.degrees(ego.prior(DT, turning[2])[0].theta_rad) == pytest.approx(-6.0)


def test_a_turn_that_carried_on_while_coasting_is_found_against_the_old_reference():
    # 0.3 s of coasting through a 1.9 rad/s turn: 33 deg since the reference, beyond what
    # one scan time allows (23 deg at max_yaw_rate_rad_s); the prior missed the turn
    room = room_segments(3.0, 2.5, 2.0, 1.5)
    ego, layout, points, segments = started(room)
    for _ in range(2):
        failed = ego.match(layout, np.full_like(points, np.nan), segments, DT,
                           (Motion(), (0.01, 0.03)), False, None)  # fmt: skip
        ego.coast(failed, 0.0, DT, None)
    turned, _ = tilted_scan(pose=(0.0, 0.0, math.radians(33.0)), walls=room)
    layout, points, segments = prepared(turned)
    found = ego.match(layout, points, segments, DT, (Motion(), (0.01, 0.03)), False, None)
    assert math.degrees(found.step.theta_rad) == pytest.approx(-33.0, abs=0.5)


def test_a_robot_that_stopped_is_found_where_a_wrong_velocity_finds_no_pairs():
    # a bad match in a pitch event left a velocity of 4 m/s: the constant-velocity prior
    # puts every reference point 0.4 m off, farther than association_m, so no pair forms;
    # the robot in fact stood still, and the walls show it
    room = room_segments(3.0, 3.0, 2.0, 2.0)
    ego, layout, points, segments = started(room)
    wrong = (Motion(0.0, -0.4, 0.0), (0.01, 0.03))
    assert 0.4 > PARAMS.association_m
    found = ego.match(layout, points, segments, DT, wrong, False, None)
    assert found.trusted and found.step.translation_m < 0.005
    # with odometry the prior is a measurement: a match far from it stays untrusted
    assert not ego.match(layout, points, segments, DT, wrong, True, None).trusted


@pytest.mark.parametrize(("dt", "held"), [(0.025, True), (0.1, False)])
def test_a_line_that_moves_with_the_pitch_cannot_pull_the_drive_faster_than_physics(dt, held):
    # a corridor whose ends are out of range: only a line across it ahead fixes x. Three
    # level scans measure a drive of 0.4 m/s towards the line (a wall); in the fourth the
    # line is 10 cm nearer than the drive puts it (a floor line as the pitch grows). At
    # 40 Hz no balancing robot's sensor moves 10 cm off its measured velocity in one scan
    # time: the drive stays within the steady doubt; at 10 Hz the body's swing about the
    # axle can move it that far, and the match is taken as found
    corridor = room_segments(20.0, 20.0, 1.0, 1.0)
    step_m = 0.4 * dt

    def matched_at(ego, k, line_x_m):
        line = np.array([[[line_x_m, -1.0], [line_x_m, 1.0]]])
        scan, _ = tilted_scan(pose=(k * step_m, 0.0, 0.0), walls=np.concatenate((corridor, line)))
        layout, points, segments = prepared(scan)
        found = ego.match(layout, points, segments, dt, ego.prior(dt, None), False, None)
        ego.commit(points, np.zeros(len(points), bool), found, 0.0, dt, None)
        return found

    ego = EgoMotion(PARAMS)
    for k in range(3):
        measured = matched_at(ego, k, 2.0)
    assert measured.step.tx_m == pytest.approx(-step_m, abs=0.002) and ego.steady
    pulled = matched_at(ego, 3, 1.9)
    bound = ego.steady_doubt_m(dt) + egomotion.STEP_NOISE_M  # (a fit without noise)
    assert pulled.trusted and pulled.step.tx_m < 0.0
    if held:
        assert bound < 0.05
        assert -pulled.step.tx_m - step_m == pytest.approx(bound, abs=0.002)
        assert pulled.weak[0] == 0.0  # the drive along the pull is left to the view's doubt
    else:
        assert bound > 0.1
        assert pulled.step.tx_m == pytest.approx(-step_m - 0.1, abs=0.005)


def test_the_steady_doubt_holds_only_a_measured_velocity():
    # after a start afresh the velocity is 0 by default, not measured: a robot already
    # driving is found as it drives (no doubt drawn around a standing prior)
    room = room_segments(3.0, 3.0, 2.0, 2.0)
    ego = EgoMotion(PARAMS)
    for x_m in (0.0, 0.075):
        scan, _ = tilted_scan(pose=(x_m, 0.0, 0.0), walls=room)
        layout, points, segments = prepared(scan)
        found = ego.match(layout, points, segments, 0.025, ego.prior(0.025, None), False, None)
        ego.commit(points, np.zeros(len(points), bool), found, 0.0, 0.025, None)
    assert found.step.tx_m == pytest.approx(-0.075, abs=0.003)
    assert ego.steady_doubt_m(-1.0) == 0.0  # (no negative doubt)


@pytest.mark.parametrize(("turn_noise_deg", "proven"), [(0.0, True), (1.5, False)])
def test_odometry_proves_itself_by_turning_as_the_scans_do(turn_noise_deg, proven):
    # a two-wheeled robot's odometry turns as the scans do; a skid-steer rover's slides
    # by degrees in every step: only the first may carry a level scan whose match failed
    room = room_segments(3.0, 3.0, 2.0, 2.0)
    ego = EgoMotion(PARAMS)
    assert not ego.odometry_proven  # unproven until matches have agreed with it
    rng = np.random.default_rng(1)
    for k in range(30):
        yaw = math.radians(2.0) * k
        scan, _ = tilted_scan((0.03 * k, 0.0, yaw), walls=room, stamp=DT * k)
        layout, points, segments = prepared(scan)
        pose = np.array([0.03 * k, 0.0, yaw + math.radians(turn_noise_deg) * rng.standard_normal()])
        match = ego.match(layout, points, segments, DT, ego.prior(DT, pose), True, None)
        ego.commit(points, np.zeros(len(scan), bool), match, 0.0, DT, pose)
    assert ego.odometry_proven is proven


def test_a_scan_with_nothing_left_to_match_does_not_replace_the_reference():
    # in a hall beyond the scanner's range a pitched scan can be all floor and ceiling:
    # with its new returns and candidate lines left out nothing is left to match later
    # scans against, so the previous reference stays and the measured step is carried
    room = room_segments(3.0, 3.0, 2.0, 2.0)
    ego, layout, points, segments = started(room)
    reference = ego.reference
    moved, _ = tilted_scan(pose=(0.05, 0.0, 0.0), walls=room)
    layout, points, segments = prepared(moved)
    prior = (Motion(0.0, -0.05, 0.0), (0.01, 0.03))
    match = ego.match(layout, points, segments, DT, prior, False, None)
    assert match.trusted
    ego.commit(points, np.ones(len(moved), bool), match, 0.0, DT, None)  # every beam moving
    assert ego.reference is reference
    assert ego.since_reference.tx_m == pytest.approx(-0.05, abs=0.005)
    # the next scan, 5 cm on again, is matched against the old reference
    after, _ = tilted_scan(pose=(0.1, 0.0, 0.0), walls=room)
    layout, points, segments = prepared(after)
    found = ego.match(layout, points, segments, DT, prior, False, None)
    assert found.trusted and found.step.tx_m == pytest.approx(-0.05, abs=0.005)
    # a scan with enough left replaces it as before
    ego.commit(points, np.zeros(len(after), bool), found, 0.0, DT, None)
    assert ego.reference is not reference and ego.since_reference == Motion()


def test_a_noisy_scanners_right_match_is_trusted(monkeypatch):
    # 8 cm of range noise: a right match leaves a median residual (5.4 cm) over
    # MAX_RESIDUAL_M, well within what the scan's own noise explains
    before, _ = room_scan(noise_m=0.08, seed=1)
    after, _ = room_scan(pose=(0.1, 0.0, 0.0), noise_m=0.08, seed=2)
    match, _ = matched(before, after)
    assert match.trusted
    assert match.step.tx_m == pytest.approx(-0.1, abs=0.03)
    # a balancing robot's IMU never reads exactly 0: within its band the scan is level
    assert matched(before, after, tilt=math.radians(0.3))[0].trusted
    monkeypatch.setattr(egomotion, "NOISE_RESIDUAL_FACTOR", 0.0)  # the fixed bound alone
    assert not matched(before, after)[0].trusted


def test_a_noisy_scanners_tilted_match_keeps_the_fixed_bound():
    # the same right match, but the plane was tilted: by the IMU, or by the last scan's
    # floor line; a tilted scan's fit carries more than the noise, and refused it coasts
    before, _ = room_scan(noise_m=0.08, seed=1)
    after, _ = room_scan(pose=(0.1, 0.0, 0.0), noise_m=0.08, seed=2)
    assert not matched(before, after, tilt=math.radians(5.0), tilted=True)[0].trusted
    assert not matched(before, after, line_tilt=math.radians(1.0))[0].trusted


def test_a_level_scans_fit_is_trusted_within_the_bound_or_the_scans_own_noise():
    quiet, _ = room_scan(noise_m=0.01)
    noisy, _ = room_scan(noise_m=0.05)
    quiet_ranges = np.where(quiet.valid_mask(), quiet.ranges, np.nan)
    noisy_ranges = np.where(noisy.valid_mask(), noisy.ranges, np.nan)
    assert fit_trusted(MAX_RESIDUAL_M, quiet_ranges, True)
    assert fit_trusted(MAX_RESIDUAL_M, noisy_ranges, False)
    assert not fit_trusted(math.nan, noisy_ranges, True)  # no fit
    assert not fit_trusted(0.08, quiet_ranges, True)  # far more than 1 cm of noise leaves
    assert fit_trusted(0.08, noisy_ranges, True)
    assert not fit_trusted(0.11, noisy_ranges, True)  # over twice the noise
    # a tilted scan's fit carries more than the noise: the bound stays
    assert not fit_trusted(0.08, noisy_ranges, False)


def test_a_scans_clutter_cannot_vouch_for_a_poor_fit():
    # range jumps on most triples of beams: the median second difference is the scene's
    # (about a metre here), not the scanner's; no fit over MAX_NOISE_RESIDUAL_M is trusted
    garbled = np.where(np.arange(720) % 2 == 0, 1.0, 3.0)
    assert range_noise_m(garbled) > 0.5
    assert not fit_trusted(MAX_NOISE_RESIDUAL_M + 0.01, garbled, True)
    assert fit_trusted(MAX_NOISE_RESIDUAL_M, garbled, True)
