"""Runs a scenario: the timeline drives the simulation, frames flow to the filter and sinks.

The loop is a schedule of breakpoints (every LiDAR frame, every shove start and end,
every command point); between two breakpoints the simulation steps through a slice of
the precomputed command arrays, so nothing but the controller and ``mj_step`` runs per
physics step.
"""

from __future__ import annotations

import dataclasses
import math
import sys
import time
from collections.abc import Sequence
from typing import Any

import numpy as np
from tqdm import tqdm

from pvfilter import ScanFilter
from twsb_sim.collision_region import CollisionRegion
from twsb_sim.config_errors import ConfigError
from twsb_sim.control.gains import UnstableClosedLoopError
from twsb_sim.environment import check_rooms, house_extras, movers
from twsb_sim.frame_filter import FrameFilter, as_frame_filter
from twsb_sim.house import House, HouseExtras, SpawnPose, house_with
from twsb_sim.house.standing import ROBOT_HEIGHT_M, why_cannot_stand
from twsb_sim.kernel import FIRST_COMPILE_NOTICE, compiled_on_this_machine
from twsb_sim.movers import MoverSet
from twsb_sim.scenario import HouseChoice, Scenario
from twsb_sim.simulation import Shove as ActiveShove
from twsb_sim.simulation import Simulation
from twsb_sim.sinks import FrameSink
from twsb_sim.stopping import stop_within
from twsb_sim.summary import RunSummary
from twsb_sim.timeline import heading_force_to_world, phase_at, sample_commands


class SimulationDiverged(ConfigError):
    """The physics blew up (MuJoCo reset the state): the scenario asks for more than the
    simulation can take. The frames before it are kept; none after it is made."""

    def __init__(self, source: str, reason: str) -> None:
        super().__init__(
            source,
            "",
            f"the simulation {reason}; a shove, a command or a robot value "
            "of this scenario is beyond what the physics can take",
        )


def build_house(choice: HouseChoice, extras: HouseExtras | None = None) -> House:
    """The house a scenario asks for (with ``extras`` added)."""
    return house_with(choice.name, choice.seed, extras)


def scenario_world(scenario: Scenario) -> tuple[House, MoverSet, tuple[float, float, float]]:
    """The house (with what the scenario adds to it), its movers, and the robot's start.

    Floor features on the robot's path and movers placed relative to the start pose are
    placed once the start is known; they do not block, so they leave the spawn poses as
    they are.
    """
    environment, source = scenario.environment, scenario.source
    height = scenario.robot.lidar_height_m
    if not environment:
        house = build_house(scenario.house)
        return house, MoverSet(), start_pose(scenario.house, house, source, height)
    check_rooms(environment, build_house(scenario.house), source)
    fixed = dataclasses.replace(house_extras(environment, (0.0, 0.0, 0.0)), floor_features=())
    start = start_pose(scenario.house, build_house(scenario.house, fixed), source, height)
    house = build_house(scenario.house, house_extras(environment, start))
    return house, movers(environment, house, start), start


LIDAR_HEAD_M = 0.05  # m, the scanner's head above its origin


def start_pose(
    choice: HouseChoice, house: House, source: str, lidar_height_m: float = 0.25
) -> tuple[float, float, float]:
    """The robot's start (x m, y m, yaw rad) from the scenario's house table.

    Raises:
        ConfigError: a spawn index the house does not have, or a ``start`` where the
            robot cannot stand (outside the house, in a wall or a piece of furniture).
    """
    if choice.start is not None:
        x, y, yaw_deg = choice.start
        reason = why_cannot_stand(house, x, y, max(ROBOT_HEIGHT_M, lidar_height_m + LIDAR_HEAD_M))
        if reason is not None:
            raise ConfigError(
                source, "house.start", f"no place for the robot at ({x:g}, {y:g}): {reason}"
            )
        return x, y, math.radians(yaw_deg)
    if choice.spawn >= len(house.spawn_poses):
        raise ConfigError(
            source,
            "house.spawn",
            f"{house.name} has {len(house.spawn_poses)} spawn poses, got index {choice.spawn}",
        )
    pose: SpawnPose = house.spawn_poses[choice.spawn]
    return pose.x_m, pose.y_m, pose.yaw_rad


def simulation_for(
    scenario: Scenario, seed: int, collision_region: CollisionRegion | None = None
) -> Simulation:
    """Build the house, robot, controller, LiDAR, sensors and movers of a scenario, robot
    at its start (``collision_region``: see :class:`~twsb_sim.simulation.Simulation`)."""
    house, mover_set, start = scenario_world(scenario)
    try:
        sim = Simulation(
            house,
            robot=scenario.robot,
            lidar=scenario.lidar,
            controller=scenario.controller,
            fall_pitch_deg=scenario.simulation.fall_pitch_deg,
            seed=seed,
            imu=scenario.imu,
            attitude=scenario.attitude,
            odometry=scenario.odometry,
            movers=mover_set,
            balance=scenario.balance,
            start=start,
            collision_region=collision_region,
        )
    except UnstableClosedLoopError as error:
        raise ConfigError(scenario.source, "controller", str(error)) from None
    return sim


def run_scenario(
    scenario: Scenario,
    seed: int | None = None,
    scan_filter: ScanFilter | FrameFilter | None = None,
    sinks: Sequence[FrameSink] = (),
    progress: bool = False,
    collision_region: CollisionRegion | None = None,
) -> RunSummary:
    """Simulate ``scenario`` and hand every frame to the filter and the sinks.

    A fall ends the run early (``summary.fell``, with the reason); Ctrl-C ends it too,
    after the sinks are closed so what was simulated is kept, and is then re-raised.

    Args:
        scenario: what to run.
        seed: the run's seed (default: the scenario's); same scenario and seed give
            bitwise-identical frames.
        scan_filter: a :class:`pvfilter.ScanFilter` (run on the scans alone), a
            :class:`twsb_sim.frame_filter.FrameFilter` (given its robot inputs), or None.
        sinks: consumers of the frames (see :mod:`twsb_sim.sinks`).
        progress: show a progress bar over simulated time.
        collision_region: where the robot will stay: a cheaper physics step, the same
            frames; the run raises :class:`~twsb_sim.collision_region.LeftCollisionRegion`
            if the robot leaves it (see :class:`~twsb_sim.simulation.Simulation`).

    Returns:
        The run's summary.
    """
    seed = scenario.seed if seed is None else seed
    if progress and not compiled_on_this_machine():  # the first frames wait for it
        tqdm.write(FIRST_COMPILE_NOTICE, file=sys.stderr)
    sim = simulation_for(scenario, seed, collision_region)
    summary = RunSummary(scenario=scenario.name, seed=seed, house=sim.house.name)
    if scan_filter is not None:
        scan_filter = as_frame_filter(scan_filter)
        summary.filter_name = scan_filter.label
        scan_filter.reset()
    started = time.perf_counter()
    n_frames = math.floor(scenario.duration_s * scenario.lidar.rate_hz + 1e-9) + 1
    bar = tqdm(total=n_frames, desc=scenario.name, unit="frame", disable=not progress, leave=False)
    try:
        _simulate(scenario, sim, scan_filter, sinks, summary, bar)
    except BaseException as error:
        if stop_within(error) is not None:  # a Ctrl-C or SIGTERM, perhaps wrapped
            summary.end_reason = "interrupted"
        raise
    finally:
        bar.close()
        summary.wall_s = time.perf_counter() - started
        summary.max_abs_pitch_deg = max(
            summary.max_abs_pitch_deg, math.degrees(sim.max_abs_pitch_rad)
        )
        summary.mujoco_warnings = sim.mujoco_warnings()
        for sink in sinks:
            sink.close(summary)
    return summary


def _simulate(
    scenario: Scenario,
    sim: Simulation,
    scan_filter: FrameFilter | None,
    sinks: Sequence[FrameSink],
    summary: RunSummary,
    bar: tqdm,
) -> None:
    dt = sim.dt_s
    n_steps = round(scenario.duration_s / dt)
    frame_every = round(1.0 / (sim.lidar.config.rate_hz * dt))
    commands = sample_commands(scenario.commands, dt, n_steps + 1)
    to_step = lambda t: round(t / dt)  # noqa: E731
    shove_starts = {to_step(s.t_s): s for s in scenario.shoves}
    shove_ends = {to_step(s.end_s) for s in scenario.shoves}
    phase_starts = {to_step(p.t_s) for p in scenario.commands}
    for sink in sinks:  # optional hook: the sink sees the house, the model and the timeline
        if hasattr(sink, "on_start"):
            sink.on_start(scenario, sim)
    frame_steps = range(0, n_steps + 1, frame_every)
    timeline_steps = {*frame_steps, *shove_starts, *shove_ends, *phase_starts, n_steps}
    # optional hook: sinks with a ``state_rate_hz`` get the robot's truth at that rate too;
    # with none, no breakpoint is added, so the physics loop pays nothing; their extra
    # breakpoints only sample the state (no fall check), so the run stays the same
    state_every = _state_intervals(sinks, dt)
    state_steps = {k for _, every in state_every for k in range(0, n_steps + 1, every)}
    breakpoints = sorted(timeline_steps | state_steps)
    events = lambda text: [sink.on_event(sim.time_s, text) for sink in sinks]  # noqa: E731
    frame_index = 0
    for k, k_next in zip(breakpoints, [*breakpoints[1:], None], strict=True):
        if k in shove_ends:
            sim.set_shove(None)
        if k in phase_starts:
            events(f"phase: {phase_at(scenario.commands, k * dt)}")
        if k in shove_starts:
            shove = shove_starts[k]
            force = heading_force_to_world(shove.force_n, sim.truth().yaw_rad)
            sim.set_shove(ActiveShove(force_world_n=force, point_body_m=np.array(shove.point_m)))
            events(
                f"shove: {np.linalg.norm(force):.0f} N for {shove.duration_s:g} s"
                + (f" ({shove.label})" if shove.label else "")
            )
        diverged = sim.divergence()
        if diverged is not None:  # the state was reset: no frame from here on is true
            summary.end_reason = f"diverged before t={k * dt:.3f} s: {diverged}"
            raise SimulationDiverged(scenario.source, summary.end_reason)
        fall = sim.fall_reason() if k in timeline_steps else None
        if fall is not None:
            # (the peak runs over the states the steps started from; the state the fall
            # was read in comes after them, and the summary's peak must not be below it)
            reading_deg = abs(math.degrees(sim.truth().pitch_rad))
            summary.max_abs_pitch_deg = max(summary.max_abs_pitch_deg, reading_deg)
            reason = f"fell: {fall} at t={sim.time_s:.2f} s"
            summary.fell, summary.end_reason = True, reason
            events(reason)
            return
        if k in state_steps:
            truth = sim.truth()
            for sink, every in state_every:
                if k % every == 0:
                    sink.on_state(truth)
        if k % frame_every == 0:
            frame = sim.frame(frame_index, phase=phase_at(scenario.commands, k * dt))
            result = scan_filter.process(frame) if scan_filter is not None else None
            summary.add_frame(frame, None if result is None else result.removed)
            for sink in sinks:
                sink.on_frame(frame, result)
            frame_index += 1
            bar.update()
        if k_next is not None:
            sim.run_commands(commands.velocity_mps[k:k_next], commands.yaw_rate_rad_s[k:k_next])


def _state_intervals(sinks: Sequence[FrameSink], dt_s: float) -> list[tuple[Any, int]]:
    """Each sink that asks for ``on_state`` calls, with the physics steps between two calls."""
    rates = [(sink, getattr(sink, "state_rate_hz", None)) for sink in sinks]
    return [(sink, max(1, round(1.0 / (hz * dt_s)))) for sink, hz in rates if hz]
