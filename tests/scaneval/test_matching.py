import math

import numpy as np
import pytest
from scipy.spatial import cKDTree

from scaneval.geometry import scan_points, transform_points, wrap_angle
from scaneval.match_result import fitness
from scaneval.matching import MATCHERS, hsm, icp, rigid_fit
from scaneval.metrics import chamfer_distance
from scaneval.synthetic import cluttered_room, scan_from_pose

# stated tolerances (m, rad): 2 cm and 0.5 degrees; for HSM that is one bin of its
# Hough directions (0.5 degrees) and one bin of its projections (2 cm)
FINE = {name: (0.02, math.radians(0.5)) for name in ("icp", "ndt", "hsm")}


def pose_error(estimated, truth):
    rotation_error = abs(float(wrap_angle(estimated[2] - truth[2])))
    return float(np.hypot(*(estimated[:2] - truth[:2]))), rotation_error


def fitness_at(pose, source, target):
    return fitness(transform_points(source, pose), cKDTree(target), 1.0)[0]


def test_rigid_fit_recovers_exact_transform():
    source = np.random.default_rng(0).uniform(-3, 3, (50, 2))
    pose = np.array([0.5, -0.2, 1.1])
    np.testing.assert_allclose(rigid_fit(source, transform_points(source, pose)), pose, atol=1e-12)


@pytest.mark.parametrize("name", sorted(FINE))
def test_matcher_recovers_known_transform_of_room_scan(name, room_pair):
    source, target, truth = room_pair
    match = MATCHERS[name](source, target)
    translation_error, rotation_error = pose_error(match.pose, truth)
    assert match.converged
    assert translation_error < FINE[name][0]
    assert rotation_error < FINE[name][1]
    assert match.fitness <= 1.05 * fitness_at(truth, source, target)


@pytest.mark.parametrize("name", sorted(FINE))
def test_matcher_recovers_transform_with_half_the_source_missing(name):
    room = cluttered_room()
    truth = np.array([-0.2, 0.12, math.radians(-3.0)])
    target = scan_points(scan_from_pose(room, (0.0, 0.0, 0.0), rng=np.random.default_rng(3)))
    right_half = (-math.pi, 0.0)
    source = scan_points(
        scan_from_pose(room, truth, rng=np.random.default_rng(4), blocked=right_half)
    )
    match = MATCHERS[name](source, target)
    translation_error, rotation_error = pose_error(match.pose, truth)
    assert translation_error < FINE[name][0]
    assert rotation_error < FINE[name][1]


def test_icp_alignment_brings_chamfer_distance_down_to_that_at_the_true_pose(room_pair):
    source, target, truth = room_pair
    aligned = chamfer_distance(transform_points(source, icp(source, target).pose), target)
    assert aligned < 0.2 * chamfer_distance(source, target)
    assert aligned < 1.05 * chamfer_distance(transform_points(source, truth), target)


def test_icp_ignores_non_finite_points(room_pair):
    source, target, _ = room_pair
    with_nan = np.vstack((source, [[np.nan, 1.0], [np.inf, 0.0]]))
    np.testing.assert_allclose(icp(with_nan, target).pose, icp(source, target).pose)


def test_icp_with_too_few_points_reports_not_converged():
    match = icp(np.zeros((2, 2)), np.ones((10, 2)))
    assert not match.converged
    assert match.iterations == 0


def test_hsm_recovers_large_rotation_without_initial_guess():
    room = cluttered_room()
    truth = np.array([0.6, -0.4, math.radians(100.0)])
    target = scan_points(scan_from_pose(room, (0.0, 0.0, 0.0), rng=np.random.default_rng(5)))
    source = scan_points(scan_from_pose(room, truth, rng=np.random.default_rng(6)))
    translation_error, rotation_error = pose_error(hsm(source, target).pose, truth)
    assert translation_error < 0.02
    assert rotation_error < math.radians(0.5)


@pytest.mark.parametrize("name", sorted(MATCHERS))
def test_matcher_starts_from_initial_pose(name):
    room = cluttered_room()
    truth = np.array([0.6, -0.4, math.radians(100.0)])
    target = scan_points(scan_from_pose(room, (0.0, 0.0, 0.0), rng=np.random.default_rng(5)))
    source = scan_points(scan_from_pose(room, truth, rng=np.random.default_rng(6)))
    guess = truth + np.array([0.1, 0.1, 0.05])
    translation_error, rotation_error = pose_error(
        MATCHERS[name](source, target, initial_pose=guess).pose, truth
    )
    assert translation_error < 0.02
    assert rotation_error < math.radians(0.5)


@pytest.mark.parametrize("name", sorted(MATCHERS))
def test_matcher_of_identical_scans_returns_identity(name, room_pair):
    _, target, _ = room_pair
    match = MATCHERS[name](target, target)
    np.testing.assert_allclose(match.pose, 0.0, atol=1e-3)
    assert match.fitness < 1e-6  # m^2: NDT fits cell Gaussians, not the points themselves
    assert match.inlier_fraction == 1.0
