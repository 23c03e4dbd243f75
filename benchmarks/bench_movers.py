"""How fast the closed loop runs with people in view, against the same loop without them.

Runs, in one process and on one core, the closed loop as ``twsb run`` runs it (LQR every
physics step, LiDAR ray cast and frame at 10 Hz, no filter) on:

1. ``hard_stop`` (house1, nothing moves) — the reference;
2. ``people_crossing`` (house1: three people and a dog walking through the robot's view);
3. ``doors_and_bump`` (house1: three door leaves swinging, a stool the robot pushes);

and a bare ``mujoco.mj_step`` loop of the reference model (the floor no Python loop can
beat). Movers are posed only when the LiDAR casts, so people should cost only the extra
geoms in the ray cast. Timings on a shared machine are noisy: each result is the best of
``--repeats`` measurements, interleaved, reported as a real-time factor and as a ratio to
the reference measured in the same run. Usage::

    python benchmarks/bench_movers.py [--seconds 16] [--repeats 3]
"""

from __future__ import annotations

import argparse

from bench_simulation import bare_real_time_factor  # this folder's: the same bare loop

from twsb_sim.runner import run_scenario
from twsb_sim.scenario import load_scenario
from twsb_sim.scenario_files import resolve_scenario

SCENARIOS = ("hard_stop", "people_crossing", "doors_and_bump")


def closed_loop_rate(name: str, seconds: float) -> float:
    """Simulated seconds per wall second of a scenario (closed loop + LiDAR), repeated."""
    scenario = load_scenario(resolve_scenario(name))
    total_sim = total_wall = 0.0
    while total_sim < seconds:
        summary = run_scenario(scenario, seed=0)
        total_sim += summary.simulated_s
        total_wall += summary.wall_s
    return total_sim / total_wall


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=16.0, help="simulated s per measurement")
    parser.add_argument("--repeats", type=int, default=3, help="best of this many")
    args = parser.parse_args()
    best = {name: 0.0 for name in ("bare mj_step", *SCENARIOS)}
    for _ in range(args.repeats):  # interleaved: machine load hits all alike
        best["bare mj_step"] = max(
            best["bare mj_step"], bare_real_time_factor(args.seconds, SCENARIOS[0])
        )
        for name in SCENARIOS:
            best[name] = max(best[name], closed_loop_rate(name, args.seconds))
    reference = best[SCENARIOS[0]]
    for name, rtf in best.items():
        print(f"{name:22s} {rtf:6.1f}x real time  = {rtf / reference:4.2f} of {SCENARIOS[0]}")
    print(f"(best of {args.repeats}, {args.seconds:g} simulated s each)")


if __name__ == "__main__":
    main()
