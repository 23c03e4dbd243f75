"""A run confined to a region: the geoms out of reach leave collision, the frames stay the
same to the bit, and leaving the region is caught."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from twsb_sim.collision_region import (
    CollisionRegion,
    LeftCollisionRegion,
    confine_collisions,
    robot_reach_m,
)
from twsb_sim.house import Room, add_house_to_spec
from twsb_sim.house.floorplan import assemble_house
from twsb_sim.house.furniture import make_furniture
from twsb_sim.movers import LightFurniture, MoverSet
from twsb_sim.robot import RobotConfig, load_robot_spec
from twsb_sim.simulation import Simulation

# a 12 m x 6 m room with a table near the robot's path and a shelf far from it
HOUSE = assemble_house(
    "strip",
    None,
    2.5,
    [Room("room", -6, -3, 6, 3)],
    [],
    [make_furniture("table", 0, 1.2, 1.0, 0.0), make_furniture("shelf", 1, -4.5, -2.6, 0.0)],
)
# the robot drives along +x from the origin, at most 2 m
REGION = CollisionRegion((0.0, 0.0, 0.0), 0.0, (-0.5, -0.5, -1.0), (2.5, 0.5, 0.8))


def _drive(region: CollisionRegion | None, frames: int = 12) -> tuple[Simulation, list]:
    sim = Simulation(HOUSE, start=(0.0, 0.0, 0.0), seed=3, collision_region=region)
    out = []
    for k in range(frames):
        sim.step(0.6 if k < 8 else 0.0, 0.2, 50)
        out.append(sim.frame(k))
    return sim, out


def test_a_confined_run_makes_the_same_frames_as_a_full_one():
    confined, frames = _drive(REGION)
    full, reference = _drive(None)
    out_of_collision = (confined.model.geom_contype == 0) & (full.model.geom_contype == 1)
    assert confined.region_guard is not None and full.region_guard is None
    assert out_of_collision.sum() >= 4  # the far walls, the shelf, the ceiling
    for a, b in zip(frames, reference, strict=True):
        assert np.array_equal(a.scan.ranges, b.scan.ranges)
        assert np.array_equal(a.labels, b.labels)
        assert np.array_equal(a.truth.imu_accel_mps2, b.truth.imu_accel_mps2)
        assert np.array_equal(a.sensors.pose_lidar_in_odom, b.sensors.pose_lidar_in_odom)
    assert np.array_equal(confined.data.qpos, full.data.qpos)


def test_leaving_the_region_is_caught_at_the_step_that_leaves_it():
    small = CollisionRegion((0.0, 0.0, 0.0), 0.0, (-0.2, -0.2, -1.0), (0.2, 0.2, 0.8))
    sim = Simulation(HOUSE, start=(0.0, 0.0, 0.0), collision_region=small)
    with pytest.raises(LeftCollisionRegion, match="outside the collision region"):
        sim.step(0.5, 0.0, 1000)  # 0.5 m/s: the LiDAR passes x = 0.2 m within a second
    assert sim.time_s == pytest.approx(2.0)  # the steps ran; the check came after them


def test_a_start_outside_the_region_is_refused():
    with pytest.raises(LeftCollisionRegion):
        Simulation(HOUSE, start=(3.0, 0.0, 0.0), collision_region=REGION)


def test_geoms_within_the_robots_reach_of_the_region_keep_their_contacts():
    spec = load_robot_spec(RobotConfig())
    add_house_to_spec(spec, HOUSE)
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    reach = robot_reach_m(model, data)
    assert 0.3 < reach < 0.8  # the torso's far corner from the LiDAR, or a wheel's rim
    removed = set(confine_collisions(spec, REGION))
    kept = {g.name for g in spec.worldbody.geoms if g.contype} - {"floor"}
    assert {"wall_0", "ceiling"} <= removed  # the walls 2.5 m and more away, overhead
    assert any(name.startswith("shelf_1") for name in removed)
    # the table's near legs stand 0.5 m beside the region, within the robot's reach
    assert any(name.startswith("table_0") for name in kept)
    assert "floor" not in removed  # a plane never leaves collision


def test_a_robot_that_reaches_a_kept_geom_touches_it():
    region = CollisionRegion((0.0, 0.0, 0.0), math.pi / 2, (-0.5, -0.5, -1.0), (3.0, 0.5, 0.8))
    sim = Simulation(HOUSE, start=(0.0, 0.0, math.pi / 2), collision_region=region)
    touched = set()
    for _ in range(120):  # 6 s at 0.8 m/s towards the wall at y = 3 m, kept in collision
        sim.step(0.8, 0.0, 25)
        contacts = sim.data.contact.geom[: sim.data.ncon].ravel()
        touched |= {sim.model.geom(int(g)).name for g in contacts}
    assert any(name.startswith("wall") for name in touched)


def test_free_furniture_keeps_every_geom_in_collision():
    movers = MoverSet([LightFurniture("pushable_0", "box", 1.5, 0.0)])
    sim = Simulation(HOUSE, start=(0.0, 0.0, 0.0), movers=movers, collision_region=REGION)
    assert sim.region_guard is None
    assert (sim.model.geom_contype[sim.model.geom_bodyid == 0] == 1).all()


@pytest.mark.parametrize(
    ("lower", "upper"), [((0, 0, 0), (1, 1, 0)), ((0, 0, 0), (1, math.inf, 1))]
)
def test_a_region_must_be_a_finite_box(lower, upper):
    with pytest.raises(ValueError, match="collision region"):
        CollisionRegion((0.0, 0.0, 0.0), 0.0, lower, upper)
