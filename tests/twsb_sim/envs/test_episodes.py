"""What episodes do: standing, falling, disturbances, rewards, the filter and the sink."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest

from twsb_sim.envs import REWARD_TERMS, TORQUE_ID, VELOCITY_ID, Disturbances
from twsb_sim.labels import is_pitch_variation
from twsb_sim.sinks import NullSink


def test_zero_commands_stand_for_the_whole_episode() -> None:
    env = gym.make(VELOCITY_ID, house="house2")
    env.reset(seed=0)
    steps, max_pitch = 0, 0.0
    while True:
        _, _, terminated, truncated, info = env.step(np.zeros(2, dtype=np.float32))
        steps += 1
        max_pitch = max(max_pitch, abs(info["pitch_rad"]))
        if terminated or truncated:
            break
    assert truncated and not terminated
    assert steps == env.spec.max_episode_steps
    assert info["time_s"] == pytest.approx(20.0)
    assert info["fall_reason"] == ""
    assert max_pitch < math.radians(1.0)


def test_random_torques_fall_and_terminate_with_the_reason() -> None:
    env = gym.make(TORQUE_ID)
    env.reset(seed=1)
    env.action_space.seed(1)
    for _ in range(env.spec.max_episode_steps):
        _, reward, terminated, truncated, info = env.step(env.action_space.sample())
        if terminated or truncated:
            break
    assert terminated and not truncated
    assert info["fall_reason"].startswith(("pitch:", "roll:"))
    # the reading to a tenth of a degree: "45 deg > 45 deg" read as false
    reading = info["fall_reason"].split("| ")[1].split(" deg")[0]
    assert float(reading) > 45.0 and len(reading.split(".")[1]) == 1
    assert info["fall_reason"].endswith(" deg > 45 deg")
    assert info["time_s"] < 5.0
    assert info["reward_fall"] == -10.0 and reward < -9.0


def test_reward_terms_are_in_info_and_sum_to_the_reward() -> None:
    env = gym.make(VELOCITY_ID)
    env.reset(seed=2, options={"target": (0.5, 0.0)})
    for _ in range(20):
        _, reward, _, _, info = env.step(np.array([0.5, 0.0], dtype=np.float32))
    terms = [info[f"reward_{name}"] for name in REWARD_TERMS]
    assert reward == pytest.approx(sum(terms))
    # tracking the target: the velocity kernel is near its best of weight * dt = 0.1
    assert info["reward_velocity"] > 0.09
    assert info["reward_pitch"] <= 0.0 and info["reward_fall"] == 0.0


def test_hard_stop_overrides_the_command_and_pitches_the_robot() -> None:
    env = gym.make(
        VELOCITY_ID,
        spawn=0,
        target_velocity_mps=1.0,
        disturbances=Disturbances(hard_stop_rate_hz=0.3, hard_stop_duration_s=1.5),
    )
    _, info = env.reset(seed=0)
    pitch_variation_beams, stops = 0, 0
    for _ in range(80):
        obs, _, terminated, _, info = env.step(np.array([1.0, 0.0], dtype=np.float32))
        assert not terminated
        if info["hard_stop_active"]:
            stops += 1
            assert obs["target"].tolist() == [0.0, 0.0]
        pitch_variation_beams += int(is_pitch_variation(info["labels"]).sum())
    assert stops > 0
    assert pitch_variation_beams > 0
    frame = env.unwrapped.latest_frame
    np.testing.assert_array_equal(frame.labels, info["labels"])
    assert frame.hit_points_world.shape == (720, 3)


def test_shoves_push_the_robot_and_it_recovers() -> None:
    env = gym.make(
        VELOCITY_ID,
        target_velocity_mps=0.0,
        target_yaw_rate_rad_s=0.0,
        disturbances={"shove_rate_hz": 0.5, "shove_force_n": [20.0, 30.0]},
    )
    env.reset(seed=5)
    shoved, max_pitch = 0, 0.0
    for _ in range(40):
        _, _, terminated, _, info = env.step(np.zeros(2, dtype=np.float32))
        assert not terminated
        shoved += info["shove_active"]
        max_pitch = max(max_pitch, abs(info["pitch_rad"]))
    assert shoved > 0 and max_pitch > math.radians(2.0)


def test_filter_mask_is_in_info_when_the_filter_is_on() -> None:
    env = gym.make(VELOCITY_ID, scan_filter=True)
    _, info = env.reset(seed=0)
    assert info["filter_removed"].shape == (720,) and info["filter_removed"].dtype == bool
    _, _, _, _, info = env.step(np.zeros(2, dtype=np.float32))
    assert "filter_removed" in info
    _, info = gym.make(VELOCITY_ID).reset(seed=0)
    assert "filter_removed" not in info


class Recorder(NullSink):
    def __init__(self) -> None:
        self.frames, self.events, self.summaries = [], [], []

    def on_frame(self, frame, filter_result):
        self.frames.append((frame, filter_result))

    def on_event(self, t_s, text):
        self.events.append(text)

    def close(self, summary):
        self.summaries.append(summary)


def test_sink_gets_every_scan_the_events_and_the_summary_once() -> None:
    sink = Recorder()
    env = gym.make(
        VELOCITY_ID,
        sink=sink,
        scan_filter=True,
        control_period_s=0.2,
        disturbances={"shove_rate_hz": 2.0},
    )
    env.reset(seed=0)
    for _ in range(10):
        env.step(np.zeros(2, dtype=np.float32))
    env.close()
    env.close()
    # one scan at reset, then two per 0.2 s step: every scan, in time order; a scan is
    # stamped with its first beam, one revolution (0.1 s) before it is handed out
    stamps = [frame.stamp_s for frame, _ in sink.frames]
    assert stamps == pytest.approx(np.arange(21) * 0.1 - 0.1)
    assert all(result is not None for _, result in sink.frames)
    assert sink.events[0].startswith("episode 1: house1")
    assert any(text.startswith("shove:") for text in sink.events)
    assert len(sink.summaries) == 1 and sink.summaries[0].frames == 21


def test_faster_control_rate_keeps_the_latest_scan() -> None:
    env = gym.make(VELOCITY_ID, control_period_s=0.02)
    env.reset(seed=0)
    stamps = []
    for _ in range(10):
        _, _, _, _, info = env.step(np.array([0.5, 0.0], dtype=np.float32))
        stamps.append(info["scan_stamp_s"])
    # the latest complete revolution, stamped with its first beam
    assert stamps == pytest.approx([-0.1] * 4 + [0.0] * 5 + [0.1])
    assert env.unwrapped.metadata["render_fps"] == 50


def test_wheel_odometry_follows_the_true_motion() -> None:
    env = gym.make(VELOCITY_ID, spawn=0)
    _, info = env.reset(seed=0)
    x0, y0, yaw0 = info["pose_world"]
    for _ in range(30):
        obs, _, _, _, info = env.step(np.array([0.5, 0.3], dtype=np.float32))
    x, y, yaw = info["pose_world"]
    c, s = math.cos(yaw0), math.sin(yaw0)
    dx, dy = x - x0, y - y0
    true_in_odom = (c * dx + s * dy, -s * dx + c * dy, math.remainder(yaw - yaw0, math.tau))
    np.testing.assert_allclose(obs["odometry"], true_in_odom, atol=0.05)
    assert np.linalg.norm(true_in_odom[:2]) > 1.0


def test_house_options_choose_the_house_per_reset() -> None:
    env = gym.make(VELOCITY_ID, house=["house1", "house2"])
    names = {env.reset(seed=seed)[1]["house"] for seed in range(6)}
    assert names == {"house1", "house2"}
    _, info = env.reset(options={"house": 11, "spawn": 0})
    assert info["house"] != "house1" and info["house"] != "house2"
    with pytest.raises(ValueError, match="house"):
        env.reset(options={"house": "castle"})
    with pytest.raises(ValueError, match="spawn"):
        env.reset(options={"spawn": 999})
    with pytest.raises(ValueError, match="unknown keys"):
        env.reset(options={"speed": 1.0})
