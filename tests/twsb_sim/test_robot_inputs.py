"""The robot inputs a filter gets from a simulated frame: the robot's sensors, or the truth."""

from __future__ import annotations

import numpy as np
import pytest

from twsb_sim.robot_inputs import imu_pitch_roll, robot_inputs, sensor_pose_2d
from twsb_sim.runner import run_scenario
from twsb_sim.scenario import load_scenario
from twsb_sim.scenario_files import resolve_scenario
from twsb_sim.sinks import NullSink


class _Frames(NullSink):
    def __init__(self) -> None:
        self.frames = []

    def on_frame(self, frame, filter_result) -> None:
        self.frames.append(frame)


@pytest.fixture(scope="module")
def frame():
    collect = _Frames()
    scenario = load_scenario(resolve_scenario("hard_stop"))
    run_scenario(scenario, sinks=[collect])
    return collect.frames[30]


def test_the_robot_s_inputs_come_from_its_sensors(frame):
    inputs = robot_inputs(frame, ("pitch_rad", "pose_sensor_in_odom"))
    assert (inputs["pitch_rad"], inputs["roll_rad"]) == tuple(frame.attitude_estimate)
    np.testing.assert_array_equal(inputs["pose_sensor_in_odom"], frame.lidar_pose_in_odom)
    # the estimate is not the truth (noise, bias, lag): the realistic input is exercised
    assert inputs["pitch_rad"] != pytest.approx(frame.truth.pitch_rad, abs=1e-6)


def test_the_truth_is_given_when_asked(frame):
    inputs = robot_inputs(frame, ("roll_rad", "pose_sensor_in_odom"), truth=True)
    assert (inputs["pitch_rad"], inputs["roll_rad"]) == imu_pitch_roll(frame.truth.imu_quat)
    np.testing.assert_array_equal(inputs["pose_sensor_in_odom"], sensor_pose_2d(frame.truth))


def test_only_the_contract_s_inputs_exist(frame):
    with pytest.raises(ValueError, match="robot input: unknown 'speed'"):
        robot_inputs(frame, ("speed",))


def test_an_estimate_of_several_turns_reaches_the_filter_as_an_angle(frame, monkeypatch):
    # after a fall the estimator's integral can read several turns; filters take angles
    wound = (0.1 + 2 * np.pi, 9.553)  # pitch, roll as the estimator integrated them
    monkeypatch.setattr(type(frame), "attitude_estimate", property(lambda self: wound))
    inputs = robot_inputs(frame, ("pitch_rad",))
    assert inputs["pitch_rad"] == pytest.approx(0.1)
    assert inputs["roll_rad"] == pytest.approx(9.553 - 4 * np.pi)
    assert abs(inputs["roll_rad"]) <= np.pi
