"""Houses: they compile, every geom is named and classed, seeds are reproducible,
spawn poses are honest, rooms are connected."""

from __future__ import annotations

import math
from collections import deque
from functools import cache

import mujoco
import numpy as np
import pytest

from twsb_sim.house import (
    FURNITURE_KINDS,
    ROBOT_RADIUS_M,
    House,
    SurfaceClass,
    add_house_to_spec,
    house_spec,
    make_house,
    random_house,
    surface_classes,
)

SEEDS = range(20)
NAMES = ["house1", "house2", "basement", "attic", *(f"random_{s}" for s in SEEDS)]
NAMED = ("house1", "house2", "basement", "attic")


@cache
def _house(name: str) -> House:
    return random_house(int(name.split("_")[1])) if name not in NAMED else make_house(name)


@cache
def _model(name: str) -> mujoco.MjModel:
    return house_spec(_house(name)).compile()


def _expected_class(name: str) -> SurfaceClass:
    if name == "floor" or name.startswith("floor_"):
        return SurfaceClass.FLOOR
    if name == "ceiling" or name.startswith("ceiling_"):
        return SurfaceClass.CEILING
    if name.startswith(("wall_", "door_frame_", "stairs_", "shelfboard_")):
        return SurfaceClass.STRUCTURE
    assert name.split("_")[0] in FURNITURE_KINDS, f"unknown geom name {name!r}"
    return SurfaceClass.FURNITURE


@pytest.mark.parametrize("name", NAMES)
def test_house_compiles_and_every_geom_is_named_and_classed(name):
    model = _model(name)
    assert 40 <= model.ngeom <= 250
    names = [model.geom(i).name for i in range(model.ngeom)]
    assert all(names) and len(set(names)) == len(names)
    classes = surface_classes(model)
    assert classes.dtype == np.uint8 and classes.shape == (model.ngeom,)
    for i, geom_name in enumerate(names):
        assert classes[i] == _expected_class(geom_name), geom_name
    assert set(model.geom_group) <= {0, 1, 2}
    assert np.all(model.geom_bodyid == 0)  # static
    assert np.all(model.geom_contype == 1) and np.all(model.geom_conaffinity == 1)
    assert names.count("floor") == 1 and names.count("ceiling") == 1
    assert (classes == SurfaceClass.FURNITURE).sum() >= 10


@pytest.mark.parametrize("name", NAMES)
def test_ceiling_height_and_walls(name):
    house, model = _house(name), _model(name)
    assert 2.0 <= house.ceiling_height_m <= 3.0
    ceiling = model.geom("ceiling")
    assert ceiling.pos[2] - ceiling.size[2] == pytest.approx(house.ceiling_height_m)
    walls = [p for p in house.walls if p.name.startswith("wall_")]
    assert all(min(p.size[:2]) == pytest.approx(house.wall_thickness_m / 2) for p in walls)
    assert house.wall_thickness_m == pytest.approx(0.1)
    for door in house.doorways:
        assert 0.8 <= door.width_m <= 1.0 and 1.9 <= door.height_m <= 2.1
        assert door.height_m <= house.ceiling_height_m - 0.1


def test_robot_geoms_are_classed_robot():
    spec = mujoco.MjSpec()
    add_house_to_spec(spec, make_house("house1"))
    body = spec.worldbody.add_body(name="base", pos=[1, 2, 0.3])
    body.add_freejoint(name="root")
    body.add_geom(name="base_shell", type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.1] * 3, group=3)
    model = spec.compile()
    classes = surface_classes(model)
    assert classes[model.geom("base_shell").id] == SurfaceClass.ROBOT


def test_same_seed_same_house_other_seed_other_house():
    assert random_house(3) == random_house(3)
    assert house_spec(random_house(3)).to_xml() == house_spec(random_house(3)).to_xml()
    xmls = {house_spec(_house(f"random_{s}")).to_xml() for s in SEEDS}
    assert len(xmls) == len(SEEDS)
    assert make_house("house1") != make_house("house2")


def test_unknown_house_name_is_a_clear_error():
    with pytest.raises(ValueError, match=r"^house: expected one of"):
        make_house("house3")


@pytest.mark.parametrize("name", NAMES)
def test_rooms_are_connected_through_open_doorways(name):
    house, model = _house(name), _model(name)
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    neighbours = {room.name: set() for room in house.rooms}
    geomid = np.zeros(1, np.int32)
    for door in house.doorways:
        a, b = door.rooms
        neighbours[a].add(b)
        neighbours[b].add(a)
        # a ray through the middle of the opening at robot height passes the wall line
        normal = np.array([0.0, 1.0, 0.0]) if door.along_x else np.array([1.0, 0.0, 0.0])
        for z in (0.1, 0.5, 1.0, door.height_m - 0.05):
            start = np.array([door.x_m, door.y_m, z]) - 0.3 * normal
            for lateral in (-0.3, 0.0, 0.3):
                offset = lateral * np.array([normal[1], normal[0], 0.0])
                dist = mujoco.mj_ray(model, data, start + offset, normal, None, 1, -1, geomid)
                assert dist < 0 or dist > 0.45, (door.name, z, lateral)
    seen, todo = {house.rooms[0].name}, deque([house.rooms[0].name])
    while todo:
        for other in neighbours[todo.popleft()] - seen:
            seen.add(other)
            todo.append(other)
    assert seen == set(neighbours)


def _obstacle_footprints(model: mujoco.MjModel, data: mujoco.MjData):
    """(centre xy, half extents xy, rotation 2x2, is_cylinder) of every geom that can
    block a robot: not a floor or ceiling surface (it drives over floor features and
    under sloped ceilings), bottom below 1.5 m."""
    rows = []
    for i in range(model.ngeom):
        name = model.geom(i).name
        if name.split("_")[0] in ("floor", "ceiling"):
            continue
        size, z = model.geom_size[i], data.geom_xpos[i, 2]
        is_cyl = model.geom_type[i] == mujoco.mjtGeom.mjGEOM_CYLINDER
        half_z = size[1] if is_cyl else size[2]
        if z - half_z >= 1.5:
            continue
        half = np.array([size[0], size[0]]) if is_cyl else size[:2].copy()
        rows.append((data.geom_xpos[i, :2], half, data.geom_xmat[i].reshape(3, 3)[:2, :2], is_cyl))
    return rows


def _distance_to_footprints(points: np.ndarray, rows) -> np.ndarray:
    """Exact distance from each point (N, 2) to the nearest footprint (rectangle or disc)."""
    best = np.full(points.shape[0], np.inf)
    for centre, half, rot, is_cyl in rows:
        rel = points - centre
        if is_cyl:
            d = np.linalg.norm(rel, axis=1) - half[0]
        else:
            local = np.abs(rel @ rot)
            outside = np.linalg.norm(np.maximum(local - half, 0), axis=1)
            d = np.where(np.all(local <= half, axis=1), -1.0, outside)
        best = np.minimum(best, d)
    return best


@pytest.mark.parametrize(
    "name", ["house1", "house2", "basement", "attic", "random_0", "random_6", "random_7"]
)
def test_spawn_poses_are_free_and_their_clearances_honest(name):
    house, model = _house(name), _model(name)
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    rows = _obstacle_footprints(model, data)
    assert len(house.spawn_poses) >= len(house.rooms)
    for pose in house.spawn_poses:
        assert any(room.contains(pose.x_m, pose.y_m) for room in house.rooms)
        heading = np.array([math.cos(pose.yaw_rad), math.sin(pose.yaw_rad)])
        start = np.array([pose.x_m, pose.y_m])
        steps = np.concatenate([
            np.linspace(0.0, pose.clear_ahead_m, 200)[:, None] * heading,
            -np.linspace(0.0, pose.clear_behind_m, 200)[:, None] * heading,
        ])  # fmt: skip
        gaps = _distance_to_footprints(start + steps, rows)
        assert gaps.min() >= ROBOT_RADIUS_M - 1e-9, pose
        assert pose.clear_ahead_m >= 0.3 and pose.clear_behind_m >= 0.3


@pytest.mark.parametrize("name", NAMED)
def test_named_layouts_have_a_long_free_lane(name):
    best = _house(name).spawn_poses[0]
    assert best.clear_ahead_m >= 6.0
    assert best.clear_ahead_m == max(p.clear_ahead_m for p in _house(name).spawn_poses)


def test_random_houses_have_several_rooms_and_a_long_lane():
    for seed in SEEDS:
        house = _house(f"random_{seed}")
        assert len(house.rooms) >= 3
        assert house.spawn_poses[0].clear_ahead_m >= 6.0
