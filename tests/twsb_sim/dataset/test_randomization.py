"""Randomization ranges: defaults, TOML overrides, and errors that name the key."""

from __future__ import annotations

import tomllib

import pytest

from twsb_sim.config_errors import ConfigError
from twsb_sim.dataset.randomization import (
    Randomization,
    load_randomization,
    randomization_from_table,
)


def test_printed_defaults_read_back_equal():
    ranges = Randomization()
    assert randomization_from_table(tomllib.loads(ranges.to_toml())) == ranges


def test_defaults_stay_within_the_papers_speeds():
    motion = Randomization().motion
    assert max(motion.cruise_velocity_mps) <= 1.0
    assert max(motion.reverse_velocity_mps) <= 1.0
    assert max(motion.turn_rate_rad_s) <= 0.6


def test_a_file_overrides_only_what_it_names(tmp_path):
    path = tmp_path / "ranges.toml"
    path.write_text("[robot]\nlidar_height_m = 0.3\n[shoves]\nprobability = 0.9\n")
    ranges = load_randomization(path)
    assert ranges.robot.lidar_height_m == (0.3, 0.3)  # a number fixes the value
    assert ranges.shoves.probability == 0.9
    assert ranges.motion == Randomization().motion


@pytest.mark.parametrize(
    ("table", "key"),
    [
        ({"robot": {"lidar_height_m": [0.4, 0.3]}}, "robot.lidar_height_m"),
        ({"robot": {"wheel_radius_m": 0.1}}, "robot.wheel_radius_m"),
        ({"motion": {"cruise_velocity_mps": [0.1, 3.0]}}, "motion.cruise_velocity_mps"),
        ({"motion": {"turn_probability": 0.9, "pause_probability": 0.5}}, "motion"),
        ({"episode": {"duration_s": "long"}}, "episode.duration_s"),
        ({"houses": {}}, "houses"),
        ({"sensors": {"lidar_tilt_deg": [0.0, 20.0]}}, "sensors.lidar_tilt_deg"),
        ({"sensors": {"imu_noise": 2.0}}, "sensors.imu_noise"),
    ],
)
def test_mistakes_name_the_file_and_key(table, key):
    with pytest.raises(ConfigError) as error:
        randomization_from_table(table, source="mine.toml")
    assert error.value.source == "mine.toml"
    assert error.value.key.startswith(key)


def test_missing_file_is_a_config_error(tmp_path):
    with pytest.raises(ConfigError, match="no such ranges file"):
        load_randomization(tmp_path / "absent.toml")
