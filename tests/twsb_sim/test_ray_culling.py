"""The culling never drops a geom a ray meets: pseudo-angles order directions as their
angles do, and a geom is filed in the sector of every direction that reaches it."""

from __future__ import annotations

import math

import numpy as np

from twsb_sim.ray_culling import SECTORS, _pseudo_angle, _sector, index_geoms


def test_pseudo_angles_grow_with_the_angle_around_the_circle():
    angles = np.linspace(-math.pi, math.pi, 20001)[:-1]
    turns = np.array([_pseudo_angle(math.cos(a), math.sin(a)) for a in angles])
    shifted = np.mod(turns - turns[0], 4)  # start the circle at -pi, as the angles do
    assert np.all(np.diff(shifted) > 0)
    assert shifted[-1] < 4
    quarter = len(angles) // 4
    np.testing.assert_allclose(shifted[::quarter], [0, 1, 2, 3], atol=1e-12)
    assert _pseudo_angle(0.0, 0.0) == 0.0


def test_a_box_is_in_the_sector_of_every_direction_to_it():
    rng = np.random.default_rng(4)
    eye = np.eye(3).ravel()
    for _ in range(200):
        centre = rng.uniform(-5, 5, 3)
        extents = rng.uniform(0.01, 2.0, (1, 3))
        xpos, xmat = centre[None, :], eye[None, :]
        no_cutoff = np.array([False])
        order, near, low, high, start, items = index_geoms(
            np.zeros(3), extents, no_cutoff, np.ones(1), np.array([0]), xpos, xmat, 12.0
        )
        assert order.tolist() == [0]
        np.testing.assert_allclose(low[0], centre - extents[0], atol=1e-5)  # widened by 1 um
        np.testing.assert_allclose(high[0], centre + extents[0], atol=1e-5)
        points = centre + rng.uniform(-1, 1, (50, 3)) * extents  # inside the box
        assert near[0] <= np.linalg.norm(points, axis=1).min()
        for x, y, _ in points:
            s = _sector(_pseudo_angle(x, y))
            assert 0 in items[start[s] : start[s + 1]].tolist(), (centre, x, y)
        assert 0 < start[SECTORS] <= SECTORS
