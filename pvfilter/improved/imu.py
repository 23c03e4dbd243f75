"""The optional IMU input: the attitude the robot's estimator gives, and how far off it is.

An attitude estimator's pitch is noisy, biased by up to about a degree, and lags the body
by tens of milliseconds; a rotating LiDAR measures a floor line over tens of
milliseconds more. So the pitch of the scan plane is taken to lie within
``imu_angle_error_deg`` plus the pitch rate times ``IMU_TIMING_S`` of the estimate: a
fast pitch change widens the band, a steady tilt keeps it narrow. The rate comes from
consecutive estimates.

A band that supports a line is not enough to veto one. An estimate that lags cannot
have seen a pitch change that began within its lag and the sweep: at the onset of a
shove or a hard stop it still reads level while the scan already shows the floor. So a
line the band cannot explain is vetoed only where it needs more tilt than the body can
reach in ``IMU_TIMING_S`` at ``max_pitch_rate_rad_s`` (``Attitude.reach_rad``), unless
the scan before already showed a strong line beyond the band: the estimate has had a
scan's time to catch up since, and a line it still cannot explain is not the floor.

Estimators and mounts can be worse than that: a complementary filter leans toward the
apparent gravity while the robot accelerates (``atan(a / g)``: 3 deg at 0.5 m/s^2) and
lags a fast pitch by more than its nominal delay, and a LiDAR mounted a degree off
pitches its plane a degree away from the body. So the scans check the IMU: each
confident floor line (:func:`pvfilter.improved.scoring.line_pitch`) puts the plane at a
pitch of its own, and the band is at least ``IMU_CHECK_FACTOR`` times the
``IMU_CHECK_QUANTILE`` quantile of how far the estimate was from the latest
``IMU_CHECK_LINES`` such lines. A good IMU keeps its
narrow band; a poor one widens it until the scans decide, so an IMU that is off never
vetoes a floor line the scans show. The error is not taken as an offset to correct: an
estimator that lags is off one way while the robot pitches nose down and the other way
nose up. Wrong lines among the confident ones (a wall taken for the floor) are mostly a
minority the quantile passes over. Where they are not, the band they teach stops at
``IMU_CHECK_MAX_BAND_DEG`` (the pitch rate's widening comes on top, and a wider
``imu_angle_error_deg`` stands): lines farther from the estimate than a balancing
robot's estimator, a LiDAR mounted a few degrees off and a ramp's slope together put
them are the ones that are wrong. In an attic, low walls 2 m behind a plane pitched 7
degrees would, as floor lines, need 15 to 25 degrees of tilt; learned from them, the
band grew to 26 degrees, and the IMU counted against no line within it.

Nor can the band mend an estimate of the wrong sign (an IMU whose pitch is positive nose
up, say): it puts the floor on the ceiling's side, vetoes the floor lines, and no
confident line is left to check it against (the fourth generator's first set with its
pitch negated: mean AUC 0.617, against 0.852 from the scans alone). So each scan where
the estimate shows a tilt, changing slowly, and the scan alone shows where the floor is
counts whether the two sides agree. A line on the estimate's up side disagrees only where
it lies nearer than a ceiling can at the estimate's tilt: there it can only be the floor.
Once ``IMU_SIGN_MIN_VOTES`` scans disagree, and at least ``IMU_SIGN_RATIO`` times as many
as agree, the IMU is disowned until the filter is reset: it filters from the scans alone,
with a :class:`ImuSignWarning`.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections import deque

import numpy as np

from pvfilter.improved.params import ImprovedParams

IMU_TIMING_S = 0.1  # s: how far a beam's time may be from the estimate's (the estimator's
# lag of tens of ms, and half a scan)
IMU_CHECK_LINES = 24  # the latest confident floor lines the estimate is checked against
IMU_CHECK_MIN_LINES = 4  # before this many lines, the band is the default
IMU_CHECK_MAX_RATE = 0.5  # rad/s: lines seen while the estimate changes faster are not
# compared (the rate's own widening of the band covers the lag then)
IMU_CHECK_QUANTILE = 0.8  # the differences seen are measured by this quantile of their size
IMU_CHECK_FACTOR = 1.5  # the band is this many times that quantile: about 1.9 standard
# deviations of normal differences (a veto must hold for nearly all of them)
IMU_CHECK_MAX_BAND_DEG = 10.0  # deg: the widest band the lines can teach: a balancing
# robot's estimate is off by a few degrees at most (its controller acts on it; the
# simulator's, 2-4 while it accelerates), with a mount up to about 3 deg off and the
# slope of a ramp up to about 6 deg (a wheelchair ramp's 1:12 is 4.8) on top. Capped at
# 6 deg, the independent sequences' 6 deg hospital ramp scored lower
IMU_SIGN_MIN_VOTES = 6  # scans whose floor side contradicts the estimate's before it is
# disowned (with a good IMU 0-5 scans of a fourth-generator sequence do, against 0-69
# that agree)
IMU_SIGN_RATIO = 3.0  # and at least this many times as many as agree with it
MAX_BAND_RAD = math.radians(IMU_CHECK_MAX_BAND_DEG)


class ImuSignWarning(UserWarning):
    """The IMU's pitch put the floor on the other side from the scans' floor lines, scan
    after scan: the filter ignores it until reset (pitch is positive nose down)."""


@dataclasses.dataclass(frozen=True)
class Attitude:
    """The scan plane's attitude as the IMU gives it.

    Attributes:
        pitch_rad: pitch, rad, positive nose down.
        roll_rad: roll, rad, positive left side up.
        error_rad: how far the scan plane's pitch may be from ``pitch_rad``, rad.
        reach_rad: how much farther the body may have tilted since the estimate, rad: a
            line within it is not vetoed (see the module docstring).
    """

    pitch_rad: float
    roll_rad: float
    error_rad: float
    reach_rad: float = 0.0

    @property
    def tilt_rad(self) -> float:
        """The plane's tilt, rad (>= 0)."""
        return abs(self.pitch_rad)

    @property
    def tilted(self) -> bool:
        """The plane is tilted beyond what the error explains."""
        return self.tilt_rad > self.error_rad

    @property
    def down_side(self) -> int:
        """Where the floor is: +1 ahead (nose down), -1 behind."""
        return 1 if self.pitch_rad > 0.0 else -1


class AttitudeTrack:
    """The IMU's estimates scan after scan, for their rate, checked against the scans'
    floor lines (see the module docstring).

    Args:
        params: ``imu_angle_error_deg`` is used.
    """

    def __init__(self, params: ImprovedParams) -> None:
        self.params = params
        self.reset()

    def reset(self) -> None:
        """Forget the previous estimate and what the scans showed of the IMU's error."""
        self.previous: tuple[float, float] | None = None  # (stamp s, pitch rad) as given
        self.current: Attitude | None = None  # the latest scan's
        self.rate_rad_s = 0.0  # the latest estimate's rate of change
        self.rate_known = False  # it came from two consecutive estimates
        self.differences: deque[float] = deque(maxlen=IMU_CHECK_LINES)  # line - estimate, rad
        self.learned_rad = 0.0  # the band the differences call for
        self.contradicted = False  # the latest scan showed a strong line beyond the band
        self.sides_agree = self.sides_disagree = 0  # scans: the IMU's floor side and the scan's
        self.disowned = False  # its sign contradicts the scans: it is ignored until reset

    def update(self, attitude: tuple[float, float] | None, stamp: float) -> Attitude | None:
        """The attitude for the scan at ``stamp`` (None without an IMU, or one disowned)."""
        if attitude is None or self.disowned:
            self.previous = self.current = None
            return None
        pitch, roll = attitude
        rate = self.rate_rad_s = 0.0
        self.rate_known = self.previous is not None and stamp > self.previous[0]
        if self.rate_known:
            rate = self.rate_rad_s = (pitch - self.previous[1]) / (stamp - self.previous[0])
        self.previous = (stamp, pitch)
        default = math.radians(self.params.imu_angle_error_deg)
        band = max(default, self.learned_rad)
        reach = 0.0 if self.contradicted else self.params.max_pitch_rate_rad_s * IMU_TIMING_S
        self.current = Attitude(pitch, roll, band + abs(rate) * IMU_TIMING_S, reach)
        return self.current

    def check(
        self, line_pitch_rad: float | None, contradicted: bool = False, scan_down_side: int = 0
    ) -> None:
        """Compare the latest estimate with the pitch the scan's confident floor line puts
        the plane at (None: the scan has none), and note whether the scan showed a strong
        line beyond the estimate's band (``contradicted``: the next scan's estimate vetoes
        without ``reach_rad``). A line on the up side of a plane the IMU shows tilted may
        be the ceiling, and is passed over. ``scan_down_side``: where the scan alone puts
        the floor (+1 ahead, -1 behind, 0 unknown), for the estimate's sign."""
        self.contradicted = contradicted
        current = self.current
        # (a lagging estimate's sign may be behind the body's while it swings; after a
        # scan without the IMU its rate is not known)
        steady = self.rate_known and abs(self.rate_rad_s) <= IMU_CHECK_MAX_RATE
        if current is not None and current.tilted and scan_down_side != 0 and steady:
            self._vote(scan_down_side == current.down_side)
        if line_pitch_rad is None or current is None or self.previous is None:
            return
        if current.tilted and line_pitch_rad * current.down_side < 0.0:
            return
        if abs(self.rate_rad_s) > IMU_CHECK_MAX_RATE:
            return
        self.differences.append(line_pitch_rad - self.previous[1])
        if len(self.differences) >= IMU_CHECK_MIN_LINES:
            differences = np.abs(np.fromiter(self.differences, float))
            size = float(np.quantile(differences, IMU_CHECK_QUANTILE))
            self.learned_rad = min(IMU_CHECK_FACTOR * size, MAX_BAND_RAD)

    def _vote(self, agree: bool) -> None:
        """Count one scan's floor side against the estimate's; disown a contradicted IMU."""
        if agree:
            self.sides_agree += 1
            return
        self.sides_disagree += 1
        if (
            self.sides_disagree >= IMU_SIGN_MIN_VOTES
            and self.sides_disagree >= IMU_SIGN_RATIO * self.sides_agree
        ):
            self.disowned = True
            self.current = None
            warnings.warn(
                f"the IMU's pitch put the floor on the other side from the scans' floor "
                f"lines in {self.sides_disagree} scans (agreeing in {self.sides_agree}): "
                "ignored until reset; pitch_rad is positive nose down",
                ImuSignWarning,
                stacklevel=4,
            )
