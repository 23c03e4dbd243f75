"""The generator's environment draws: classes by weight, features on the lane, people in
free space; deterministic, and apart from the house, robot and motion streams."""

from __future__ import annotations

import collections
import dataclasses
import math
import tomllib

import numpy as np
import pytest

from twsb_sim.dataset.environment_ranges import FloorRanges, MoverRanges, RobotClassWeights
from twsb_sim.dataset.episode import draw_episode
from twsb_sim.dataset.randomization import Randomization, randomization_from_table
from twsb_sim.house.spawn import Obstacles
from twsb_sim.robot_classes import ROBOT_CLASSES
from twsb_sim.runner import scenario_world
from twsb_sim.scenario import scenario_from_table

RANGES = Randomization()
DRAWS = [draw_episode(7, k, RANGES) for k in range(30)]  # ~0.2 s each (a house)


def test_the_class_weights_name_every_robot_class():
    assert set(RobotClassWeights().weights()) == set(ROBOT_CLASSES)


def test_draws_are_deterministic():
    again = draw_episode(7, 5, RANGES)
    assert again.scenario_table == DRAWS[5].scenario_table
    assert again.robot_class == DRAWS[5].robot_class


def test_classes_features_ceilings_and_people_come_at_their_rates():
    classes = collections.Counter(d.robot_class for d in DRAWS)
    assert 8 <= classes["lqr"] <= 22 and len(classes) >= 4  # weight 0.5 of 1.0
    rate = lambda key: np.mean([key in d.scenario_table for d in DRAWS])  # noqa: E731
    assert 0.25 <= rate("floor_features") <= 0.75  # 0.5
    assert 0.0 < rate("ceiling") <= 0.35  # 0.15
    assert 0.1 <= rate("people") <= 0.55  # 0.3
    for draw in DRAWS:
        for feature in draw.scenario_table.get("floor_features", []):
            assert -draw.lane.behind_m - 1e-9 <= feature["ahead_m"] <= draw.lane.ahead_m + 1e-9
            assert abs(feature["ahead_m"]) >= 0.4  # never under the robot at its start


def test_a_braking_class_gets_its_balance_table_and_the_rest_keeps_the_robot_draw():
    braking = next(d for d in DRAWS if d.robot_class.endswith("_brake"))
    balance = braking.scenario_table["balance"]
    assert balance["brake_torque_nm"] > 0 and balance.get("kind", "lqr") in ("lqr", "pid")
    soft = next(d for d in DRAWS if d.robot_class == "soft_lqr")
    assert soft.scenario_table["controller"] == {"aggressiveness": 0.05, "torque_weight": 100.0}
    assert "body_mass_kg" in soft.scenario_table["robot"]


def test_people_walk_in_free_space():
    with_people = [d for d in DRAWS if "people" in d.scenario_table][:3]
    assert with_people
    for draw in with_people:
        scenario = scenario_from_table(draw.scenario_table, source="draw")
        house, movers, _ = scenario_world(scenario)
        obstacles = Obstacles(house.parts())
        for person in (m for m in movers.movers if m.name.startswith("person")):
            points = np.array([person.path.at(t)[:2] for t in np.arange(0.0, 40.0, 0.25)])
            assert obstacles.is_free(points, 0.25).all()


def test_changing_the_environment_ranges_leaves_house_robot_and_motion_alone():
    quiet = dataclasses.replace(
        RANGES,
        floor=FloorRanges(probability=0.0),
        movers=MoverRanges(people_probability=0.0, pet_probability=0.0),
    )
    for k in (0, 3, 9):
        a, b = DRAWS[k].scenario_table, draw_episode(7, k, quiet).scenario_table
        for key in ("house", "commands", "shoves", "lidar", "duration_s", "seed"):
            assert a[key] == b[key]
        assert a["robot"] == b["robot"]


@pytest.mark.parametrize(
    ("table", "key"),
    [({"floor": {"probability": 2.0}}, "floor.probability"),
     ({"movers": {"people": [3.0, 1.0]}}, "movers.people"),
     ({"robot_classes": {"lqr": -1.0}}, "robot_classes.lqr"),
     ({"robot_classes": {name: 0.0 for name in ROBOT_CLASSES}}, "robot_classes.lqr"),
     ({"ceiling": {"height_m": 1.0}}, "ceiling.height_m"),
     ({"shoves": {"impulse_fraction": [0.5, 3.0]}}, "shoves.impulse_fraction")],
)  # fmt: skip
def test_ranges_files_name_the_bad_key(table, key):
    with pytest.raises(ValueError) as caught:
        randomization_from_table(table, source="ranges.toml")
    assert str(caught.value).startswith(f"ranges.toml: {key}: ")


def test_the_ranges_print_and_read_back():
    text = RANGES.to_toml()
    assert "[robot_classes]" in text and "[movers]" in text
    assert randomization_from_table(tomllib.loads(text)) == RANGES
    assert math.isclose(RANGES.shoves.impulse_fraction[1], 0.95)
