"""The spawn search: its compiled, pruned slab test gives what testing every box with numpy
gives, to the bit, and a house searches its spawn poses only when they are asked for."""

from __future__ import annotations

import math

import numpy as np
import pytest

from twsb_sim.house import HouseExtras, make_house, random_house, with_extras
from twsb_sim.house.named import plain_house
from twsb_sim.house.spawn import MAX_CLEARANCE_M, Obstacles


def _every_box(obstacles: Obstacles, xy: np.ndarray, yaw: np.ndarray, radius: float):
    """The slab test of every (point, box) pair, no pruning: the reference."""
    heading = np.stack((np.cos(yaw), np.sin(yaw)), -1)
    c, s = np.cos(obstacles.boxes[:, 4]), np.sin(obstacles.boxes[:, 4])
    rel = xy[:, None, :] - obstacles.boxes[None, :, :2]
    local = np.stack((c * rel[..., 0] + s * rel[..., 1], -s * rel[..., 0] + c * rel[..., 1]), -1)
    hx, hy = heading[:, None, 0], heading[:, None, 1]
    d_local = np.stack((c * hx + s * hy, -s * hx + c * hy), -1)
    d_local = np.where(np.abs(d_local) < 1e-12, 1e-12, d_local)
    half = obstacles.boxes[None, :, 2:4] + radius
    t1, t2 = (-half - local) / d_local, (half - local) / d_local
    t_near, t_far = np.minimum(t1, t2).max(axis=-1), np.maximum(t1, t2).min(axis=-1)
    hit = np.where((t_near <= t_far) & (t_far >= 0), np.maximum(t_near, 0), np.inf)
    return hit.min(axis=1, initial=np.inf)


@pytest.mark.parametrize("house", [make_house("house1"), random_house(3), random_house(11)])
def test_pruned_box_clearance_equals_testing_every_box(house):
    obstacles = Obstacles(house.parts())
    rng = np.random.default_rng(0)
    x0, y0, x1, y1 = house.extent_m
    xy = np.column_stack([rng.uniform(x0, x1, 2000), rng.uniform(y0, y1, 2000)])
    # the search's four axis headings, their reverses, and any heading
    yaw = np.concatenate([
        np.repeat([0.0, math.pi / 2, math.pi, -math.pi / 2, 1.5 * math.pi], 200),
        rng.uniform(-math.pi, math.pi, 1000),
    ])  # fmt: skip
    reference = np.minimum(_every_box(obstacles, xy, yaw, 0.25), MAX_CLEARANCE_M)
    obstacles.discs = np.zeros((0, 3))  # the boxes alone
    assert obstacles.clearance_m(xy, yaw, 0.25).tobytes() == reference.tobytes()
    assert np.isfinite(reference).sum() > 1000  # most rays do meet a box


def test_spawn_poses_are_searched_on_first_use_and_see_blocking_extras():
    plain = plain_house("house1")
    house = with_extras(plain, HouseExtras(ceiling_height_m=2.2))
    assert "spawn_poses" not in house.__dict__  # built without the search
    assert house.spawn_poses == plain.spawn_poses  # a lower ceiling blocks nothing new
    assert "spawn_poses" in house.__dict__  # searched once, then kept
    stairs = make_house("basement")  # its staircase blocks the robot
    assert stairs.spawn_poses != plain_house("basement").spawn_poses


def test_a_disc_is_reached_where_the_two_circles_first_touch():
    obstacles = Obstacles([])
    obstacles.discs = np.array([[3.0, 0.5, 0.2]])  # a table leg 3 m ahead, 0.5 m to the left
    xy = np.zeros((3, 2))
    clear = obstacles.clearance_m(xy, np.array([0.0, math.pi, math.pi / 2]), 0.25)
    # |(t, 0) - (3, 0.5)| = 0.45: t = 3 - sqrt(0.45^2 - 0.5^2) has no root, so it misses
    assert clear[0] == MAX_CLEARANCE_M and clear[1] == MAX_CLEARANCE_M
    assert clear[2] == MAX_CLEARANCE_M  # to the left, it passes 3 m short of the leg
    near = obstacles.clearance_m(np.array([[0.0, 0.3]]), np.array([0.0]), 0.25)
    assert near[0] == pytest.approx(3.0 - math.sqrt(0.45**2 - 0.2**2), abs=1e-12)
    inside = obstacles.clearance_m(np.array([[2.9, 0.5]]), np.array([math.pi]), 0.25)
    assert inside[0] == 0.0  # already touching: no room at all
