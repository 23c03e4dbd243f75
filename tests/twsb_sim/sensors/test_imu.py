"""The IMU's error model against its parameters, and the attitude filter against closed form."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from twsb_sim.sensors.attitude import AttitudeFilterConfig, ComplementaryFilter, quat_from_rpy
from twsb_sim.sensors.imu import STANDARD_GRAVITY_MPS2, ImuConfig, ImuModel

G = STANDARD_GRAVITY_MPS2
AT_REST = np.array([0.0, 0.0, 0.0, 0.0, 0.0, G])  # gyro, accel of a level IMU at rest


def _gravity(roll: float, pitch: float) -> np.ndarray:
    """The specific force a still IMU reads at a roll and pitch (+ nose down)."""
    return G * np.array(
        [-math.sin(pitch), math.cos(pitch) * math.sin(roll), math.cos(pitch) * math.cos(roll)]
    )


def test_white_noise_std_is_the_density_times_root_rate():
    config = dataclasses.replace(ImuConfig.ideal(rate_hz=400.0),
                                 gyro_noise_density_rad_s_sqrt_hz=2e-4,
                                 accel_noise_density_mps2_sqrt_hz=2e-3)  # fmt: skip
    readings = ImuModel(config, np.random.default_rng(0)).measure(np.tile(AT_REST, (20000, 1)))
    errors = readings - AT_REST
    np.testing.assert_allclose(errors[:, :3].std(axis=0), 2e-4 * 20.0, rtol=0.03)
    np.testing.assert_allclose(errors[:, 3:].std(axis=0), 2e-3 * 20.0, rtol=0.03)
    assert np.all(np.abs(errors.mean(axis=0)) < 3 * errors.std(axis=0) / math.sqrt(20000))


def test_bias_offsets_are_drawn_once_per_run_within_their_bounds():
    config = dataclasses.replace(ImuConfig.ideal(), gyro_bias_offset_rad_s=0.02,
                                 accel_bias_offset_mps2=0.2)  # fmt: skip
    offsets = []
    for seed in range(200):
        readings = ImuModel(config, np.random.default_rng(seed)).measure(np.tile(AT_REST, (5, 1)))
        assert np.ptp(readings, axis=0).max() == 0.0  # constant within the run
        offsets.append(readings[0] - AT_REST)
    offsets = np.array(offsets)
    assert np.all(np.abs(offsets[:, :3]) <= 0.02) and np.all(np.abs(offsets[:, 3:]) <= 0.2)
    assert offsets[:, :3].std() == pytest.approx(0.02 / math.sqrt(3), rel=0.1)  # uniform


def test_bias_random_walk_spreads_as_root_time():
    config = dataclasses.replace(ImuConfig.ideal(rate_hz=100.0), gyro_bias_walk_rad_s_sqrt_s=1e-3)
    finals = []
    for seed in range(300):
        model = ImuModel(config, np.random.default_rng(seed))
        for _ in range(4):  # in batches: the walk carries over between calls
            readings = model.measure(np.tile(AT_REST, (100, 1)))
        finals.append(readings[-1, :3])
    assert np.std(finals) == pytest.approx(1e-3 * math.sqrt(4.0), rel=0.1)  # 4 s of walk


def test_readings_saturate_at_the_range():
    config = dataclasses.replace(ImuConfig.ideal(), gyro_range_rad_s=1.0, accel_range_mps2=20.0)
    readings = ImuModel(config, np.random.default_rng(0)).measure(
        np.array([[3.0, -0.5, -2.0, 50.0, 0.0, -30.0]])
    )
    np.testing.assert_array_equal(readings, [[1.0, -0.5, -1.0, 20.0, 0.0, -20.0]])


def test_defaults_are_the_bmi088_data_sheet():
    config = ImuConfig()
    assert math.degrees(config.gyro_noise_density_rad_s_sqrt_hz) == pytest.approx(0.014)
    assert config.accel_noise_density_mps2_sqrt_hz / G == pytest.approx(175e-6)
    assert math.degrees(config.gyro_bias_offset_rad_s) == pytest.approx(1.0)
    assert config.accel_bias_offset_mps2 / G == pytest.approx(0.020)
    assert math.degrees(config.gyro_range_rad_s) == pytest.approx(2000.0)


@pytest.mark.parametrize(
    ("field", "value"),
    [("rate_hz", 1000.0), ("rate_hz", "fast"), ("latency_s", -0.01), ("gyro_range_rad_s", 0.0),
     ("accel_bias_offset_mps2", -1.0), ("gyro_noise_density_rad_s_sqrt_hz", float("nan"))],
)  # fmt: skip
def test_config_errors_start_with_the_field_name(field, value):
    with pytest.raises(ValueError, match=rf"^{field}: expected"):
        ImuConfig(**{field: value})


def test_still_tilted_imu_settles_on_the_gravity_attitude_with_the_time_constant():
    tau, rate = 0.5, 200.0
    f = ComplementaryFilter(AttitudeFilterConfig(time_constant_s=tau), 1.0 / rate)
    f.update(np.array([AT_REST]))  # starts level
    roll, pitch = math.radians(-4.0), math.radians(7.0)
    still = np.tile(np.r_[0.0, 0.0, 0.0, _gravity(roll, pitch)], (int(3 * rate), 1))
    rpy = f.update(still)
    a = tau / (tau + 1.0 / rate)
    k = np.arange(1, len(still) + 1)
    # a first-order lag: the gap closes by the gain a at every sample
    np.testing.assert_allclose(rpy[:, 1], pitch * (1 - a**k), atol=1e-9)
    np.testing.assert_allclose(rpy[:, 0], roll * (1 - a**k), atol=1e-9)
    assert rpy[int(tau * rate), 1] == pytest.approx(pitch * (1 - math.exp(-1)), rel=0.01)


def test_the_filter_starts_at_rest_not_from_a_sample_in_free_fall():
    # a robot set down just above the floor measures no gravity for a moment: its tilt
    # from that sample is noise (here 53 deg of roll); the filter starts from the first
    # sample that measures about g, and reads level until then
    f = ComplementaryFilter(AttitudeFilterConfig(), 1.0 / 200.0)
    roll, pitch = math.radians(1.0), math.radians(-2.0)
    falling = np.array([[0.0, 0.0, 0.0, -0.04, 0.12, 0.09]] * 2)
    resting = np.tile(np.r_[0.0, 0.0, 0.0, _gravity(roll, pitch)], (3, 1))
    rpy = f.update(np.concatenate((falling, resting)))
    np.testing.assert_array_equal(rpy[:2], 0.0)
    np.testing.assert_allclose(rpy[2:, :2], [[roll, pitch]] * 3, atol=1e-12)
    # once started it follows every sample, a free-falling one too
    assert f.update(falling)[0, 0] != pytest.approx(roll)


def test_consistent_rotation_is_tracked_and_yaw_integrates_the_gyro():
    dt = 0.005  # s, 200 Hz
    f = ComplementaryFilter(AttitudeFilterConfig(time_constant_s=0.3), dt)
    pitch_rate, yaw_rate = math.radians(10.0), 0.4  # rad/s, about the body y and world z
    rows = []
    for k in range(1, 201):
        pitch = pitch_rate * k * dt
        # body rates of yaw about world z then pitch about body y (no roll)
        gyro = [-math.sin(pitch) * yaw_rate, pitch_rate, math.cos(pitch) * yaw_rate]
        rows.append([*gyro, *_gravity(0.0, pitch)])
    f.update(np.array([AT_REST]))
    rpy = f.update(np.array(rows))
    pitches = pitch_rate * np.arange(1, 201) * dt
    np.testing.assert_allclose(rpy[:, 1], pitches, atol=1e-3)
    np.testing.assert_allclose(rpy[:, 0], 0.0, atol=2e-4)  # Euler steps of 5 ms
    np.testing.assert_allclose(rpy[-1, 2], yaw_rate * 1.0, atol=1e-3)


def test_quat_from_rpy_is_z_y_x():
    q = quat_from_rpy(0.0, 0.3, 0.0)
    np.testing.assert_allclose(q, [math.cos(0.15), 0.0, math.sin(0.15), 0.0])
    w, x, y, z = quat_from_rpy(0.2, -0.1, 1.0)
    assert math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y)) == pytest.approx(0.2)
    assert math.asin(2 * (w * y - z * x)) == pytest.approx(-0.1)
