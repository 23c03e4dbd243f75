import math

import numpy as np
import pytest

from pvfilter.scan import Scan
from scaneval.geometry import (
    compose,
    invert,
    pose_from_matrix,
    scan_points,
    se2_matrix,
    transform_points,
    wrap_angle,
)


def test_compose_matches_matrix_product():
    a, b = np.array([1.0, -2.0, 2.5]), np.array([0.3, 0.7, 1.9])
    expected = pose_from_matrix(se2_matrix(a) @ se2_matrix(b))
    np.testing.assert_allclose(compose(a, b), expected, atol=1e-12)


def test_pose_composed_with_its_inverse_is_identity():
    pose = np.array([0.4, -1.3, -2.9])
    np.testing.assert_allclose(compose(pose, invert(pose)), 0.0, atol=1e-12)
    np.testing.assert_allclose(compose(invert(pose), pose), 0.0, atol=1e-12)


def test_transform_points_is_rotation_then_translation():
    moved = transform_points(np.array([[1.0, 0.0], [0.0, 2.0]]), (1.0, 1.0, math.pi / 2))
    np.testing.assert_allclose(moved, [[1.0, 2.0], [-1.0, 1.0]], atol=1e-12)


def test_transform_by_composition_equals_transform_twice():
    points = np.random.default_rng(0).normal(size=(20, 2))
    a, b = (0.2, 0.1, 0.5), (-1.0, 0.4, -2.0)
    np.testing.assert_allclose(
        transform_points(points, compose(a, b)),
        transform_points(transform_points(points, b), a),
        atol=1e-12,
    )


def test_wrap_angle_lands_in_half_open_interval():
    wrapped = wrap_angle(np.array([math.pi, -math.pi, 3 * math.pi + 0.1, -0.1]))
    np.testing.assert_allclose(wrapped, [-math.pi, -math.pi, -math.pi + 0.1, -0.1], atol=1e-12)


def test_scan_points_drop_invalid_and_masked_beams():
    scan = Scan(
        ranges=[1.0, np.nan, np.inf, -np.inf, 20.0, 2.0],
        angle_min=0.0,
        angle_increment=math.pi / 2,
        range_min=0.1,
        range_max=10.0,
    )
    np.testing.assert_allclose(scan_points(scan), [[1.0, 0.0], [0.0, 2.0]], atol=1e-12)
    mask = np.array([True, False, False, False, False, False])
    np.testing.assert_allclose(scan_points(scan, mask), [[0.0, 2.0]], atol=1e-12)


def test_scan_points_rejects_mask_of_wrong_length():
    scan = Scan(ranges=[1.0, 1.0], angle_min=0.0, angle_increment=0.1, range_min=0.1, range_max=5)
    with pytest.raises(ValueError, match="mask"):
        scan_points(scan, np.zeros(3, dtype=bool))
