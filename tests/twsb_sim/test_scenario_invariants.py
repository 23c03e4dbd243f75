"""Every shipped scenario: it builds, runs with bounded torques and no MuJoCo warning,
and the same seed gives bitwise-identical frames."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from twsb_sim.runner import run_scenario
from twsb_sim.scenario import load_scenario
from twsb_sim.sinks import NullSink

SCENARIOS = sorted((Path(__file__).resolve().parents[2] / "scenarios").glob("*.toml"))
SECONDS = 3.0


class Keep(NullSink):
    def __init__(self) -> None:
        self.frames = []

    def on_frame(self, frame, filter_result):
        self.frames.append(frame)


def first_seconds(path: Path):
    scenario = load_scenario(path)
    return dataclasses.replace(
        scenario,
        duration_s=SECONDS,
        commands=tuple(c for c in scenario.commands if c.t_s + c.ramp_s <= SECONDS),
        shoves=tuple(s for s in scenario.shoves if s.end_s <= SECONDS),
    )


@pytest.mark.parametrize("path", SCENARIOS, ids=[p.stem for p in SCENARIOS])
def test_scenario_runs_cleanly_and_deterministically(path):
    scenario = first_seconds(path)
    runs = []
    for _ in range(2):
        sink = Keep()
        summary = run_scenario(scenario, seed=11, sinks=[sink])
        assert not summary.fell, summary.end_reason
        assert summary.mujoco_warnings == {}
        assert summary.frames == round(SECONDS * 10) + 1
        runs.append(sink.frames)
    limit = scenario.robot.wheel_torque_limit_nm
    for a, b in zip(*runs, strict=True):
        assert np.array_equal(a.scan.ranges, b.scan.ranges, equal_nan=True)
        assert np.array_equal(a.labels, b.labels)
        assert np.array_equal(a.truth.position_base_in_world, b.truth.position_base_in_world)
        sa, sb = a.sensors, b.sensors  # the sensors' errors come from the seed too
        assert np.array_equal(sa.imu.gyro_rad_s, sb.imu.gyro_rad_s)
        assert np.array_equal(sa.attitude_rpy_rad, sb.attitude_rpy_rad)
        assert np.array_equal(sa.odometry.pose_odom, sb.odometry.pose_odom)
        assert np.array_equal(sa.pose_lidar_in_odom, sb.pose_lidar_in_odom)
        assert np.abs(a.truth.wheel_torques_nm).max() <= limit + 1e-12
