"""The environments follow Gymnasium's API: check_env, vector envs, seeding, registration."""

from __future__ import annotations

import subprocess
import sys
import warnings

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

from twsb_sim.envs import ENV_IDS, TORQUE_ID, VELOCITY_ID, Disturbances, register


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_check_env_passes_without_warnings(env_id: str) -> None:
    env = gym.make(env_id)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        # rendering is checked in test_render.py, in a process whose GL backend is chosen
        check_env(env.unwrapped, skip_render_check=True)
    assert [str(w.message) for w in caught] == []
    env.close()


def test_import_registers_nothing_and_register_is_idempotent() -> None:
    code = (
        "import gymnasium as gym, twsb_sim.envs as e\n"
        "assert not set(e.ENV_IDS) & set(gym.registry)\n"
        "e.register(); e.register()\n"
        "assert set(e.ENV_IDS) <= set(gym.registry)\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True, timeout=60)
    register()  # again in this process, after the session fixture did: no error, no change
    assert gym.spec(VELOCITY_ID).max_episode_steps == 200
    assert gym.spec(TORQUE_ID).max_episode_steps == 2000


def test_make_vec_steps_several_envs() -> None:
    envs = gym.make_vec(VELOCITY_ID, num_envs=3, vectorization_mode="sync", house="random")
    obs, info = envs.reset(seed=7)
    assert obs["scan"].shape == (3, 720) and obs["scan"].dtype == np.float32
    for _ in range(5):
        obs, reward, terminated, truncated, info = envs.step(envs.action_space.sample())
    assert reward.shape == terminated.shape == truncated.shape == (3,)
    assert info["labels"].shape == (3, 720)
    assert not terminated.any()
    # seeds 7, 8, 9 draw three different random houses
    assert len(set(info["house"])) == 3
    envs.close()


def test_make_vec_async_runs_in_subprocesses() -> None:
    envs = gym.make_vec(TORQUE_ID, num_envs=2, vectorization_mode="async")
    obs, _ = envs.reset(seed=0)
    obs, *_ = envs.step(np.zeros((2, 2), dtype=np.float32))
    assert obs["imu_quat"].shape == (2, 4)
    envs.close()


def run_episode(env_id: str, seed: int, steps: int, **kwargs) -> list:
    env = gym.make(env_id, **kwargs)
    env.action_space.seed(seed)
    record = [env.reset(seed=seed)]
    for _ in range(steps):
        record.append(env.step(env.action_space.sample()))
        if record[-1][2] or record[-1][3]:
            break
    env.close()
    return record


def assert_same(a, b) -> None:
    if isinstance(a, dict):
        assert a.keys() == b.keys()
        for key in a:
            assert_same(a[key], b[key])
    elif isinstance(a, tuple | list):
        assert len(a) == len(b)
        for x, y in zip(a, b, strict=True):
            assert_same(x, y)
    elif isinstance(a, np.ndarray):
        np.testing.assert_array_equal(a, b)
    else:
        assert a == b


DISTURBED = {
    "house": ["house1", "house2", "random"],
    "disturbances": Disturbances(shove_rate_hz=1.0, hard_stop_rate_hz=0.5),
}


def test_same_seed_gives_the_same_episode() -> None:
    first = run_episode(VELOCITY_ID, seed=3, steps=60, **DISTURBED)
    again = run_episode(VELOCITY_ID, seed=3, steps=60, **DISTURBED)
    assert_same(first, again)
    infos = [step[-1] for step in first[1:]]
    assert any(i["shove_active"] for i in infos) and any(i["hard_stop_active"] for i in infos)


def test_another_seed_gives_another_episode() -> None:
    first = run_episode(VELOCITY_ID, seed=3, steps=5, **DISTURBED)
    other = run_episode(VELOCITY_ID, seed=4, steps=5, **DISTURBED)
    assert not np.array_equal(first[-1][0]["scan"], other[-1][0]["scan"])
