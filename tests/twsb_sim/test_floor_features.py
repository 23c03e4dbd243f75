"""Floor features against closed-form geometry and physics: profiles, friction, and how a
threshold tips the robot."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from twsb_sim.house import FloorFeature, HouseExtras, Room, house_spec, with_extras
from twsb_sim.house.floor_features import CARPET_FRICTION, floor_feature_parts
from twsb_sim.house.floorplan import assemble_house
from twsb_sim.house.mjspec import OWN_FRICTION_CONDIM, OWN_FRICTION_PRIORITY
from twsb_sim.simulation import Simulation

TRACK_WIDTH_M = 0.30  # m, between the wheels' mid-planes (models/README.md)


def _room(features: tuple[FloorFeature, ...] = ()):
    plain = assemble_house("strip", None, 2.5, [Room("room", -6, -3, 6, 3)], [], [])
    return with_extras(plain, HouseExtras(floor_features=features))


def _robot_at(features: tuple[FloorFeature, ...], x_m: float = 0.0) -> Simulation:
    """The default robot at (x_m, 0), facing +x."""
    sim = Simulation(_room(features))
    sim.reset((x_m, 0.0, 0.0))
    return sim


def _height_profile(feature: FloorFeature, along: np.ndarray) -> np.ndarray:
    """Surface height under vertical rays along the feature's crossing direction."""
    model = house_spec(_room((feature,))).compile()
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    geom = np.zeros(1, np.int32)
    heights = []
    for a in along:
        start = np.array([a, 0.0, 1.0])
        dist = mujoco.mj_ray(model, data, start, np.array([0.0, 0.0, -1.0]), None, 1, -1, geom)
        heights.append(1.0 - dist)
    return np.array(heights)


def test_threshold_profile_rises_at_its_bevel_angle_to_its_height():
    h, top, bevel = 0.02, 0.08, 30.0
    feature = FloorFeature("threshold", 0.0, 0.0, 0.0, h, 1.0, top, bevel)
    run = h / math.tan(math.radians(bevel))
    along = np.linspace(-top / 2 - run - 0.02, top / 2 + run + 0.02, 41)
    expected = np.clip(np.minimum(along + top / 2 + run, top / 2 + run - along), 0, run)
    expected *= math.tan(math.radians(bevel))
    np.testing.assert_allclose(_height_profile(feature, along), np.minimum(expected, h), atol=1e-6)
    assert feature.footprint_length_m == pytest.approx(top + 2 * run)


def test_ramp_profile_and_a_crossing_direction_along_y():
    h, top, slope = 0.06, 0.3, 8.0
    feature = FloorFeature("ramp", 0.0, 0.0, math.pi / 2, h, 1.0, top, slope)
    run = h / math.tan(math.radians(slope))
    model = house_spec(_room((feature,))).compile()
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    geom = np.zeros(1, np.int32)
    for along, expected in ((0.0, h), (-top / 2 - run / 2, h / 2), (top / 2 + run / 4, 0.75 * h)):
        dist = mujoco.mj_ray(model, data, np.array([0.0, along, 1.0]), np.array([0, 0, -1.0]),
                             None, 1, -1, geom)  # fmt: skip
        assert 1.0 - dist == pytest.approx(expected, abs=1e-6)


def test_cable_lies_on_the_floor_across_the_path():
    cable = FloorFeature("cable", 1.0, 0.5, 0.0, 0.016, 2.0)
    (part,) = floor_feature_parts(cable, 0)
    assert part.z_min_m == pytest.approx(0.0, abs=1e-9)
    assert part.z_max_m == pytest.approx(0.016)
    assert not part.blocking and part.name == "floor_cable_0"


def test_rug_has_its_own_friction_which_sets_the_wheel_contact():
    rug = FloorFeature("rug", 0.0, 0.0, 0.0, 0.01, 2.0, 2.0)
    sim = _robot_at((rug,))
    geom = sim.model.geom("floor_rug_0")
    assert geom.priority[0] == OWN_FRICTION_PRIORITY and geom.condim[0] == OWN_FRICTION_CONDIM
    np.testing.assert_allclose(geom.friction, CARPET_FRICTION)
    sim.step(0.0, 0.0, 250)
    rug_id = geom.id
    on_rug = [c for c in sim.data.contact[: sim.data.ncon] if rug_id in (c.geom1, c.geom2)]
    assert len(on_rug) == 2  # both wheels stand on the rug
    for contact in on_rug:
        assert contact.dim == OWN_FRICTION_CONDIM
        assert contact.friction[0] == pytest.approx(CARPET_FRICTION[0])


def test_a_strip_under_one_wheel_rolls_the_robot_by_atan_height_over_track():
    """Standing with its left wheel on a 2 cm strip, the robot rolls left side up by
    atan(0.02 / 0.30) (REP-103: roll positive = left side up)."""
    h = 0.02
    strip = FloorFeature("rug", 0.0, TRACK_WIDTH_M / 2, 0.0, h, 0.12, 0.6)  # under the left wheel
    sim = _robot_at((strip,))
    sim.step(0.0, 0.0, 1000)
    roll = sim.handles.read_balance_state(sim.data).roll_rad
    assert roll == pytest.approx(math.atan2(h, TRACK_WIDTH_M), abs=math.radians(0.3))


def test_driving_onto_a_threshold_tips_the_body_nose_down_first():
    """The bevel slows the wheels; the body, carried on, pitches forward (positive)."""
    threshold = FloorFeature("threshold", 1.0, 0.0, 0.0, 0.025, 1.0, 0.08, 30.0)
    sim = _robot_at((threshold,), x_m=-2.0)
    sim.step(0.5, 0.0, 2500)  # at 0.5 m/s and level well before the threshold
    assert abs(sim.pitch_rad()) < math.radians(0.5)
    assert sim.truth().position_base_in_world[0] < 0.8  # the bevel's foot is at ~0.92 m
    pitch = []
    for _ in range(300):  # 3 s: over the threshold
        sim.step(0.5, 0.0, 5)
        pitch.append(sim.pitch_rad())
    pitch = np.degrees(pitch)
    tipped = np.abs(pitch) > 1.0
    assert tipped.any() and pitch[np.argmax(tipped)] > 1.0
    assert sim.truth().position_base_in_world[0] > 1.3  # it got over
