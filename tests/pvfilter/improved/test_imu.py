"""The IMU input: its error band widens with the pitch rate; which side is down."""

import math

import pytest

from pvfilter.improved import ImprovedParams
from pvfilter.improved.imu import IMU_TIMING_S, AttitudeTrack

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
