"""BodyBeams: the silent beams that returned the robot's own body lately."""

import numpy as np

from pvfilter.improved.body import BodyBeams

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


def test_a_near_return_that_keeps_its_range_while_the_sensor_travels_is_the_body():
    beams = BodyBeams()
    # 4 cm a scan, counted from the first scan that showed the returns: not yet after 8 cm,
    # the body from 12 cm on
    for _ in range(3):
        assert beams.returning_body(NEAR_M, 0.04, 0.1, 1.5) is None
    body = beams.returning_body(NEAR_M, 0.04, 0.1, 1.5)
    assert body is not None and body.tolist() == [True, True, False, True]


def test_a_near_surface_the_sensor_passes_changes_its_range_and_is_not_the_body():
    beams = BodyBeams()
    for k in range(10):  # the sensor drives 5 cm a scan at a wall ahead 0.5 m off
        ahead = np.array([0.5 - 0.05 * k * 0.5, np.nan, np.nan, np.nan])
        assert beams.returning_body(ahead, 0.05, 0.1, 1.5) is None


def test_standing_still_shows_no_body_however_long():
    beams = BodyBeams()
    for _ in range(30):
        assert beams.returning_body(NEAR_M, 0.0, 0.1, 1.5) is None


def test_the_body_keeps_its_range_within_a_scanners_noise_near_it():
    # 1 cm of noise near the sensor: a range 2.5 cm off (2.5 sigma) is kept, 4 cm is not
    for off_m, body_seen in ((0.025, True), (0.04, False)):
        beams = BodyBeams()
        for k in range(4):
            body = beams.returning_body(NEAR_M + off_m * (k % 2), 0.05, 0.1, 1.5)
        assert (body is not None) == body_seen


def test_a_beam_that_showed_the_body_is_taken_so_for_a_while_after_a_dropout():
    beams = BodyBeams()
    for _ in range(4):
        beams.returning_body(NEAR_M, 0.05, 0.1, 1.5)
    # one scan without the returns, then the robot stands: a near return on those beams
    # is still the body for memory_s (1.5 s) since it was shown, then no longer
    assert beams.returning_body(np.full(4, np.nan), 0.0, 0.1, 1.5) is None
    for _ in range(13):
        assert beams.returning_body(NEAR_M, 0.0, 0.1, 1.5) is not None
    beams.returning_body(NEAR_M, 0.0, 0.1, 1.5)  # (1.5 s: either)
    assert beams.returning_body(NEAR_M, 0.0, 0.1, 1.5) is None


def test_a_new_sequence_forgets_the_near_returns():
    beams = BodyBeams()
    for _ in range(4):
        beams.returning_body(NEAR_M, 0.05, 0.1, 1.5)
    assert beams.tracking
    beams.reset()
    assert not beams.tracking
    assert beams.returning_body(NEAR_M, 0.05, 0.1, 1.5) is None
