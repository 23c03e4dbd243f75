import math

import numpy as np
import pytest

from scaneval.geometry import transform_points
from scaneval.metrics import (
    associate,
    ate,
    auc_pr,
    chamfer_distance,
    confusion_counts,
    pr_curve,
    precision_recall,
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


def test_precision_is_one_when_nothing_is_removed():
    positive = np.array([True, True, False, False])
    precision, recall = precision_recall(np.zeros(4, bool), positive, np.ones(4, bool))
    assert (precision, recall) == (1.0, 0.0)


def test_precision_recall_count_only_finite_beams():
    removed = np.array([True, True, False, True, False])
    positive = np.array([True, False, True, True, True])
    finite = np.array([True, True, True, False, False])
    assert confusion_counts(removed, positive, finite) == (1, 1, 1)
    assert precision_recall(removed, positive, finite) == (0.5, 0.5)


def test_auc_of_perfect_curve_is_one():
    assert auc_pr([1.0, 1.0], [0.5, 1.0]) == pytest.approx(1.0)
    assert auc_pr([1.0], [1.0]) == pytest.approx(1.0)


def test_auc_of_flat_curve_at_half_is_half():
    assert auc_pr([0.5, 0.5, 0.5], [0.1, 0.6, 1.0]) == pytest.approx(0.5)


def test_auc_sorts_unsorted_points_by_recall():
    precision, recall = [0.4, 1.0, 0.8], [1.0, 0.2, 0.6]
    expected = 0.2 * 1.0 + 0.4 * (1.0 + 0.8) / 2 + 0.4 * (0.8 + 0.4) / 2
    assert auc_pr(precision, recall) == pytest.approx(expected)


def test_auc_extends_to_recall_zero_at_lowest_recall_precision_and_not_beyond_last():
    # one point: a rectangle from recall 0 to 0.5 at its precision, nothing past 0.5
    assert auc_pr([0.6], [0.5]) == pytest.approx(0.3)
    assert auc_pr([0.6, 0.2], [0.5, 0.0]) == pytest.approx(0.5 * (0.2 + 0.6) / 2)


def test_pr_curve_from_counts():
    curve = pr_curve([0.9, 0.5, 0.1], tp=[0, 5, 10], fp=[0, 0, 10], fn=[10, 5, 0])
    np.testing.assert_allclose(curve.precision, [1.0, 1.0, 0.5])
    np.testing.assert_allclose(curve.recall, [0.0, 0.5, 1.0])
    assert curve.auc == pytest.approx(0.5 + 0.5 * 0.75)


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


def test_a_curve_states_its_operating_point():
    curve = pr_curve([0.0, 0.5, 0.8], tp=[10, 6, 2], fp=[10, 2, 0], fn=[0, 4, 8])
    figures = curve.at(0.5)
    assert figures == {"auc": curve.auc, "operating_point": 0.5, "precision": 0.75, "recall": 0.6}
    with pytest.raises(ValueError, match=r"0\.3 is not a swept value"):
        curve.at(0.3)
