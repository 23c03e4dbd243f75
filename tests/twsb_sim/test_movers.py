"""People, pets, doors and light furniture: where they are when, and what the LiDAR calls
their beams."""

from __future__ import annotations

import math

import numpy as np
import pytest

from twsb_sim.house import Doorway
from twsb_sim.labels import BeamLabel
from twsb_sim.movers import Person, SwingingDoor, WalkPath
from twsb_sim.runner import run_scenario
from twsb_sim.scenario import scenario_from_table
from twsb_sim.sinks import NullSink


class Keep(NullSink):
    def __init__(self) -> None:
        self.frames = []

    def on_frame(self, frame, filter_result):
        self.frames.append(frame)


def _frames(table: dict, seed: int = 3) -> list:
    keep = Keep()
    run_scenario(scenario_from_table(table, source="test"), seed=seed, sinks=[keep])
    return keep.frames


def test_walk_path_walks_stands_turns_and_comes_back():
    path = WalkPath(((0.0, 0.0), (2.0, 0.0)), speed_mps=1.0, start_s=1.0, stand_s=2.0)
    assert path.at(0.5)[:2] == (0.0, 0.0) and path.at(0.5).speed_mps == 0.0
    state = path.at(2.0)  # 1 s of walking
    assert (state.x_m, state.y_m, state.walked_m, state.speed_mps) == pytest.approx((1, 0, 1, 1))
    standing = path.at(3.2)  # at the far end, turning round at 2 rad/s
    assert standing.x_m == pytest.approx(2.0) and standing.speed_mps == 0.0
    assert abs(math.remainder(standing.heading_rad, math.tau)) == pytest.approx(0.4, abs=1e-9)
    assert math.cos(path.at(4.9).heading_rad) == pytest.approx(-1.0)  # turned round
    back = path.at(5.5)  # 0.5 s on the way back
    assert back.x_m == pytest.approx(1.5) and math.cos(back.heading_rad) == pytest.approx(-1.0)
    assert path.cycle_s == pytest.approx(8.0) and path.at(1.0 + 8.0 + 1.0).x_m == pytest.approx(1.0)
    quick = WalkPath(((0.0, 0.0), (2.0, 0.0)), speed_mps=1.0)  # no stand: as long as the turn
    assert quick.cycle_s == pytest.approx(4.0 + 2 * math.pi / 2.0)
    one_way = WalkPath(((0.0, 0.0), (1.0, 1.0)), speed_mps=2.0, back_and_forth=False)
    assert one_way.at(100.0)[:2] == pytest.approx((1.0, 1.0))


def test_a_person_s_legs_are_dynamic_and_move_at_the_scripted_speed():
    """A person walks across 3 m ahead of a robot standing still: the beams on the legs
    are DYNAMIC, and their mean moves along the path at the walking speed."""
    speed = 1.1
    frames = _frames({
        "duration_s": 3.0, "house": {"name": "house1", "spawn": 3},
        "people": [{"waypoints": [[3.0, 2.0], [3.0, -2.0]], "speed_mps": speed,
                    "back_and_forth": False}],
    })  # fmt: skip
    times, lateral = [], []
    for frame in frames[2:]:
        dynamic = frame.labels == BeamLabel.DYNAMIC
        if dynamic.sum() < 3:
            continue
        points = frame.hit_points_world[dynamic]
        assert np.all(points[:, 2] < 0.3)  # the scan plane at 0.25 m meets the legs
        times.append(frame.stamp_s)
        lateral.append(points[:, 1].mean())
    assert len(times) >= 20
    slope = np.polyfit(times, lateral, 1)[0]
    assert slope == pytest.approx(-speed, rel=0.1)


def test_a_swinging_door_eases_open_and_its_free_end_sweeps_a_quarter_circle():
    doorway = Doorway("door_0", ("a", "b"), 2.0, 4.0, True, 0.9, 2.0)
    door = SwingingDoor("door_leaf_0", doorway, True, True, 90.0, False, (1.0, 5.0), 2.0)
    assert door.opening(0.5) == 0.0 and door.opening(2.0) == pytest.approx(0.5)
    assert door.opening(4.0) == 1.0 and door.opening(6.0) == pytest.approx(0.5)
    assert door.opening(8.0) == pytest.approx(0.0, abs=1e-12)
    (hinge,), (quat,) = door.poses(4.0)
    assert hinge[:2] == pytest.approx((1.55, 4.0))  # the opening's west end
    yaw = 2 * math.atan2(quat[3], quat[0])
    assert yaw == pytest.approx(math.pi / 2)  # opened towards +y


def test_door_leaves_pets_and_pushed_furniture_are_dynamic():
    frames = _frames({
        "duration_s": 6.0, "house": {"name": "house1", "spawn": 0},
        "commands": [{"t_s": 0.5, "velocity_mps": 0.6, "ramp_s": 0.5}],
        "doors": [{"doorway": "door_0", "opens_positive": False, "toggle_times_s": [0.5]}],
        "pets": [{"waypoints": [[2.0, -1.0], [2.0, 1.0]], "speed_mps": 0.8}],
        "light_furniture": [{"kind": "box", "ahead_m": 2.0, "mass_kg": 2.0}],
    })  # fmt: skip
    geoms = {}
    for frame in frames:
        for label, geom in zip(frame.labels, frame.geom_ids, strict=True):
            if label == BeamLabel.DYNAMIC:
                geoms[int(geom)] = True
    assert len(geoms) >= 3  # the leaf, the pet's parts, the box
    start = frames[0].hit_points_world
    assert np.isfinite(start).any()


def test_a_bumped_box_moves_and_tips_the_robot():
    """Ramped up gently to 0.6 m/s, the robot then meets a 5 kg box: it pushes it along,
    and the bump tips the body far more than the gentle start did."""
    from twsb_sim.runner import simulation_for

    table = {
        "duration_s": 8.0, "house": {"name": "house1", "spawn": 0},
        "light_furniture": [{"kind": "box", "ahead_m": 2.0, "mass_kg": 5.0}],
    }  # fmt: skip
    sim = simulation_for(scenario_from_table(table, source="test"), 0)
    box_start = sim.data.body("pushable_0").xpos.copy()
    ramp = 0.6 * np.minimum(np.arange(1500) / 1000.0, 1.0)  # 2 s to 0.6 m/s, then 1 s on
    sim.run_commands(ramp, np.zeros(1500))
    start_peak, sim.max_abs_pitch_rad = sim.max_abs_pitch_rad, 0.0
    sim.step(0.6, 0.0, 2000)  # it reaches the box (1.55 m from its front) after ~2.5 s
    moved = np.linalg.norm(sim.data.body("pushable_0").xpos[:2] - box_start[:2])
    assert moved > 0.15
    assert sim.max_abs_pitch_rad > 2 * start_peak and math.degrees(sim.max_abs_pitch_rad) > 6.0


def test_a_person_standing_still_poses_the_same_every_time():
    path = WalkPath(((1.0, 1.0), (2.0, 1.0)), 1.0, start_s=10.0)
    person = Person("person_0", path)
    a, b = person.poses(3.0), person.poses(3.0)
    assert np.array_equal(a[0], b[0]) and np.array_equal(a[1], b[1])
    assert a[0][0] == pytest.approx((1.0, 1.0, 0.0))


def test_static_geoms_are_posed_once_and_nothing_ever_sleeps():
    """The model skips the house's static geom poses per step (MuJoCo's sleeping), yet
    the robot and a pushable box standing still stay awake, and the run is the same to
    the bit as with sleeping off."""
    import copy

    import mujoco

    from twsb_sim.runner import simulation_for

    table = {
        "duration_s": 4.0, "house": {"name": "house1", "spawn": 0},
        "light_furniture": [{"kind": "box", "ahead_m": 2.0, "mass_kg": 5.0}],
        "pets": [{"waypoints": [[2.0, -1.0], [2.0, 1.0]], "speed_mps": 0.8}],
    }  # fmt: skip
    sim = simulation_for(scenario_from_table(table, source="test"), 0)
    model, data = sim.model, sim.data
    assert model.opt.enableflags & mujoco.mjtEnableBit.mjENBL_SLEEP
    plain_model = copy.copy(model)
    plain_model.opt.enableflags &= ~int(mujoco.mjtEnableBit.mjENBL_SLEEP)
    plain = mujoco.MjData(plain_model)
    mujoco.mj_copyData(plain, plain_model, data)
    for k in range(1500):  # 3 s standing still: long enough for anything allowed to sleep
        sim.step(0.0, 0.0)
        plain.ctrl[:] = data.ctrl
        mujoco.mj_step(plain_model, plain)
        if k % 250 == 0:  # the pet walks: its geoms follow, as the LiDAR needs
            for d in (data, plain):
                sim.movers.pose(d, float(d.time))
            mujoco.mj_forward(model, data)
            mujoco.mj_forward(plain_model, plain)
            np.testing.assert_array_equal(data.geom_xpos, plain.geom_xpos)
    assert (data.tree_asleep < 0).all()  # negative: awake
    np.testing.assert_array_equal(data.qpos, plain.qpos)
    np.testing.assert_array_equal(data.qvel, plain.qvel)
    np.testing.assert_array_equal(data.geom_xmat, plain.geom_xmat)
