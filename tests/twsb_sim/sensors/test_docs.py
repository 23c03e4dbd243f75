"""docs/sensors.md cannot drift from the code: its TOML blocks load, its numbers hold."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

import pytest

from twsb_sim.dataset.randomization import Randomization
from twsb_sim.lidar import LidarConfig
from twsb_sim.scenario import scenario_from_table

PAGE = (Path(__file__).resolve().parents[3] / "docs" / "sensors.md").read_text(encoding="utf-8")
TOML_BLOCKS = re.findall(r"```toml\n(.*?)```", PAGE, flags=re.DOTALL)


@pytest.mark.parametrize("block", TOML_BLOCKS, ids=[f"block{i}" for i in range(len(TOML_BLOCKS))])
def test_every_toml_block_is_a_valid_scenario_table(block):
    table = {"duration_s": 1.0, **tomllib.loads(block)}
    scenario_from_table(table, source="docs/sensors.md")


def test_the_ideal_block_switches_every_lidar_error_off():
    ideal_block = next(b for b in TOML_BLOCKS if "dropout_probability = 0.0" in b)
    scenario = scenario_from_table({"duration_s": 1.0, **tomllib.loads(ideal_block)})
    assert scenario.lidar == LidarConfig.ideal()
    robot = scenario.robot
    assert (robot.lidar_offset_x_m, robot.lidar_tilt_pitch_deg, robot.lidar_tilt_roll_deg) == (
        0.0, 0.0, 0.0,
    )  # fmt: skip


def _default_cell(field: str) -> float:
    """The number in the default column of the LiDAR table's row for ``field``."""
    for line in PAGE.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 5 and cells[1] == f"`{field}`":
            return float(re.match(r"[-+]?[0-9.]+", cells[2]).group())
    raise AssertionError(f"{field}: not in the LiDAR table")


@pytest.mark.parametrize(
    "field",
    ["range_min_m", "range_max_m", "range_noise_std_m", "range_noise_fraction",
     "range_resolution_m", "dropout_probability", "grazing_dropout_start_deg"],
)  # fmt: skip
def test_the_lidar_table_gives_the_codes_defaults(field):
    assert _default_cell(field) == pytest.approx(getattr(LidarConfig(), field))


def test_the_generate_ranges_named_on_the_page_are_the_codes():
    assert Randomization().sensors.lidar_tilt_deg == (0.0, 3.0) and "(0-3°" in PAGE
