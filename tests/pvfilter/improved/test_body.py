"""BodyBeams: the silent beams that returned the robot's own body lately."""

import numpy as np

from pvfilter.improved.body import BODY_HELD_SCANS, BodyBeams
from pvfilter.improved.motion import STILL, Motion

BODY = np.array([True, False, False, False])
NONE = np.zeros(4, bool)
SILENT = np.array([True, True, False, False])


def test_nothing_is_tracked_until_a_body_is_seen():
    beams = BodyBeams()
    assert beams.silent_body(NONE, SILENT, 0.1, 1.5) is None


def test_a_beam_that_returned_the_body_is_the_body_again_while_silent_for_a_while():
    beams = BodyBeams()
    assert beams.silent_body(BODY, NONE, 0.1, 1.5) is None  # a return: nothing silent
    for _ in range(14):  # 1.4 s of silence
        assert beams.silent_body(NONE, SILENT, 0.1, 1.5).tolist() == [True, False, False, False]
    assert beams.silent_body(NONE, SILENT, 0.2, 1.5) is None  # 1.6 s: silence again


def test_a_new_sequence_forgets_the_body():
    beams = BodyBeams()
    beams.silent_body(BODY, NONE, 0.1, 1.5)
    beams.reset()
    assert beams.silent_body(NONE, SILENT, 0.1, 1.5) is None


NEAR_M = np.array([0.2, 0.3, np.nan, 0.4])  # per beam, the near returns (NaN: none)
NOTHING_NEAR = np.full(4, np.nan)
FORWARD = Motion(tx_m=-0.05)  # the sensor drove 5 cm ahead (the world moved back)


def test_a_near_return_that_keeps_its_range_while_the_sensor_drives_is_the_body():
    beams = BodyBeams()
    # 4 cm a scan, counted from the first scan that showed the returns: not yet after 8 cm,
    # the body from 12 cm on
    for _ in range(3):
        assert beams.returning_body(NEAR_M, Motion(tx_m=-0.04), 0.1, 1.5) is None
    body = beams.returning_body(NEAR_M, Motion(tx_m=-0.04), 0.1, 1.5)
    assert body is not None and body.tolist() == [True, True, False, True]


def test_a_near_return_that_keeps_its_range_while_the_sensor_turns_is_the_body():
    # 0.1 rad a scan: a point 0.4 m off moves 4 cm across the beams a scan, one 0.2 m off
    # 2 cm: the body after 0.12 m, on the farther beam first
    beams = BodyBeams()
    seen = [beams.returning_body(NEAR_M, Motion(theta_rad=0.1), 0.1, 1.5) for _ in range(7)]
    assert [None if b is None else b.tolist() for b in seen[:3]] == [None, None, None]
    assert seen[3].tolist() == [False, False, False, True]
    assert seen[6].tolist() == [True, True, False, True]  # (0.2 m x 0.5 rad: 0.1 m, an edge)


def test_a_near_surface_the_sensor_passes_changes_its_range_and_is_not_the_body():
    beams = BodyBeams()
    for k in range(10):  # driving 5 cm a scan past a wall seen 60 deg off its normal
        passing = np.array([0.5 - 0.025 * k, np.nan, np.nan, np.nan])
        assert beams.returning_body(passing, FORWARD, 0.1, 1.5) is None


def test_a_standing_robot_whose_matches_jitter_shows_no_body_however_long():
    # 2 mm of jitter a scan on each axis for 40 s: 1.1 m of steps summed, a few
    # centimetres away from where it started
    rng = np.random.default_rng(0)
    beams = BodyBeams()
    for _ in range(400):
        jitter = Motion(theta_rad=rng.normal(0.0, 1e-3), tx_m=rng.normal(0.0, 0.002),
                        ty_m=rng.normal(0.0, 0.002))  # fmt: skip
        assert beams.returning_body(NEAR_M, jitter, 0.1, 1.5) is None


def test_the_body_keeps_its_range_within_a_scanners_noise_near_it():
    # 1 cm of noise near the sensor: a range 2.5 cm off is kept, 4 cm is not
    for off_m, body_seen in ((0.025, True), (0.04, False)):
        beams = BodyBeams()
        for k in range(4):
            body = beams.returning_body(NEAR_M + off_m * (k % 2), FORWARD, 0.1, 1.5)
        assert (body is not None) == body_seen


def test_a_beam_that_showed_the_body_is_taken_so_for_a_while_after_a_dropout():
    beams = BodyBeams()
    for _ in range(4):
        beams.returning_body(NEAR_M, FORWARD, 0.1, 1.5)
    # one scan without the returns, then the robot stands: a near return on those beams
    # is still the body for memory_s (1.5 s) since it was shown, then no longer
    assert beams.returning_body(NOTHING_NEAR, STILL, 0.1, 1.5) is None
    for _ in range(13):
        assert beams.returning_body(NEAR_M, STILL, 0.1, 1.5) is not None
    beams.returning_body(NEAR_M, STILL, 0.1, 1.5)  # (1.5 s: either)
    assert beams.returning_body(NEAR_M, STILL, 0.1, 1.5) is None


def test_nothing_near_for_a_while_follows_nothing():
    beams = BodyBeams()
    for _ in range(4):
        beams.returning_body(NEAR_M, FORWARD, 0.1, 1.5)
    for _ in range(14):
        beams.returning_body(NOTHING_NEAR, FORWARD, 0.1, 1.5)
    assert beams.tracking  # 1.4 s since the body was shown
    for _ in range(2):  # (1.5 s: either)
        beams.returning_body(NOTHING_NEAR, FORWARD, 0.1, 1.5)
    assert not beams.tracking


def test_a_new_sequence_forgets_the_near_returns():
    beams = BodyBeams()
    for _ in range(4):
        beams.returning_body(NEAR_M, FORWARD, 0.1, 1.5)
    assert beams.tracking
    beams.reset()
    assert not beams.tracking
    assert beams.returning_body(NEAR_M, FORWARD, 0.1, 1.5) is None


def test_only_beams_that_return_the_body_scan_after_scan_are_held():
    # held after BODY_HELD_SCANS scans and hold_s seconds of body, scan after scan
    beams = BodyBeams()
    mast = np.array([True, True, False, False])
    for _ in range(BODY_HELD_SCANS - 1):
        assert beams.held(mast, 1.0, 1.5) is None  # not yet for enough scans
    assert beams.held(mast, 1.0, 1.5).tolist() == [True, True, False, False]
    assert beams.held(np.array([True, False, True, False]), 1.0, 1.5).tolist() == [
        True,
        False,
        False,
        False,
    ]
    assert beams.held(None, 1.0, 1.5) is None  # a scan without the body ends every run
    for _ in range(BODY_HELD_SCANS - 1):
        assert beams.held(mast, 1.0, 1.5) is None
    assert beams.held(mast, 1.0, 1.5) is not None  # (held again)
    beams.reset()  # a new sequence
    assert beams.held(mast, 1.0, 1.5) is None


def test_a_body_is_held_only_after_hold_s_however_many_scans():
    # at 32 Hz, three scans are 0.09 s: a wall the sensor drives along that long is no
    # part of the robot yet
    beams = BodyBeams()
    mast = np.array([True, False])
    held = [beams.held(mast, 0.03125, 1.5) is not None for _ in range(60)]
    assert held.index(True) == 47  # 48 scans: 1.5 s
