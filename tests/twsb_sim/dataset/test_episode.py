"""Episodes: drawn from (seed, k) alone, simulated reproducibly, falls kept and flagged."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from twsb_sim.dataset.episode import draw_episode, episode_seed_sequence, run_episode
from twsb_sim.dataset.loader import open_dataset
from twsb_sim.dataset.randomization import randomization_from_table
from twsb_sim.dataset.recorder import EpisodeRecorder
from twsb_sim.dataset.schema import SCHEMA
from twsb_sim.labels import BeamLabel
from twsb_sim.robot_classes import ROBOT_CLASSES
from twsb_sim.runner import run_scenario
from twsb_sim.scenario import scenario_from_table

from .conftest import SHORT


def test_episode_seed_is_the_kth_child_of_the_data_set_seed():
    children = np.random.SeedSequence(7).spawn(4)
    assert episode_seed_sequence(7, 3).generate_state(4).tolist() == (
        children[3].generate_state(4).tolist()
    )


def test_draw_depends_on_seed_and_episode_only(short_settings):
    ranges = short_settings.randomization
    first = draw_episode(7, 2, ranges)
    draw_episode(7, 5, ranges)  # drawing another episode in between changes nothing
    assert draw_episode(7, 2, ranges).scenario_table == first.scenario_table
    assert draw_episode(7, 3, ranges).scenario_table != first.scenario_table
    assert draw_episode(8, 2, ranges).scenario_table != first.scenario_table


def test_drawn_table_is_a_valid_scenario(short_settings):
    draw = draw_episode(3, 0, short_settings.randomization)
    scenario = scenario_from_table(draw.scenario_table)
    assert scenario.house.seed is not None or scenario.house.name in ("house1", "house2")
    assert 2.0 <= scenario.duration_s <= 3.0


def test_same_episode_same_rows(short_settings):
    a = run_episode(5, 1, short_settings.randomization)
    b = run_episode(5, 1, short_settings.randomization)
    assert a.table.schema.equals(SCHEMA)
    assert a.table.equals(b.table)
    assert a.summary == b.summary
    assert a.summary["scans"] == a.table.num_rows == round(a.summary["simulated_s"] * 10) + 1
    labels = np.stack(a.table["labels"].to_numpy(zero_copy_only=False))
    counts = a.table["n_occluded"].to_numpy()
    assert (counts == (labels == BeamLabel.OCCLUDED).sum(axis=1)).all()


@pytest.mark.parametrize(
    ("shoves", "reason"),
    [
        (
            {"longitudinal_force_n": 200.0, "max_angular_impulse_n_m_s": 50.0,
             "displacement_m_per_n_s": 0.0, "sideways_fraction": 0.0},
            "|pitch|",
        ),
        (
            {"sideways_fraction": 1.0, "lateral_force_n": 150.0,
             "max_sideways_angular_impulse_n_m_s": 50.0},
            "|roll|",
        ),
    ],
)  # fmt: skip
def test_a_fall_is_kept_cut_and_flagged(shoves, reason):
    table = {
        **SHORT,
        "episode": {"duration_s": 6.0},
        # impulse_fraction 0: the force comes from the force range (cut at the caps); no
        # push mid-turn (its cap blends in the sideways one); the default robot only
        "shoves": {
            "probability": 1.0,
            "duration_s": 0.3,
            "height_m": 0.45,
            "impulse_fraction": 0.0,
            "turning_probability": 0.0,
            **shoves,
        },
        "robot_classes": {name: float(name == "lqr") for name in ROBOT_CLASSES},
    }
    ranges = randomization_from_table(table)
    for episode in range(20):  # the first episode whose plan has a shove
        if draw_episode(1, episode, ranges).scenario_table["shoves"]:
            break
    result = run_episode(1, episode, ranges)
    assert result.summary["fell"]
    assert reason in result.summary["end_reason"]
    assert 0 < result.table.num_rows < 61  # kept, up to the fall
    roll = np.degrees(np.abs(result.table["roll_rad"].to_numpy()))
    assert roll.max() <= 45.0


def test_summary_scenario_reruns_to_the_same_scans(reference):
    episode = open_dataset(reference).episode(4)
    scenario = scenario_from_table(episode.summary["scenario"])
    recorder = EpisodeRecorder()
    run_scenario(scenario, seed=scenario.seed, sinks=[recorder])
    np.testing.assert_array_equal(np.stack(recorder.ranges), episode.ranges)


def test_sensor_draws_stay_in_their_ranges_and_leave_the_rest_as_it_was(short_settings):
    ranges = short_settings.randomization
    tilts = []
    for k in range(8):
        table = draw_episode(3, k, ranges).scenario_table
        robot = table["robot"]
        tilts.append(math.hypot(robot["lidar_tilt_pitch_deg"], robot["lidar_tilt_roll_deg"]))
        assert -0.02 <= robot["lidar_offset_x_m"] <= 0.05
        assert 0.005 <= table["lidar"]["range_noise_fraction"] <= 0.015
        assert abs(table["odometry"]["left_wheel_radius_error"]) <= 0.01
        assert table["imu"]["gyro_noise_density_rad_s_sqrt_hz"] > 0
    assert max(tilts) <= 3.0 + 1e-3 and len(set(tilts)) == 8
    level = dataclasses.replace(
        ranges, sensors=dataclasses.replace(ranges.sensors, lidar_tilt_deg=(0.0, 0.0))
    )
    a, b = draw_episode(3, 1, ranges).scenario_table, draw_episode(3, 1, level).scenario_table
    assert b["robot"]["lidar_tilt_pitch_deg"] == 0.0
    for key in ("house", "commands", "shoves", "controller", "seed"):
        assert a[key] == b[key]
    assert a["robot"]["body_mass_kg"] == b["robot"]["body_mass_kg"]
