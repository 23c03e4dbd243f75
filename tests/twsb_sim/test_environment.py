"""Scenario files' environment tables: every key read and checked, every mistake one line
naming the file and the key; relative placements land where they say."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from twsb_sim.cli import main
from twsb_sim.config_errors import ConfigError
from twsb_sim.runner import scenario_world
from twsb_sim.scenario import load_scenario

HEAD = 'duration_s = 2.0\n[house]\nname = "house1"\nspawn = 3\n'


def _error(tmp_path: Path, body: str) -> str:
    path = tmp_path / "bad.toml"
    path.write_text(HEAD + body)
    with pytest.raises(ConfigError) as caught:
        scenario_world(load_scenario(path))
    message = str(caught.value)
    assert message.startswith(f"{path}: ") and "\n" not in message
    return message


BAD = [
    ("[ceiling]\nheight_m = 1.0\n", "ceiling.height_m"),
    ("[ceiling]\nlow = 2.0\n", "ceiling.low"),
    ('[[floor_features]]\nkind = "carpet"\nahead_m = 1.0\n', "floor_features[0].kind"),
    ('[[floor_features]]\nkind = "rug"\n', "floor_features[0].ahead_m"),
    ("[[floor_features]]\nahead_m = 1.0\nat_m = [1.0, 2.0]\n", "floor_features[0].ahead_m"),
    ("[[floor_features]]\nahead_m = 1.0\nheight_m = 0.5\n", "floor_features[0].height_m"),
    ("[[floor_features]]\nahead_m = 1.0\nslope_deg = 80.0\n", "floor_features[0].slope_deg"),
    ("[[floor_features]]\nahead_m = 1.0\nfriction = [1.0]\n", "floor_features[0].friction"),
    ('[[floor_features]]\nahead_m = 1.0\nlength_m = "long"\n', "floor_features[0].length_m"),
    ('[[attic_slopes]]\nside = "north"\n', "attic_slopes[0].room"),
    ('[[attic_slopes]]\nroom = "attic"\n', "attic_slopes[0].room"),
    ('[[attic_slopes]]\nroom = "living"\nside = "up"\n', "attic_slopes[0].side"),
    ('[[attic_slopes]]\nroom = "living"\npitch_deg = 5.0\n', "attic_slopes[0].pitch_deg"),
    ('[[staircases]]\nroom = "living"\nwidth_m = 3.0\n', "staircases[0].width_m"),
    ('[[wall_shelves]]\nroom = "living"\nheight_m = 3.0\n', "wall_shelves[0].height_m"),
    ("[[people]]\nspeed_mps = 1.0\n", "people[0].waypoints"),
    ("[[people]]\nwaypoints = [[1.0, 2.0]]\n", "people[0].waypoints"),
    ("[[people]]\nwaypoints = [[0, 0], [1, 1]]\nspeed_mps = 9.0\n", "people[0].speed_mps"),
    ("[[people]]\nwaypoints = [[0, 0], [1, 1]]\nheight_m = 3.0\n", "people[0].height_m"),
    ('[[people]]\nwaypoints = [[0, 0], [1, 1]]\nframe = "robot"\n', "people[0].frame"),
    ("[[people]]\nwaypoints = [[0, 0], [1, 1]]\nstand_s = -1.0\n", "people[0].stand_s"),
    ("[[people]]\nwaypoints = [[0, 0], [1, 1]]\nwalk = true\n", "people[0].walk"),
    (
        "[[pets]]\nwaypoints = [[0, 0], [1, 1]]\nshoulder_height_m = 2.0\n",
        "pets[0].shoulder_height_m",
    ),
    ("[[doors]]\nopen_deg = 90.0\n", "doors[0].doorway"),
    ('[[doors]]\ndoorway = "door_9"\n', "doors[0].doorway"),
    ('[[doors]]\ndoorway = "door_1"\ntoggle_times_s = ["soon"]\n', "doors[0].toggle_times_s[0]"),
    ('[[doors]]\ndoorway = "door_1"\ntoggle_times_s = [3.0, 1.0]\n', "doors[0].toggle_times_s"),
    ('[[doors]]\ndoorway = "door_1"\nopen_deg = 200.0\n', "doors[0].open_deg"),
    ('[[light_furniture]]\nkind = "sofa"\nahead_m = 1.0\n', "light_furniture[0].kind"),
    ("[[light_furniture]]\nahead_m = 1.0\nmass_kg = 100.0\n", "light_furniture[0].mass_kg"),
    ("[[light_furniture]]\nahead_m = 1.0\nsize_m = [0.3, 0.3]\n", "light_furniture[0].size_m"),
    ("[people]\nspeed_mps = 1.0\n", "people"),
    ('[balance]\nkind = "mpc"\n', "balance.kind"),
    ("[balance]\nbrake_torque_nm = -1.0\n", "balance.brake_torque_nm"),
    ("[balance]\nbrake_s = 5.0\n", "balance.brake_s"),
    ("[balance]\npid_kp_nm_per_rad = 0.0\n", "balance.pid_kp_nm_per_rad"),
    ("[balance]\ngain = 1.0\n", "balance.gain"),
]


@pytest.mark.parametrize(("body", "key"), BAD, ids=[key for _, key in BAD])
def test_a_bad_environment_key_is_one_line_naming_file_and_key(tmp_path, body, key):
    assert f": {key}: " in _error(tmp_path, body)


def test_the_command_line_prints_the_error_and_exits_with_status_2(tmp_path, capsys):
    path = tmp_path / "bad.toml"
    path.write_text(HEAD + "[[people]]\nwaypoints = [[0, 0], [1, 1]]\nspeed_mps = 9.0\n")
    assert main(["run", str(path), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("twsb: error: ") and "people[0].speed_mps" in err and "\n" not in err


def test_relative_placements_land_ahead_of_the_start_pose(tmp_path):
    path = tmp_path / "ok.toml"
    path.write_text(
        HEAD
        + """
[ceiling]
height_m = 2.1
[[floor_features]]
kind = "threshold"
ahead_m = 2.0
lateral_m = 0.5
[[people]]
waypoints = [[3.0, -1.0], [3.0, 1.0]]
[[light_furniture]]
kind = "box"
at_m = [7.0, 1.0]
yaw_deg = 30.0
"""
    )
    house, movers, (x0, y0, yaw) = scenario_world(load_scenario(path))
    assert house.ceiling_height_m == 2.1
    # the scenario's features come after the house's own (house1's thresholds, rugs, cable)
    top = [p for p in house.features if p.name.endswith("_top")][-1]
    assert top.name == "floor_threshold_7_top"
    c, s = math.cos(yaw), math.sin(yaw)
    assert top.pos[:2] == pytest.approx((x0 + 2.0 * c - 0.5 * s, y0 + 2.0 * s + 0.5 * c))
    person, box = movers.movers
    start = person.path.at(0.0)
    assert (start.x_m, start.y_m) == pytest.approx((x0 + 3.0 * c + s, y0 + 3.0 * s - c))
    assert (box.x_m, box.y_m, box.yaw_rad) == pytest.approx((7.0, 1.0, math.radians(30.0)))


def test_a_scenario_without_environment_builds_the_house_it_always_did():
    house, movers, _ = scenario_world(load_scenario(Path("scenarios/hard_stop.toml")))
    assert not movers and house.name == "house1"
