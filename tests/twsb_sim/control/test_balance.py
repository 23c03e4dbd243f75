"""Balance controllers and the stop brake: which way a hard stop tips the body, every robot
class stands, the configuration is checked."""

from __future__ import annotations

import math

import numpy as np
import pytest

from twsb_sim.control.balance import BalanceConfig
from twsb_sim.house import Room
from twsb_sim.house.floorplan import assemble_house
from twsb_sim.robot_classes import ROBOT_CLASSES, draw_class_tables, robot_class
from twsb_sim.scenario import scenario_from_table
from twsb_sim.simulation import Simulation

ARENA = assemble_house("arena", None, 3.0, [Room("arena", -15, -5, 15, 5)], [], [])


def _sim(**tables) -> Simulation:
    scenario = scenario_from_table({"duration_s": 1.0, **tables}, source="test")
    sim = Simulation(ARENA, scenario.robot, controller=scenario.controller,
                     balance=scenario.balance)  # fmt: skip
    sim.reset((-10.0, 0.0, 0.0))
    return sim


def _hard_stop_pitch_deg(sim: Simulation) -> np.ndarray:
    """Pitch every 10 ms over 2 s after a step from 1 m/s to rest."""
    velocity = np.minimum(np.arange(2000) / 750.0, 1.0)  # 1.5 s ramp, 2.5 s cruise
    sim.run_commands(velocity, np.zeros(2000))
    pitch = []
    for _ in range(200):
        sim.step(0.0, 0.0, 5)
        pitch.append(math.degrees(sim.pitch_rad()))
    return np.array(pitch)


def _first_swing(pitch_deg: np.ndarray, above_deg: float = 2.0) -> float:
    return float(pitch_deg[np.argmax(np.abs(pitch_deg) > above_deg)])


def test_the_lqr_leans_back_on_a_hard_stop():
    pitch = _hard_stop_pitch_deg(_sim())
    assert _first_swing(pitch) < -2.0 and pitch.max() < 1.0


@pytest.mark.parametrize("kind", ["lqr", "pid"])
def test_a_stop_brake_tips_the_body_nose_down_first(kind):
    sim = _sim(balance={"kind": kind, "brake_torque_nm": 3.0, "brake_s": 0.12})
    pitch = _hard_stop_pitch_deg(sim)
    assert _first_swing(pitch) > 2.0
    assert pitch.max() > 10.0  # nose down into the floor ahead
    assert not sim.has_fallen() and abs(pitch[-1]) < 0.3 * pitch.max()  # then caught


def test_the_pid_balances_and_tracks_a_velocity():
    sim = _sim(balance={"kind": "pid"})
    sim.step(0.5, 0.0, 5000)  # hand-set gains: it overshoots and settles within 10 s
    state = sim.handles.read_balance_state(sim.data)
    assert not sim.has_fallen()
    assert state.forward_velocity_mps == pytest.approx(0.5, abs=0.05)
    sim.step(0.0, 0.3, 2000)
    assert sim.handles.read_balance_state(sim.data).yaw_rate_rad_s == pytest.approx(0.3, abs=0.03)


@pytest.mark.parametrize("name", sorted(ROBOT_CLASSES))
def test_every_robot_class_stands_and_drives(name):
    sim = _sim(**robot_class(name).tables)
    sim.step(0.6, 0.0, 1500)
    sim.step(0.0, 0.0, 1000)
    assert not sim.has_fallen() and sim.mujoco_warnings() == {}


def test_a_braking_class_draws_its_brake_within_its_ranges():
    rng = np.random.default_rng(0)
    tables = draw_class_tables(rng, "pid_brake")
    assert tables["balance"]["kind"] == "pid"
    assert 2.0 <= tables["balance"]["brake_torque_nm"] <= 3.0
    assert 0.06 <= tables["balance"]["brake_s"] <= 0.14
    assert draw_class_tables(rng, "lqr") == {}
    with pytest.raises(ValueError, match=r"^robot_class: expected one of"):
        robot_class("mpc")


@pytest.mark.parametrize(
    ("field", "value"),
    [("kind", "mpc"), ("brake_torque_nm", -1.0), ("brake_s", 0.0), ("pid_max_lean_rad", 2.0),
     ("pid_kp_nm_per_rad", float("nan"))],
)  # fmt: skip
def test_balance_config_names_the_field_it_refuses(field, value):
    with pytest.raises(ValueError, match=rf"^{field}: "):
        BalanceConfig(**{field: value})
