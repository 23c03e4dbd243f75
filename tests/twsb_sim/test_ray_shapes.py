"""Each compiled intersection gives MuJoCo's own numbers (``mju_rayGeom``), and the
closed-form answer where one is simple."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from twsb_sim.ray_shapes import BOX, CYLINDER, PLANE, SHAPES, SPHERE, ray_geom

EYE = np.eye(3).ravel()


def _mujoco(kind, pos, mat, size, p, v):
    normal = np.zeros(3)
    x = mujoco.mju_rayGeom(pos, mat, size, p, v, kind, normal)
    return x, normal


def _random_rotation(rng):
    quat = rng.normal(size=4)
    mat = np.empty(9)
    mujoco.mju_quat2Mat(mat, quat / np.linalg.norm(quat))
    return mat


@pytest.mark.parametrize("kind", SHAPES)
def test_every_shape_is_mujocos_to_the_bit(kind):
    rng = np.random.default_rng(kind)
    hits = 0
    for i in range(1500):
        pos = rng.uniform(-1, 1, 3)
        mat = EYE if i % 5 == 0 else _random_rotation(rng)
        size = rng.uniform(0.05, 1.0, 3)
        if kind == PLANE and i % 3 == 0:
            size[:2] = 0.0  # unbounded
        p = rng.uniform(-2, 2, 3)
        if i % 7 == 0:
            p = pos + rng.uniform(-0.03, 0.03, 3)  # from inside (or just outside)
        v = pos + rng.normal(scale=0.6, size=3) - p
        if i % 4 == 0:
            v = np.round(v)  # along the axes, some components zero
        if not v.any():
            continue
        expected_x, expected_normal = _mujoco(kind, pos, mat, size, p, v)
        x, *normal = ray_geom(kind, pos, mat, size, p, v)
        assert x == expected_x
        if x >= 0:
            hits += 1
            assert np.array_equal(normal, expected_normal)
        else:
            assert normal == [0.0, 0.0, 0.0]
    assert hits > 200  # the sample does hit (a plane only from its front)


def test_closed_form_hits_grazes_and_misses():
    origin = np.zeros(3)
    unit = np.array([1.0, 0.0, 0.0])
    # a unit sphere 3 m ahead: hit at 2 m, normal back at the ray
    x, *n = ray_geom(SPHERE, np.array([3.0, 0, 0]), EYE, np.array([1.0, 0, 0]), origin, unit)
    assert x == pytest.approx(2.0) and n == pytest.approx([-1, 0, 0])
    # grazing: the ray touches the sphere's side (discriminant exactly 0), as MuJoCo counts it
    pos = np.array([3.0, 1.0, 0.0])
    x, *n = ray_geom(SPHERE, pos, EYE, np.array([1.0, 0, 0]), origin, unit)
    assert x == _mujoco(SPHERE, pos, EYE, np.array([1.0, 0, 0]), origin, unit)[0] == 3.0
    # a box around the origin: from inside, the ray meets the far face
    x, *n = ray_geom(BOX, origin, EYE, np.array([0.5, 0.2, 0.3]), origin, unit)
    assert (x, n) == (0.5, [1.0, 0.0, 0.0])
    # a cylinder standing 2 m ahead, radius 0.5: its round side at 1.5 m
    cylinder = np.array([2.0, 0.0, 0.0])
    x, *n = ray_geom(CYLINDER, cylinder, EYE, np.array([0.5, 1.0, 0]), origin, unit)
    assert x == pytest.approx(1.5) and n == pytest.approx([-1, 0, 0])
    # a plane is seen from its front only
    floor = np.array([0.0, 0.0, -1.0])
    down, up = np.array([0.0, 0.0, -1.0]), np.array([0.0, 0.0, 1.0])
    assert ray_geom(PLANE, floor, EYE, np.zeros(3), origin, down)[:2] == (1.0, 0.0)
    assert ray_geom(PLANE, floor, EYE, np.zeros(3), np.array([0, 0, -2.0]), up)[0] == -1.0
    # a finite plane is missed beside its rectangle
    beside = np.array([0.0, 0.0, -1.0]) + np.array([3.0, 0, 0])
    assert ray_geom(PLANE, beside, EYE, np.array([1.0, 1.0, 0]), origin, down)[0] == -1.0
