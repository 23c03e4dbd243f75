"""How fast the closed-loop simulation runs, against a bare ``mj_step`` loop.

Runs, in one process and on one core:

1. a bare ``mujoco.mj_step`` loop of the same model (robot in house1, zero torques, robot
   held upright by resetting it whenever it tips) — the floor no Python loop can beat;
2. the closed loop as a scenario runs it with the default sensors: LQR every physics step
   (500 Hz), the rotating LiDAR with its reading errors, the IMU (200 Hz) and its
   attitude filter, encoder odometry (50 Hz), frames at 10 Hz, the hard-stop timeline;
3. the same with a global-shutter LiDAR without reading errors (``sweep = "instant"``,
   ``LidarConfig.ideal()``), the closest to the sensors of earlier versions;
4. the default loop with the Pitch Variation Filter in the loop.

Timings on a shared machine are noisy, so the script reports each as a real-time factor
and as a ratio against the bare loop measured in the same run. Usage::

    python benchmarks/bench_simulation.py [--seconds 20] [--repeats 3]
"""

from __future__ import annotations

import argparse
import dataclasses
import time

import mujoco

from pvfilter import PitchVariationFilter
from twsb_sim.lidar import LidarConfig
from twsb_sim.runner import run_scenario, simulation_for
from twsb_sim.scenario import load_scenario
from twsb_sim.scenario_files import resolve_scenario


def bare_real_time_factor(seconds: float, scenario_name: str = "hard_stop") -> float:
    """Simulated seconds per wall second of a bare mj_step loop of the scenario's model
    (zero torques, the robot put back upright every 0.5 s)."""
    sim = simulation_for(load_scenario(resolve_scenario(scenario_name)), seed=0)
    model, data = sim.model, sim.data
    n_steps = round(seconds / sim.dt_s)
    qpos0, chunk = data.qpos.copy(), 250  # 0.5 s: the uncontrolled robot has not fallen yet
    started = time.perf_counter()
    for k in range(n_steps):
        if k % chunk == 0:
            data.qpos[:] = qpos0
            data.qvel[:] = 0.0
        mujoco.mj_step(model, data)
    return n_steps * sim.dt_s / (time.perf_counter() - started)


def closed_loop_rate(
    seconds: float, with_filter: bool, instant_lidar: bool = False
) -> tuple[float, int]:
    """Simulated seconds per wall second of the hard-stop scenario (closed loop + sensors)."""
    scenario = load_scenario(resolve_scenario("hard_stop"))
    if instant_lidar:
        scenario = dataclasses.replace(scenario, lidar=LidarConfig.ideal(sweep="instant"))
    total_sim, total_wall, frames = 0.0, 0.0, 0
    while total_sim < seconds:
        scan_filter = PitchVariationFilter() if with_filter else None
        summary = run_scenario(scenario, seed=0, scan_filter=scan_filter)
        total_sim += summary.simulated_s
        total_wall += summary.wall_s
        frames += summary.frames
    return total_sim / total_wall, frames


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--seconds", type=float, default=20.0, help="simulated seconds per measurement"
    )
    parser.add_argument(
        "--repeats",
        type=int,
        default=3,
        help="take the best of this many measurements (at least 2: the first pays for "
        "compiling and warming up)",
    )
    args = parser.parse_args()
    bare, closed, instant, filtered = [], [], [], []
    for _ in range(args.repeats):  # interleaved, so machine load hits all four alike
        bare.append(bare_real_time_factor(args.seconds))
        closed.append(closed_loop_rate(args.seconds, with_filter=False)[0])
        instant.append(closed_loop_rate(args.seconds, with_filter=False, instant_lidar=True)[0])
        filtered.append(closed_loop_rate(args.seconds, with_filter=True)[0])
    bare_rtf = max(bare)
    rows = [
        ("bare mj_step loop", bare_rtf),
        ("closed loop, default sensors", max(closed)),
        ("  instant ideal LiDAR instead", max(instant)),
        ("  + filter in the loop", max(filtered)),
    ]
    for name, rtf in rows:
        print(f"{name:32s}{rtf:7.1f}x real time  = {rtf / bare_rtf:.2f} of bare")
    print(f"(best of {args.repeats}, {args.seconds:g} simulated s each)")


if __name__ == "__main__":
    main()
