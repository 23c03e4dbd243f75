"""The stress matrix on a tiny configuration, its files, and its conditions as data-set
families."""

from __future__ import annotations

import json
import math

import pytest

from twsb_sim.cli import main
from twsb_sim.config_errors import ConfigError
from twsb_sim.dataset.episode import draw_episode
from twsb_sim.evaluation.stress import METHODS, StressConfig, run_stress
from twsb_sim.evaluation.stress_conditions import (
    CORE_CONDITIONS,
    STRESS_DIR,
    condition_names,
    condition_ranges,
    register_condition,
)
from twsb_sim.evaluation.stress_report import write_stress_outputs
from twsb_sim.scenario import scenario_from_table

TINY = StressConfig.quick(conditions=("baseline", "people"), duration_s=(3.0, 3.0))


@pytest.fixture(scope="module")
def results():
    return run_stress(TINY, progress=False)


def test_every_cell_has_its_figures_and_the_references_are_exact(results):
    assert list(results["conditions"]) == ["baseline", "people"]
    for row in results["conditions"].values():
        assert set(row["methods"]) == set(METHODS) and row["episodes"] == 1
        truth, none = row["methods"]["truth"], row["methods"]["none"]
        if row["positives"]:
            assert truth["auc"] == 1.0 and truth["recall"] == 1.0 and truth["precision"] == 1.0
            assert none["auc"] == 0.0 and none["recall"] == 0.0
        assert truth["static_removed"] == 0.0 and none["static_removed"] == 0.0
        for cell in row["methods"].values():
            assert 0.0 <= cell["precision"] <= 1.0


def test_dynamic_beams_are_counted_apart(results):
    people = results["conditions"]["people"]
    assert people["labels"]["DYNAMIC"] > 0
    assert results["conditions"]["baseline"]["labels"]["DYNAMIC"] == 0
    assert people["methods"]["truth"]["dynamic_removed"] == 0.0  # not a pitch-variation beam


def test_the_report_heat_map_and_json_are_written(results, tmp_path):
    write_stress_outputs(results, tmp_path, "twsb eval --stress --quick")
    report = (tmp_path / "report.md").read_text()
    assert "| baseline |" in report and "truth labels" in report
    assert (tmp_path / "stress_heatmap.png").stat().st_size > 10_000
    assert json.loads((tmp_path / "results.json").read_text())["methods"] == METHODS


@pytest.mark.parametrize("name", CORE_CONDITIONS)
def test_every_condition_is_a_family_the_generator_draws(name):
    ranges = condition_ranges(name)
    draw = draw_episode(0, 0, ranges)
    scenario_from_table(draw.scenario_table, source=name)  # a valid scenario
    assert (STRESS_DIR / f"{name}.toml").is_file()


def test_conditions_have_what_they_are_named_for():
    people = draw_episode(0, 0, condition_ranges("people")).scenario_table
    assert len(people["people"]) >= 1
    low = draw_episode(0, 0, condition_ranges("low_ceilings")).scenario_table
    assert 2.0 <= low["ceiling"]["height_m"] <= 2.2
    ramps = draw_episode(0, 1, condition_ranges("ramps")).scenario_table
    assert {f["kind"] for f in ramps["floor_features"]} == {"ramp"}
    high = draw_episode(0, 0, condition_ranges("high_lidar")).scenario_table
    assert high["robot"]["lidar_height_m"] >= 0.55
    tilted = draw_episode(0, 0, condition_ranges("baseline")).scenario_table["robot"]
    level = draw_episode(0, 0, condition_ranges("level_mount")).scenario_table["robot"]
    assert math.hypot(tilted["lidar_tilt_pitch_deg"], tilted["lidar_tilt_roll_deg"]) > 0.0
    assert level["lidar_tilt_pitch_deg"] == level["lidar_tilt_roll_deg"] == 0.0


def test_unknown_condition_and_registration_errors(tmp_path, capsys):
    code = main(["eval", "--stress", "--quick", "--conditions", "fog", "--out", str(tmp_path)])
    assert code == 2 and "unknown stress condition 'fog'" in capsys.readouterr().err
    with pytest.raises(ConfigError, match="exists already"):
        register_condition("baseline", STRESS_DIR / "baseline.toml")
    with pytest.raises(ConfigError, match="no such ranges file"):
        register_condition("fog", tmp_path / "fog.toml")
    assert "fog" not in condition_names()
    assert main(["eval", "--quick", "--episodes", "2", "--out", str(tmp_path)]) == 2
    assert "--episodes: only with --stress" in capsys.readouterr().err
