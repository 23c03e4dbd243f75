"""A MEMS IMU: white noise, bias offsets, bias random walk and saturation on true rates.

MuJoCo's ``gyro`` and ``accelerometer`` sensors give the exact angular velocity and
specific force at the ``imu`` site. :class:`ImuModel` turns samples of them into what a
cheap IMU reports. Defaults are those of the Bosch BMI088 data sheet (BST-BMI088-DS001):
gyroscope output noise 0.014 °/s/√Hz, zero-rate offset ±1 °/s, bias stability 2 °/h,
range ±2000 °/s; accelerometer noise density 175 µg/√Hz, zero-g offset ±20 mg, range
±6 g (one of its ±3/6/12/24 g settings). ``docs/sensors.md`` says how each number maps.

Per sample ``k`` at rate ``f`` (period ``dt``), per axis:

    bias[k]   = bias[k-1] + bias_walk * sqrt(dt) * n1      (random walk)
    reading   = clip(true + offset + bias[k] + density * sqrt(f) * n2, -range, range)

``offset`` is drawn once per run, uniform in ``±bias_offset``. Every sample costs the same
twelve normal draws whatever the settings, so switching one effect off leaves the others'
draws unchanged.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from twsb_sim.kernel import kernel
from twsb_sim.sensors.checks import non_negative, positive, within

STANDARD_GRAVITY_MPS2 = 9.80665  # m/s²
_DEG = math.pi / 180.0


@dataclass(frozen=True)
class ImuConfig:
    """The IMU's sampling and error model (defaults: Bosch BMI088 data sheet).

    A value of 0 switches an effect off; ``ImuConfig.ideal()`` switches off all of them.
    """

    rate_hz: float = 200.0  # samples per second (Hz)
    latency_s: float = 0.005  # s from measurement to the robot's software (bus, driver)
    gyro_noise_density_rad_s_sqrt_hz: float = 0.014 * _DEG  # rad/s/√Hz (0.014 °/s/√Hz)
    gyro_bias_offset_rad_s: float = 1.0 * _DEG  # rad/s, per-run offset drawn in ± this
    gyro_bias_walk_rad_s_sqrt_s: float = 1.0e-6  # rad/s/√s (2 °/h stability over ~100 s)
    gyro_range_rad_s: float = 2000.0 * _DEG  # rad/s, readings saturate here
    accel_noise_density_mps2_sqrt_hz: float = 175e-6 * STANDARD_GRAVITY_MPS2  # m/s²/√Hz
    accel_bias_offset_mps2: float = 0.020 * STANDARD_GRAVITY_MPS2  # m/s² (±20 mg)
    accel_bias_walk_mps2_sqrt_s: float = 1.0e-4  # m/s²/√s (not in the data sheet)
    accel_range_mps2: float = 6.0 * STANDARD_GRAVITY_MPS2  # m/s², readings saturate here

    def __post_init__(self) -> None:
        within("rate_hz", self.rate_hz, 10.0, 500.0, "Hz (at most the 500 Hz physics rate)")
        within("latency_s", self.latency_s, 0.0, 0.1, "s")
        for name in (
            "gyro_noise_density_rad_s_sqrt_hz",
            "gyro_bias_offset_rad_s",
            "gyro_bias_walk_rad_s_sqrt_s",
            "accel_noise_density_mps2_sqrt_hz",
            "accel_bias_offset_mps2",
            "accel_bias_walk_mps2_sqrt_s",
        ):
            non_negative(name, getattr(self, name))
        positive("gyro_range_rad_s", self.gyro_range_rad_s, "rad/s")
        positive("accel_range_mps2", self.accel_range_mps2, "m/s²")

    @classmethod
    def ideal(cls, rate_hz: float = 200.0) -> ImuConfig:
        """A perfect IMU: no noise, bias, latency or saturation within any real motion."""
        return cls(
            rate_hz=rate_hz,
            latency_s=0.0,
            gyro_noise_density_rad_s_sqrt_hz=0.0,
            gyro_bias_offset_rad_s=0.0,
            gyro_bias_walk_rad_s_sqrt_s=0.0,
            gyro_range_rad_s=1e6,
            accel_noise_density_mps2_sqrt_hz=0.0,
            accel_bias_offset_mps2=0.0,
            accel_bias_walk_mps2_sqrt_s=0.0,
            accel_range_mps2=1e6,
        )


class ImuModel:
    """The error state of one IMU over one run (offsets and wandering biases).

    Args:
        config: the error model.
        rng: the run's IMU generator; the offsets are its first six uniform draws.
    """

    def __init__(self, config: ImuConfig, rng: np.random.Generator) -> None:
        self.config = config
        self.rng = rng
        c = config
        unit = rng.uniform(-1.0, 1.0, size=6)
        self.offset = np.concatenate(
            (unit[:3] * c.gyro_bias_offset_rad_s, unit[3:] * c.accel_bias_offset_mps2)
        )
        self.bias_walk = np.zeros(6)  # the random-walk part, gyro xyz then accel xyz
        dt = 1.0 / c.rate_hz
        self._walk_std = np.repeat(
            [c.gyro_bias_walk_rad_s_sqrt_s, c.accel_bias_walk_mps2_sqrt_s], 3
        ) * math.sqrt(dt)
        self._white_std = np.repeat(
            [c.gyro_noise_density_rad_s_sqrt_hz, c.accel_noise_density_mps2_sqrt_hz], 3
        ) * math.sqrt(c.rate_hz)
        self._range = np.repeat([c.gyro_range_rad_s, c.accel_range_mps2], 3)

    def measure(self, true_gyro_accel: np.ndarray) -> np.ndarray:
        """The IMU's readings of ``k`` consecutive samples.

        Args:
            true_gyro_accel: ``(k, 6)`` exact angular velocity (rad/s) and specific force
                (m/s²) in the imu frame, one row per sample, in time order.

        Returns:
            ``(k, 6)`` readings: gyro x y z (rad/s), accel x y z (m/s²).
        """
        draws = self.rng.standard_normal((len(true_gyro_accel), 12))
        return _measure(
            np.asarray(true_gyro_accel, dtype=np.float64), draws, self.offset, self.bias_walk,
            self._walk_std, self._white_std, self._range,
        )  # fmt: skip


@kernel
def _measure(
    true: np.ndarray,
    draws: np.ndarray,
    offset: np.ndarray,
    bias_walk: np.ndarray,
    walk_std: np.ndarray,
    white_std: np.ndarray,
    saturation: np.ndarray,
) -> np.ndarray:
    """Readings of ``k`` samples (see :meth:`ImuModel.measure`); ``bias_walk`` is carried
    on in place. ``draws``: ``(k, 12)`` N(0, 1), six for the walk, six white."""
    out = np.empty_like(true)
    walk = np.zeros(6)  # the walk since this batch began
    for r in range(len(true)):
        for c in range(6):
            walk[c] += draws[r, c] * walk_std[c]
            white = draws[r, 6 + c] * white_std[c]
            reading = true[r, c] + offset[c] + (bias_walk[c] + walk[c]) + white
            out[r, c] = np.minimum(np.maximum(reading, -saturation[c]), saturation[c])
    if len(true):
        for c in range(6):
            bias_walk[c] += walk[c]
    return out
