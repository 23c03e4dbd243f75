"""The occupancy grid of the Hector-style SLAM: interpolation, gradients, ray updates."""

import numpy as np
import pytest

from scaneval.slam import OccupancyGrid


def _random_grid(seed: int = 0) -> OccupancyGrid:
    grid = OccupancyGrid(resolution_m=0.1, size_m=4.0)
    grid.log_odds[:] = np.random.default_rng(seed).normal(0.0, 2.0, grid.log_odds.shape)
    grid.refresh()
    return grid


def test_interpolation_hits_cell_values_at_cell_centres():
    grid = _random_grid()
    i, j = np.array([5, 17, 30]), np.array([9, 22, 3])
    centres = grid.origin_xy + (np.column_stack((i, j)) + 0.5) * grid.resolution_m
    values, _ = grid.interpolate(centres)
    np.testing.assert_allclose(values, grid.probability()[i, j], atol=1e-12)


def test_gradient_matches_finite_differences():
    grid = _random_grid(1)
    rng = np.random.default_rng(2)
    # points away from cell-centre lines, where bilinear interpolation is smooth
    points = rng.uniform(-1.5, 1.5, (50, 2))
    frac = ((points - grid.origin_xy) / grid.resolution_m - 0.5) % 1.0
    points = points[np.all((frac > 0.05) & (frac < 0.95), axis=1)]
    _, gradients = grid.interpolate(points)
    h = 1e-6
    for axis in (0, 1):
        step = np.zeros(2)
        step[axis] = h
        ahead, _ = grid.interpolate(points + step)
        behind, _ = grid.interpolate(points - step)
        np.testing.assert_allclose(gradients[:, axis], (ahead - behind) / (2 * h), atol=1e-5)


def test_points_off_the_grid_read_unknown_with_no_gradient():
    grid = _random_grid()
    values, gradients = grid.interpolate(np.array([[10.0, 0.0], [-2.0, -2.0], [0.0, 1.99]]))
    np.testing.assert_array_equal(values, 0.5)
    np.testing.assert_array_equal(gradients, 0.0)


def test_ray_update_frees_the_beam_and_occupies_its_end():
    grid = OccupancyGrid(resolution_m=0.05, size_m=6.0)
    grid.update(np.zeros(2), np.array([[2.0, 0.01], [0.01, -1.5]]))
    probability = grid.probability()
    values, _ = grid.interpolate(np.array([[1.0, 0.01], [0.01, -0.7]]))
    assert np.all(values < 0.5)  # along the beams: free
    end = ((np.array([2.0, 0.01]) - grid.origin_xy) / grid.resolution_m).astype(int)
    assert probability[end[0], end[1]] == pytest.approx(0.9)  # one hit: p_occupied
    # every touched cell was updated once: free cells read p_free exactly
    assert np.isclose(probability, 0.4).sum() == pytest.approx(40 + 30, abs=4)
    assert np.isclose(probability, 0.9).sum() == 2


def test_probabilities_follow_the_log_odds_through_updates():
    grid = OccupancyGrid(resolution_m=0.05, size_m=6.0)
    rng = np.random.default_rng(5)
    for _ in range(5):
        grid.update(rng.uniform(-1, 1, 2), rng.uniform(-2.9, 2.9, (50, 2)))
    np.testing.assert_allclose(grid.probability(), 1.0 / (1.0 + np.exp(-grid.log_odds)))


def test_log_odds_stay_within_the_limit():
    grid = OccupancyGrid(resolution_m=0.1, size_m=4.0, log_odds_limit=3.0)
    for _ in range(20):
        grid.update(np.zeros(2), np.array([[1.5, 0.0]]))
    assert grid.log_odds.max() == pytest.approx(3.0)
    assert grid.log_odds.min() == pytest.approx(-3.0)


def test_endpoints_off_the_grid_are_ignored():
    grid = OccupancyGrid(resolution_m=0.1, size_m=2.0)
    grid.update(np.zeros(2), np.array([[5.0, 0.0], [0.0, 1e9], [np.nan, 0.0]]))
    assert grid.log_odds.max() == 0.0  # no endpoint inside: nothing occupied
    assert grid.log_odds.min() < 0.0  # the part of the ray inside the grid is freed


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"resolution_m": 0.0, "size_m": 1.0}, "resolution_m"),
        ({"resolution_m": 0.1, "size_m": 1.0, "p_free": 0.6}, "p_free"),
    ],
)
def test_bad_grid_parameters_are_refused(kwargs, field):
    with pytest.raises(ValueError, match=field):
        OccupancyGrid(**kwargs)
