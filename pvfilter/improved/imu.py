"""The optional IMU input: the attitude the robot's estimator gives, and how far off it is.

An attitude estimator's pitch is noisy, biased by up to about a degree, and lags the body
by tens of milliseconds; a rotating LiDAR measures a floor line over tens of
milliseconds more. So the pitch of the scan plane is taken to lie within
``imu_angle_error_deg`` plus the pitch rate times ``IMU_TIMING_S`` of the estimate: a
fast pitch change widens the band, a steady tilt keeps it narrow. The rate comes from
consecutive estimates.
"""

from __future__ import annotations

import dataclasses
import math

from pvfilter.improved.params import ImprovedParams

IMU_TIMING_S = 0.1  # s: how far a beam's time may be from the estimate's (the estimator's
# lag of tens of ms, and half a scan)


@dataclasses.dataclass(frozen=True)
class Attitude:
    """The scan plane's attitude as the IMU gives it.

    Attributes:
        pitch_rad: pitch, rad, positive nose down.
        roll_rad: roll, rad, positive left side up.
        error_rad: how far the scan plane's pitch may be from ``pitch_rad``, rad.
    """

    pitch_rad: float
    roll_rad: float
    error_rad: float

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
    """The IMU's estimates scan after scan, for their rate.

    Args:
        params: ``imu_angle_error_deg`` is used.
    """

    def __init__(self, params: ImprovedParams) -> None:
        self.params = params
        self.reset()

    def reset(self) -> None:
        """Forget the previous estimate."""
        self.previous: tuple[float, float] | None = None  # (stamp s, pitch rad)
        self.current: Attitude | None = None  # the latest scan's

    def update(self, attitude: tuple[float, float] | None, stamp: float) -> Attitude | None:
        """The attitude for the scan at ``stamp`` (None without an IMU)."""
        if attitude is None:
            self.previous = self.current = None
            return None
        pitch, roll = attitude
        rate = 0.0
        if self.previous is not None and stamp > self.previous[0]:
            rate = (pitch - self.previous[1]) / (stamp - self.previous[0])
        self.previous = (stamp, pitch)
        error = math.radians(self.params.imu_angle_error_deg) + abs(rate) * IMU_TIMING_S
        self.current = Attitude(pitch, roll, error)
        return self.current
