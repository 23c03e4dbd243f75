"""Where a physics step's time goes, stage by stage, in the houses ``twsb generate`` makes.

Builds the simulations of the first episodes of a data set (default ranges, seed 0) and
steps each from its start with the LQR holding a cruise command, reading MuJoCo's own
per-stage timers (``MjData.timer``), for three versions of each model, interleaved:

1. as the simulator builds it;
2. with MuJoCo's sleeping off, so that every static geom's pose is recomputed at each
   step (what the models did before they skipped them; same trajectories);
3. with the house's geoms out of collision but the floor (compiled so), for reference:
   what colliding with the house costs. Not a model the simulator uses.

Prints the median over episodes and repeats of each stage, in µs per step. Timings on a
shared machine are noisy; the columns are measured in the same run. Usage::

    python benchmarks/bench_step.py [--episodes 8] [--steps 1000] [--repeats 3]
"""

from __future__ import annotations

import argparse
import copy
import statistics

import mujoco
import numpy as np

from twsb_sim.control.balance import bound_control
from twsb_sim.dataset.episode import draw_episode
from twsb_sim.dataset.randomization import Randomization
from twsb_sim.house import add_house_to_spec
from twsb_sim.robot import load_robot_spec
from twsb_sim.runner import scenario_world, simulation_for
from twsb_sim.scenario import Scenario, scenario_from_table
from twsb_sim.simulation import skip_static_geom_poses

STAGES = (
    "STEP", "POS_KINEMATICS", "POS_INERTIA", "POS_COLLISION", "COL_BROAD", "COL_NARROW",
    "POS_MAKE", "VELOCITY", "ACTUATION", "CONSTRAINT", "ADVANCE",
)  # fmt: skip
VERSIONS = ("as built", "no sleeping", "floor only")
CRUISE_MPS = 0.4  # m/s, the command held while stepping
SLEEP = int(mujoco.mjtEnableBit.mjENBL_SLEEP)


def floor_only_model(scenario: Scenario) -> mujoco.MjModel:
    """The scenario's model with every static geom but the floor out of collision."""
    house, movers, _ = scenario_world(scenario)
    spec = load_robot_spec(scenario.robot)
    add_house_to_spec(spec, house)
    for geom in spec.worldbody.geoms:
        if geom.type != mujoco.mjtGeom.mjGEOM_PLANE:
            geom.contype = geom.conaffinity = 0
    if movers:
        movers.add_to_spec(spec)
    skip_static_geom_poses(spec)
    return spec.compile()


def stage_times(episode: int, steps: int, repeats: int) -> dict[str, dict[str, list[float]]]:
    """Per version and stage, the µs per step of each repeat, for one episode."""
    draw = draw_episode(0, episode, Randomization())
    scenario = scenario_from_table(draw.scenario_table, source=f"episode {episode}")
    sim = simulation_for(scenario, scenario.seed)
    plain = copy.copy(sim.model)
    plain.opt.enableflags &= ~SLEEP
    models = {"as built": sim.model, "no sleeping": plain, "floor only": floor_only_model(scenario)}
    start = sim.data  # every timing starts from the robot at its start pose
    state = mujoco.mjtState.mjSTATE_INTEGRATION
    initial = np.empty(mujoco.mj_stateSize(sim.model, state))
    mujoco.mj_getState(sim.model, start, initial, state)
    times = {version: {stage: [] for stage in STAGES} for version in VERSIONS}
    for _ in range(repeats):
        for version in VERSIONS:
            model = models[version]
            data = mujoco.MjData(model)
            mujoco.mj_setState(model, data, initial, state)
            sim.controller.reset()
            control = bound_control(sim.controller, data)
            for timer in data.timer:
                timer.duration, timer.number = 0.0, 0
            for _ in range(steps):
                control(CRUISE_MPS, 0.0)
                mujoco.mj_step(model, data)
            for stage in STAGES:
                timer = data.timer[getattr(mujoco.mjtTimer, f"mjTIMER_{stage}")]
                times[version][stage].append(timer.duration / steps * 1e6)
    return times


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=8, help="episodes (houses) measured")
    parser.add_argument("--steps", type=int, default=1000, help="physics steps per timing")
    parser.add_argument("--repeats", type=int, default=3, help="timings per version")
    args = parser.parse_args()
    all_times = {version: {stage: [] for stage in STAGES} for version in VERSIONS}
    for episode in range(args.episodes):
        for version, stages in stage_times(episode, args.steps, args.repeats).items():
            for stage, values in stages.items():
                all_times[version][stage].extend(values)
    print(f"us per physics step, median of {args.episodes} episodes x {args.repeats} repeats")
    print(f"{'stage':16s}" + "".join(f"{version:>13s}" for version in VERSIONS))
    for stage in STAGES:
        medians = (statistics.median(all_times[version][stage]) for version in VERSIONS)
        print(f"{stage.lower():16s}" + "".join(f"{value:13.2f}" for value in medians))


if __name__ == "__main__":
    main()
