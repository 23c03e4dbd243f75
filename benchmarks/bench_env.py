"""How fast the Gymnasium environments step, on one core.

Runs whole episodes (``gymnasium.make``, so with its ``TimeLimit`` and checker wrappers)
with a policy that sends the episode's target as the command, and reports env steps per
wall second and the real-time factor (simulated seconds per wall second):

1. ``TwsbVelocity-v0`` as registered: one step = one LiDAR period (0.1 s, 50 physics
   steps with the LQR), a scan and an observation per step;
2. the same with the Pitch Variation Filter in the loop;
3. the same with shoves and hard stops;
4. ``TwsbTorque-v0`` (0.01 s per step, a scan every 10 steps).

Resets are included (each episode's house is built once, then reused). Timings on a
shared machine are noisy: the best of ``--repeats`` is reported. Usage::

    python benchmarks/bench_env.py [--seconds 60] [--repeats 3]
"""

from __future__ import annotations

import argparse
import time

import gymnasium as gym
import numpy as np

from twsb_sim.envs import TORQUE_ID, VELOCITY_ID, Disturbances, register

CASES = {
    "TwsbVelocity-v0": (VELOCITY_ID, {}),
    "  + filter in the loop": (VELOCITY_ID, {"scan_filter": True}),
    "  + shoves and hard stops": (
        VELOCITY_ID,
        {"disturbances": Disturbances(shove_rate_hz=0.2, hard_stop_rate_hz=0.2)},
    ),
    "TwsbTorque-v0 (zero torques)": (TORQUE_ID, {}),
}


def measure(env_id: str, kwargs: dict, seconds: float) -> tuple[float, float]:
    """Env steps per wall second and simulated seconds per wall second."""
    env = gym.make(env_id, **kwargs)
    period = env.unwrapped.control_period_s
    obs, _ = env.reset(seed=0)  # builds the house and the controller before the clock starts
    torque = env_id == TORQUE_ID
    steps, n_steps = 0, round(seconds / period)
    started = time.perf_counter()
    while steps < n_steps:
        action = np.zeros(2, dtype=np.float32) if torque else obs["target"]
        obs, _, terminated, truncated, _ = env.step(action)
        steps += 1
        if terminated or truncated:
            obs, _ = env.reset()
    wall = time.perf_counter() - started
    env.close()
    return steps / wall, steps * period / wall


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--seconds", type=float, default=60.0, help="simulated seconds per measurement"
    )
    parser.add_argument(
        "--repeats", type=int, default=3, help="take the best of this many measurements"
    )
    args = parser.parse_args()
    register()
    best: dict[str, tuple[float, float]] = {}
    for _ in range(args.repeats):  # interleaved, so machine load hits every case alike
        for name, (env_id, kwargs) in CASES.items():
            rate, rtf = measure(env_id, kwargs, args.seconds)
            if name not in best or rate > best[name][0]:
                best[name] = (rate, rtf)
    for name, (rate, rtf) in best.items():
        print(f"{name:30s}{rate:8.0f} steps/s{rtf:8.1f}x real time")
    print(f"(best of {args.repeats}, {args.seconds:g} simulated s each, one core)")


if __name__ == "__main__":
    main()
