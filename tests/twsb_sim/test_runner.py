"""The scenario loop: frames, determinism, the paper's hard-stop signature, falls, sinks."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from twsb_sim.labels import BeamLabel, is_pitch_variation
from twsb_sim.runner import run_scenario, simulation_for
from twsb_sim.scenario import Scenario, load_scenario, scenario_from_table
from twsb_sim.sinks import NullSink
from twsb_sim.timeline import CommandPoint


class Collect(NullSink):
    """Keeps frames and events for the test to inspect."""

    def __init__(self) -> None:
        self.frames, self.events, self.summary = [], [], None

    def on_frame(self, frame, filter_result):
        self.frames.append(frame)

    def on_event(self, t_s, text):
        self.events.append((t_s, text))

    def close(self, summary):
        self.summary = summary


def short(scenario: Scenario, duration_s: float) -> Scenario:
    keep = tuple(c for c in scenario.commands if c.t_s + c.ramp_s <= duration_s)
    shoves = tuple(s for s in scenario.shoves if s.end_s <= duration_s)
    return dataclasses.replace(scenario, duration_s=duration_s, commands=keep, shoves=shoves)


@pytest.fixture(scope="module")
def hard_stop_run():
    sink = Collect()
    summary = run_scenario(load_scenario("scenarios/hard_stop.toml"), seed=3, sinks=[sink])
    return summary, sink


def test_frames_at_ten_hertz_with_one_label_per_beam(hard_stop_run):
    summary, sink = hard_stop_run
    assert summary.frames == len(sink.frames) == 81  # 0 .. 8 s inclusive
    stamps = np.array([f.stamp_s for f in sink.frames])
    np.testing.assert_allclose(np.diff(stamps), 0.1, atol=1e-9)
    for frame in sink.frames[:3]:
        assert len(frame.scan) == 720 and frame.labels.shape == (720,)


def test_hard_stop_pitches_several_degrees_and_floor_shows_in_the_papers_band(hard_stop_run):
    summary, sink = hard_stop_run
    assert not summary.fell
    assert summary.max_abs_pitch_deg > 5.0
    after_stop = [f for f in sink.frames if f.stamp_s >= 4.0]
    pv_points = []
    for frame in after_stop:
        pv = is_pitch_variation(frame.labels) & np.isfinite(frame.scan.ranges)
        if pv.any():
            angles = frame.scan.angles()[pv]
            ranges = frame.scan.ranges[pv]
            pv_points.append((angles, ranges, frame.labels[pv]))
    assert pv_points, "a hard stop from 1 m/s must make the LiDAR see the floor or ceiling"
    angles = np.concatenate([a for a, _, _ in pv_points])
    ranges = np.concatenate([r for _, r, _ in pv_points])
    labels = np.concatenate([lb for _, _, lb in pv_points])
    assert np.isin(labels, [BeamLabel.FLOOR, BeamLabel.CEILING]).mean() > 0.9
    # mostly in front of (|angle| < 60 deg) or behind (|angle| > 120 deg) the robot; the
    # floor line runs across the robot's path, so its ends reach out to the sides
    assert (np.abs(np.cos(angles)) > 0.5).mean() > 0.75
    in_band = (ranges >= 0.3) & (ranges <= 2.0)
    assert in_band.mean() > 0.5


def test_events_name_the_phases(hard_stop_run):
    _, sink = hard_stop_run
    texts = [text for _, text in sink.events]
    assert "phase: accelerate" in texts and "phase: hard stop" in texts


def test_same_seed_gives_identical_frames_and_another_seed_other_noise():
    scenario = short(load_scenario("scenarios/hard_stop.toml"), 1.0)
    runs = []
    for seed in (5, 5, 6):
        sink = Collect()
        run_scenario(scenario, seed=seed, sinks=[sink])
        runs.append(sink.frames)
    same = all(
        np.array_equal(a.scan.ranges, b.scan.ranges, equal_nan=True)
        and np.array_equal(a.labels, b.labels)
        for a, b in zip(runs[0], runs[1], strict=True)
    )
    assert same
    assert not np.array_equal(runs[0][-1].scan.ranges, runs[2][-1].scan.ranges, equal_nan=True)


def test_a_fall_ends_the_run_with_a_reason():
    scenario = scenario_from_table(
        {
            "duration_s": 6.0,
            "shoves": [
                {
                    "t_s": 1.0,
                    "force_n": [300.0, 0.0, 0.0],
                    "duration_s": 0.5,
                    "point_m": [0, 0, 0.45],
                }
            ],
        }
    )
    sink = Collect()
    summary = run_scenario(scenario, seed=0, sinks=[sink])
    assert summary.fell
    assert summary.end_reason.startswith("fell: |pitch|")
    read_deg = float(summary.end_reason.split("|pitch| ")[1].split(" deg")[0])
    assert summary.max_abs_pitch_deg >= read_deg - 0.05  # the peak holds the fall's reading
    assert sink.summary is summary  # sinks are closed, so what was simulated is kept
    assert sink.frames and sink.frames[-1].stamp_s < 6.0
    assert any(text.startswith("fell") for _, text in sink.events)


def test_interrupted_run_still_closes_sinks():
    class Interrupt(Collect):
        def on_frame(self, frame, filter_result):
            super().on_frame(frame, filter_result)
            if len(self.frames) == 3:
                raise KeyboardInterrupt

    sink = Interrupt()
    with pytest.raises(KeyboardInterrupt):
        run_scenario(load_scenario("scenarios/hard_stop.toml"), seed=0, sinks=[sink])
    assert sink.summary is not None and sink.summary.end_reason == "interrupted"
    assert len(sink.frames) == 3


def test_shove_moves_a_standing_robot():
    scenario = short(load_scenario("scenarios/shove.toml"), 3.0)
    sim_before = simulation_for(scenario, seed=0)
    start = sim_before.truth().position_base_in_world.copy()
    sink = Collect()
    summary = run_scenario(scenario, seed=0, sinks=[sink])
    assert not summary.fell
    shoved = [f for f in sink.frames if f.truth.shove_active]
    assert shoved, "the shove's frames carry the flag"
    moved = np.linalg.norm(sink.frames[-1].truth.position_base_in_world[:2] - start[:2])
    assert moved > 0.05
    assert summary.max_abs_pitch_deg > 2.0


def test_truth_matches_the_commands_in_force():
    scenario = dataclasses.replace(
        load_scenario("scenarios/hard_stop.toml"),
        duration_s=2.0,
        commands=(CommandPoint(t_s=0.5, velocity_mps=0.5, yaw_rate_rad_s=0.3, ramp_s=0.5),),
    )
    sink = Collect()
    run_scenario(scenario, seed=0, sinks=[sink])
    last = sink.frames[-1].truth
    assert last.command_velocity_mps == pytest.approx(0.5)
    assert last.command_yaw_rate_rad_s == pytest.approx(0.3)
    assert math.isfinite(last.pitch_rad) and last.rotation_sensor_to_world.shape == (3, 3)


def test_raw_torques_track_the_peak_pitch_too():
    sim = simulation_for(short(load_scenario("scenarios/hard_stop.toml"), 1.0), seed=0)
    sim.step_torques(np.array([1.0, 1.0]), n_steps=100)  # open loop: the body tips back
    assert sim.max_abs_pitch_rad >= abs(sim.pitch_rad()) > 0.01


def test_tipping_over_sideways_is_a_fall_too():
    scenario = scenario_from_table(
        {
            "duration_s": 4.0,
            "shoves": [
                {
                    "t_s": 1.0,
                    "force_n": [0.0, 80.0, 0.0],
                    "duration_s": 0.3,
                    "point_m": [0, 0, 0.45],
                }
            ],
        }
    )
    summary = run_scenario(scenario, seed=0)
    assert summary.fell
    assert summary.end_reason.startswith("fell: |roll|")
