"""The compiled reading pass gives the numbers of the numpy formulas it replaced, to the
bit, and a beam between two mixed edges reads the second's mix."""

from __future__ import annotations

import math

import numpy as np

from twsb_sim.labels import BeamLabel
from twsb_sim.lidar_reading import PARAMS, read_beams
from twsb_sim.sensors.lidar_errors import mix_edges

NUMBERS = {
    "range_min_m": 0.15,
    "range_max_m": 12.0,
    "dropout_probability": 0.05,
    "cos_grazing_start": math.cos(math.radians(80.0)),
    "horizontal_normal_min_z": 0.9,
    "range_noise_std_m": 0.005,
    "range_noise_fraction": 0.01,
    "mixed_pixel_probability": 0.5,
    "mixed_pixel_min_jump_m": 0.2,
    "range_resolution_m": 0.0005,
}


def _numpy_reading(c, dist, ids, normals, along, normal_draws, uniforms, by_geom, adjacent,
                   origins, dirs, useful, n):  # fmt: skip
    """The reading as numpy calls, before it was compiled."""
    miss = (ids < 0) | (dist > c["range_max_m"])
    lost = uniforms[0] < c["dropout_probability"]
    lost |= uniforms[1] < 1.0 - np.abs(along) / c["cos_grazing_start"]
    no_return = miss | lost
    geom = np.where(no_return, np.int32(-1), ids)
    labels = by_geom[geom]
    horizontal = np.abs(normals[2::3]) >= c["horizontal_normal_min_z"]
    labels[horizontal & (labels == BeamLabel.STATIC)] = BeamLabel.HORIZONTAL
    std = c["range_noise_std_m"] + c["range_noise_fraction"] * dist
    readings = dist + std * normal_draws
    near, far = np.minimum(dist[:-1], dist[1:]), np.maximum(dist[:-1], dist[1:])
    edge = adjacent & ~no_return[:-1] & ~no_return[1:] & (far - near > c["mixed_pixel_min_jump_m"])
    j = np.flatnonzero(edge & (uniforms[2, :-1] < c["mixed_pixel_probability"]))
    readings[j + (uniforms[3, j] < 0.5)] = near[j] + uniforms[4, j] * (far[j] - near[j])
    step = c["range_resolution_m"]
    readings = np.rint(readings / step) * step
    ranges = np.minimum(np.maximum(readings, c["range_min_m"]), c["range_max_m"])
    ranges[dist < c["range_min_m"]] = -np.inf
    ranges[no_return] = np.inf
    points = origins + dirs * dist[:, None]
    points[no_return] = np.nan
    full = [np.full(n, -np.inf), np.full(n, BeamLabel.OCCLUDED, np.uint8),
            np.full((n, 3), np.nan), np.full(n, -1, np.int32)]  # fmt: skip
    for array, values in zip(full, (ranges, labels, points, geom), strict=True):
        array[useful] = values
    return full


def test_the_compiled_pass_is_the_numpy_reading_to_the_bit():
    rng = np.random.default_rng(7)
    n, useful = 720, np.r_[0:120, 360:720]  # a blocked sector in between
    m = len(useful)
    dist = np.where(rng.random(m) < 0.1, -1.0, rng.uniform(0.05, 14.0, m))  # misses, too near
    ids = np.where(dist < 0, -1, rng.integers(0, 6, m)).astype(np.int32)
    normals = rng.normal(size=(m, 3))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    dirs = rng.normal(size=(m, 3))
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    along = np.einsum("ij,ij->i", normals, dirs)
    origins = rng.normal(size=(m, 3))
    by_geom = np.array([1, 1, 2, 3, 1, 5, 0], np.uint8)  # STATIC, FLOOR, ...; last: no hit
    adjacent = np.diff(useful) == 1
    draws, uniforms = rng.standard_normal(m), rng.random((5, m))
    params = np.array([NUMBERS[name] for name in PARAMS])
    args = (dist, ids, normals.ravel(), along, draws, uniforms, by_geom, adjacent, origins, dirs)
    compiled = read_beams(*args, useful, n, params)
    expected = _numpy_reading(NUMBERS, *args, useful, n)
    for got, want in zip(compiled, expected, strict=True):
        assert got.dtype == want.dtype and got.shape == want.shape
        assert np.array_equal(got.view(np.uint8), want.view(np.uint8))
    assert (compiled[1] == BeamLabel.HORIZONTAL).any() and np.isneginf(compiled[0][useful]).any()


def test_a_beam_two_mixed_edges_share_reads_the_second_one():
    ranges, dist = np.zeros(3), np.array([1.0, 3.0, 1.0])  # edges 0-1 and 1-2
    uniforms = np.array([[0.0, 0.0], [0.1, 0.9], [0.25, 0.75]])  # beam 1 both times
    mix_edges(ranges, dist, np.zeros(3, bool), np.ones(2, bool), uniforms, 1.0, 0.2)
    assert ranges.tolist() == [0.0, 1.0 + 0.75 * 2.0, 0.0]
