"""The IMU input: its error band widens with the pitch rate and where the scans show it off;
which side is down."""

import math

import numpy as np
import pytest

from pvfilter.improved import ImprovedParams
from pvfilter.improved.imu import (
    IMU_CHECK_FACTOR,
    IMU_CHECK_LINES,
    IMU_CHECK_MAX_BAND_DEG,
    IMU_CHECK_MIN_LINES,
    IMU_SIGN_MIN_VOTES,
    IMU_TIMING_S,
    Attitude,
    AttitudeTrack,
    ImuSignWarning,
)
from pvfilter.improved.scoring import _imu_agreement

PARAMS = ImprovedParams()
BASE = math.radians(PARAMS.imu_angle_error_deg)


def test_a_steady_tilt_keeps_the_band_narrow_and_a_fast_change_widens_it():
    track = AttitudeTrack(PARAMS)
    first = track.update((0.20, 0.0), 0.0)
    assert first.error_rad == pytest.approx(BASE)  # no rate yet
    steady = track.update((0.20, 0.01), 0.1)
    assert steady.error_rad == pytest.approx(BASE) and steady.tilted and steady.down_side == 1
    falling = track.update((-0.10, 0.0), 0.2)  # -3 rad/s
    assert falling.error_rad == pytest.approx(BASE + 3.0 * IMU_TIMING_S)
    assert falling.down_side == -1 and not falling.tilted  # within its own band


def test_no_imu_gives_no_attitude_and_forgets_the_rate():
    track = AttitudeTrack(PARAMS)
    track.update((0.2, 0.0), 0.0)
    assert track.update(None, 0.1) is None and track.current is None
    assert track.update((0.0, 0.0), 0.2).error_rad == pytest.approx(BASE)


def test_a_good_imu_keeps_its_narrow_band_against_floor_lines_that_agree():
    track = AttitudeTrack(PARAMS)
    for k in range(IMU_CHECK_LINES):
        pitch = 0.15 + 0.001 * k  # a slow, steady tilt
        track.update((pitch, 0.0), 0.1 * k)
        track.check(pitch + math.radians(0.5) * (-1) ** k)  # lines within half a degree
    assert track.current.error_rad == pytest.approx(BASE + 0.01 * IMU_TIMING_S)


def test_an_imu_that_is_off_widens_its_band_so_it_cannot_veto_the_lines():
    # an estimator 4 deg short of the floor lines (lag, a mount off by a degree): after
    # IMU_CHECK_MIN_LINES lines its band covers them
    track = AttitudeTrack(PARAMS)
    off = math.radians(4.0)
    for k in range(IMU_CHECK_MIN_LINES):
        track.update((0.10, 0.0), 0.1 * k)
        assert track.current.error_rad == pytest.approx(BASE)
        track.check(0.10 + off)
    attitude = track.update((0.10, 0.0), 1.0)
    assert attitude.error_rad == pytest.approx(IMU_CHECK_FACTOR * off)
    assert attitude.pitch_rad == 0.10  # not corrected: a lag is off either way


def _taught(track: AttitudeTrack, pitch_rad: float, line_rad: float) -> Attitude:
    """``track``'s attitude after IMU_CHECK_LINES confident lines at ``line_rad`` while the
    estimate held ``pitch_rad``."""
    for k in range(IMU_CHECK_LINES):
        track.update((pitch_rad, 0.0), 0.1 * k)
        track.check(line_rad)
    return track.update((pitch_rad, 0.0), 0.1 * IMU_CHECK_LINES)


@pytest.mark.parametrize("off_deg", [15.0, 40.0])
def test_lines_farther_off_than_a_balancing_robots_estimate_teach_at_most_the_widest_band(
    off_deg,
):
    # an attic's low walls, taken for floor lines ahead of a plane 7 deg nose down, need
    # 15 deg or more of tilt beyond the estimate: the band they teach stops at
    # IMU_CHECK_MAX_BAND_DEG, and such a line lies beyond it (the IMU counts against it)
    pitch, off = 0.12, math.radians(off_deg)
    attitude = _taught(AttitudeTrack(PARAMS), pitch, pitch + off)
    assert attitude.error_rad == pytest.approx(math.radians(IMU_CHECK_MAX_BAND_DEG))
    _, beyond, _ = _imu_agreement(
        np.array([2.0]), np.array([1.0]), np.array([pitch + off]), attitude, PARAMS
    )
    assert beyond[0]


def test_a_wider_band_set_by_the_user_stands_above_the_widest_the_lines_teach():
    wide = ImprovedParams(imu_angle_error_deg=15.0)
    attitude = _taught(AttitudeTrack(wide), 0.12, 0.12 + math.radians(30.0))
    assert attitude.error_rad == pytest.approx(math.radians(15.0))


def test_lines_seen_while_the_estimate_changes_fast_or_on_the_up_side_are_not_compared():
    track = AttitudeTrack(PARAMS)
    track.update((0.0, 0.0), 0.0)
    for k in range(1, 2 * IMU_CHECK_MIN_LINES):
        fast = (-1) ** k * 0.1  # +-2 rad/s: the rate's own band covers the lag
        track.update((fast, 0.0), 0.1 * k)
        track.check(fast + 0.2)
    assert not track.differences
    track.update((0.2, 0.0), 2.0)
    track.update((0.2, 0.0), 2.1)  # tilted nose down: the floor ahead
    track.check(-0.1)  # a line behind: the ceiling, perhaps
    assert not track.differences
    track.check(None)  # no confident line
    assert not track.differences


def test_a_veto_waits_a_scan_for_a_lagging_estimate_to_catch_up():
    # the body may have tilted max_pitch_rate * IMU_TIMING_S since the estimate: a line
    # within that is not vetoed, until a scan has shown one beyond the band
    track = AttitudeTrack(PARAMS)
    reach = PARAMS.max_pitch_rate_rad_s * IMU_TIMING_S
    assert track.update((0.0, 0.0), 0.0).reach_rad == pytest.approx(reach)
    track.check(None, contradicted=True)  # a strong line beyond the band
    assert track.update((0.0, 0.0), 0.1).reach_rad == 0.0  # the estimate had time
    track.check(None, contradicted=False)
    assert track.update((0.0, 0.0), 0.2).reach_rad == pytest.approx(reach)
    track.check(None, contradicted=True)
    track.reset()
    assert track.update((0.0, 0.0), 0.3).reach_rad == pytest.approx(reach)


def test_an_imu_of_the_wrong_sign_is_disowned_until_reset():
    # the estimate says nose down (floor ahead) where the scans put the floor behind
    track = AttitudeTrack(PARAMS)
    track.update((0.15, 0.0), 0.0)
    track.check(None, scan_down_side=-1)  # no rate yet: no vote
    with pytest.warns(ImuSignWarning, match="positive nose down"):
        for k in range(1, IMU_SIGN_MIN_VOTES + 1):
            assert track.update((0.15, 0.0), 0.1 * k) is not None
            track.check(None, scan_down_side=-1)
            assert track.disowned == (k == IMU_SIGN_MIN_VOTES)
    assert track.disowned and track.update((0.15, 0.0), 1.0) is None
    track.reset()
    assert track.update((0.15, 0.0), 2.0) is not None


def test_a_good_imu_outvotes_the_scans_that_see_a_ceiling_first():
    track = AttitudeTrack(PARAMS)
    for k in range(4 * IMU_SIGN_MIN_VOTES):
        track.update((0.15, 0.0), 0.1 * k)
        track.check(None, scan_down_side=-1 if k % 3 == 0 else 1)  # a third disagree
    assert not track.disowned and track.current is not None


def test_an_estimate_changing_fast_or_after_a_gap_does_not_vote():
    track = AttitudeTrack(PARAMS)
    for k in range(3 * IMU_SIGN_MIN_VOTES):
        pitch = 0.15 + (0.1 if k % 2 else 0.0)  # 1 rad/s back and forth
        track.update((pitch, 0.0), 0.1 * k)
        track.check(None, scan_down_side=-1)
    for k in range(3 * IMU_SIGN_MIN_VOTES):  # the IMU on every second scan only
        track.update((0.15, 0.0) if k % 2 else None, 10.0 + 0.1 * k)
        track.check(None, scan_down_side=-1)
    assert track.sides_disagree == 0 and not track.disowned
