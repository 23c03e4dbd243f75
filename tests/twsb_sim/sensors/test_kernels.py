"""The compiled sensor kernels give the numbers of the numpy and Python formulas they
replaced, to the bit: the same seed makes the same data sets as before they were compiled."""

from __future__ import annotations

import math

import numpy as np
import pytest

from twsb_sim.sensors.attitude import AttitudeFilterConfig, ComplementaryFilter
from twsb_sim.sensors.imu import ImuConfig, ImuModel
from twsb_sim.sensors.odometry import EncoderOdometry, OdometryConfig, _remainder_tau
from twsb_sim.sensors.sweep import PoseTrack, poses_from_quats

RNG = np.random.default_rng(42)


def _same(a, b) -> bool:
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    return a.shape == b.shape and np.array_equal(a.view(np.uint64), b.view(np.uint64))


def test_the_remainder_is_python_s_to_the_bit_ties_included():
    angles = [*RNG.normal(0.0, 10.0, 20000).tolist(), math.pi, -math.pi, 3 * math.pi, -0.0, 0.0]
    for angle in angles:
        assert _same(_remainder_tau(angle), math.remainder(angle, math.tau)), angle


def test_imu_errors_are_the_cumulative_sum_formula():
    config = ImuConfig(gyro_range_rad_s=0.5, accel_range_mps2=12.0)  # some readings saturate
    model, check = ImuModel(config, np.random.default_rng(1)), np.random.default_rng(1)
    check.uniform(-1.0, 1.0, size=6)  # the offsets' draws
    bias = np.zeros(6)
    for k in (20, 1, 7):
        true = RNG.normal(0.0, 3.0, (k, 6))
        draws = check.standard_normal((k, 12))
        walk = bias + np.cumsum(draws[:, :6] * model._walk_std, axis=0)
        bias = walk[-1].copy()
        expected = true + model.offset + walk + draws[:, 6:] * model._white_std
        expected = np.minimum(np.maximum(expected, -model._range), model._range)
        assert _same(model.measure(true), expected)
    assert _same(model.bias_walk, bias)


def _attitude_loop(readings, state, a, dt):
    """The filter as it was written in Python; ``state`` None or the last (r, p, y)."""
    b = 1.0 - a
    roll_in = (b * np.arctan2(readings[:, 4], readings[:, 5])).tolist()
    pitch_in = (b * np.arctan2(-readings[:, 3], np.hypot(readings[:, 4], readings[:, 5]))).tolist()
    roll, pitch, yaw = state or (roll_in[0] / b, pitch_in[0] / b, 0.0)
    out = []
    for (wx, wy, wz), r_in, p_in in zip(readings[:, :3].tolist(), roll_in, pitch_in, strict=True):
        sr, cr, cp = math.sin(roll), math.cos(roll), math.cos(pitch)
        turn = sr * wy + cr * wz
        roll = a * (roll + (wx + turn * math.sin(pitch) / cp) * dt) + r_in
        pitch = a * (pitch + (cr * wy - sr * wz) * dt) + p_in
        yaw += turn / cp * dt
        out.append((roll, pitch, (yaw + math.pi) % math.tau - math.pi))
    return out


def test_the_attitude_filter_is_the_python_loop():
    readings = np.column_stack([RNG.normal(0, 2.0, (30, 3)), RNG.normal((0, 0, 9.8), 0.5, (30, 3))])
    estimator = ComplementaryFilter(AttitudeFilterConfig(), 0.005)
    first = _attitude_loop(readings[:12], None, estimator.gain, 0.005)
    second = _attitude_loop(readings[12:], first[-1], estimator.gain, 0.005)
    assert _same(estimator.update(readings[:12]), first)
    assert _same(estimator.update(readings[12:]), second)


def test_dead_reckoning_is_the_python_loop():
    odometry = EncoderOdometry(OdometryConfig(), 0.08, 0.3)
    angles = np.cumsum(RNG.normal(0.2, 0.3, (25, 2)), axis=0)
    ticks = np.floor(angles / odometry.rad_per_tick)
    scale = odometry.rad_per_tick * odometry.radii_m
    steps = np.diff(ticks, axis=0, prepend=[[0.0, 0.0]]) * scale
    x = y = yaw = 0.0
    expected = []
    for left, right in steps.tolist():
        distance, turn = 0.5 * (left + right), (right - left) / 0.3
        heading, half = yaw + 0.5 * turn, 0.5 * turn
        chord = distance * (math.sin(half) / half if abs(half) > 1e-9 else 1.0)
        x, y = x + chord * math.cos(heading), y + chord * math.sin(heading)
        yaw = math.remainder(yaw + turn, math.tau)
        expected.append((x, y, yaw, distance / odometry.dt_s, turn / odometry.dt_s))
    poses, twists = odometry.update(angles)
    assert _same(np.column_stack([poses, twists]), expected)


def test_the_pose_track_is_numpy_s_outer_product_and_interpolation():
    quats = RNG.normal(size=(6, 4))
    quats /= np.linalg.norm(quats, axis=1, keepdims=True)
    positions = RNG.normal(size=(6, 3))
    q = quats[:, :, None] * quats[:, None, :]
    pick = lambda i, j: q[:, i, j]  # noqa: E731
    w, x, y, z = 0, 1, 2, 3
    axes = [
        1.0 - (pick(z, z) + pick(y, y)) * 2.0, (pick(w, z) + pick(x, y)) * 2.0,
        (-pick(w, y) + pick(x, z)) * 2.0, (-pick(w, z) + pick(x, y)) * 2.0,
        1.0 - (pick(z, z) + pick(x, x)) * 2.0, (pick(w, x) + pick(y, z)) * 2.0,
    ]  # fmt: skip
    poses = poses_from_quats(positions, quats)
    assert _same(poses, np.column_stack([positions, *axes]))

    track = PoseTrack(1.0, 0.002, poses)
    times = 1.0 + RNG.uniform(-0.002, 0.012, 50)  # before, within and after the span
    angles = RNG.uniform(-math.pi, math.pi, 50)
    dirs_sensor = np.column_stack([np.cos(angles), np.sin(angles), np.zeros(50)])
    where = np.minimum(np.maximum((times - 1.0) / 0.002, 0.0), 5)
    j = np.minimum(where.astype(np.intp), 4)
    lerp = poses[j] + (where - j)[:, None] * (poses[j + 1] - poses[j])
    dirs = dirs_sensor[:, :1] * lerp[:, 3:6] + dirs_sensor[:, 1:2] * lerp[:, 6:9]
    dirs /= np.sqrt(np.einsum("ki,ki->k", dirs, dirs))[:, None]
    origins, beams = track.beams(times, dirs_sensor)
    assert _same(origins, lerp[:, :3]) and _same(beams, dirs)


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_unit_quaternions_give_rotation_matrix_columns(axis):
    angle = 0.7
    quat = np.zeros(4)
    quat[0], quat[1 + axis] = math.cos(angle / 2), math.sin(angle / 2)
    pose = poses_from_quats(np.zeros((1, 3)), quat[None, :])[0]
    c, s = math.cos(angle), math.sin(angle)
    rotation = np.eye(3)
    i, k = [(1, 2), (2, 0), (0, 1)][axis]
    rotation[i, i], rotation[i, k], rotation[k, i], rotation[k, k] = c, -s, s, c
    np.testing.assert_allclose(pose[3:6], rotation[:, 0], atol=1e-15)
    np.testing.assert_allclose(pose[6:9], rotation[:, 1], atol=1e-15)
