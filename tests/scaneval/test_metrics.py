import math

import numpy as np
import pytest

from scaneval.geometry import transform_points
from scaneval.metrics import (
    associate,
    ate,
    chamfer_distance,
    read_tum,
    se2_from_xyz_quat,
    write_tum,
)


def brute_force_chamfer(a, b):
    a_to_b = [min(float(np.sum((x - y) ** 2)) for y in b) for x in a]
    b_to_a = [min(float(np.sum((y - x) ** 2)) for x in a) for y in b]
    return sum(a_to_b) / len(a) + sum(b_to_a) / len(b)


def test_chamfer_distance_equals_brute_force_double_loop():
    rng = np.random.default_rng(0)
    a, b = rng.uniform(-2, 2, (60, 2)), rng.uniform(-2, 2, (45, 2))
    assert chamfer_distance(a, b) == pytest.approx(brute_force_chamfer(a, b), rel=1e-12)


def test_chamfer_distance_ignores_non_finite_points_and_is_zero_on_itself():
    a = np.random.default_rng(1).normal(size=(30, 2))
    with_nan = np.vstack((a, [[np.nan, 0.0], [0.0, np.inf]]))
    assert chamfer_distance(with_nan, a) == 0.0
    assert math.isnan(chamfer_distance(np.full((3, 2), np.nan), a))


def trajectory(count=50):
    t = np.linspace(0.0, 2.0 * math.pi, count)
    return np.column_stack((2.0 * np.cos(t), np.sin(2 * t), t))


def test_ate_of_identical_trajectories_is_zero():
    poses = trajectory()
    assert ate(poses, poses).rmse == pytest.approx(0.0, abs=1e-12)


def test_ate_without_alignment_is_the_offset():
    poses = trajectory()
    shifted = poses + np.array([0.3, -0.4, 0.0])
    assert ate(shifted, poses, align="none").rmse == pytest.approx(0.5)


def test_ate_after_se2_alignment_of_rotated_shifted_copy_is_zero():
    poses = trajectory()
    moved = transform_points(poses[:, :2], (1.0, -2.0, 0.7))
    result = ate(moved, poses, align="se2")
    assert result.rmse == pytest.approx(0.0, abs=1e-9)
    assert result.alignment_pose[2] == pytest.approx(-0.7)


def test_ate_sim2_recovers_scale():
    poses = trajectory()
    result = ate(2.0 * poses[:, :2], poses, align="sim2")
    assert result.scale == pytest.approx(0.5)
    assert result.rmse == pytest.approx(0.0, abs=1e-9)


def test_tum_round_trip(tmp_path):
    stamps, poses = np.arange(5) * 0.1 + 100.0, trajectory(5)
    poses[:, 2] = [0.0, 1.0, -2.0, 3.0, -3.1]
    write_tum(tmp_path / "traj.txt", stamps, poses)
    read_stamps, xyz_quat = read_tum(tmp_path / "traj.txt")
    np.testing.assert_allclose(read_stamps, stamps)
    np.testing.assert_allclose(se2_from_xyz_quat(xyz_quat), poses, atol=1e-8)
    np.testing.assert_allclose(np.linalg.norm(xyz_quat[:, 3:], axis=1), 1.0)


def test_associate_pairs_nearest_stamps_within_tolerance():
    ia, ib = associate([0.0, 0.1, 0.2, 0.5], [0.005, 0.098, 0.3], max_difference_s=0.01)
    np.testing.assert_array_equal(ia, [0, 1])
    np.testing.assert_array_equal(ib, [0, 1])
