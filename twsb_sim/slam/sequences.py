"""The sequences of the SLAM experiment: the paper-like house runs and random hard stops.

``house1_single`` and ``house2_multi`` are the shipped scenarios (the paper's House
sequences 1 and 2). :func:`hard_stop_sequence` writes a new run for a seeded random house:
legs along the house's free lanes, each ending in a hard stop, with turns in place between
them. Every leg is planned on the house's obstacle footprints (``spawn.Obstacles``, the
same ones the spawn poses are chosen on) with room kept for the robot's lag and its
overshoot when it stops hard, so the robot stays off the walls.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from twsb_sim.house import ROBOT_RADIUS_M, House, make_house, random_house
from twsb_sim.house.spawn import Obstacles
from twsb_sim.scenario import HouseChoice, Scenario, load_scenario
from twsb_sim.scenario_files import resolve_scenario
from twsb_sim.timeline import CommandPoint

SHIPPED_SEQUENCES: tuple[str, ...] = ("house1_single", "house2_multi")
CLEARANCE_MARGIN_M = 0.15  # m, kept between the robot's disc and any obstacle
STOP_MARGIN_M = 0.9  # m, room kept ahead for tracking lag and the hard stop's overshoot
MIN_LEG_M = 1.2  # m, shortest leg worth driving
MAX_LEG_M = 4.5  # m
SPEEDS_MPS = (0.6, 1.0)  # m/s, range of the legs' top speeds (the paper's at most 1.0)
ACCEL_RAMP_S = 1.0  # s, from standstill to the leg's speed
TURN_RATE_RAD_S = 0.6  # rad/s, the paper's largest angular speed
TURN_RAMP_S = 0.5  # s
SETTLE_S = 2.5  # s, standing after a hard stop or a turn


@dataclasses.dataclass(frozen=True)
class SlamSequence:
    """One sequence of the experiment: a scenario and its house.

    Attributes:
        name: ``house1_single``, ``house2_multi`` or ``random_<seed>_hard_stops``.
        scenario: what to simulate.
        house: the house it runs in (built once, for the figures and the recording).
    """

    name: str
    scenario: Scenario
    house: House


def shipped_sequence(name: str) -> SlamSequence:
    """A shipped scenario file as a sequence (``house1_single``, ``house2_multi``, ...)."""

    scenario = load_scenario(resolve_scenario(name))
    choice = scenario.house
    house = make_house(choice.name) if choice.name is not None else random_house(choice.seed)
    return SlamSequence(scenario.name, scenario, house)


def _wrap(angle: float) -> float:
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


def hard_stop_sequence(house_seed: int, legs: int = 5) -> SlamSequence:
    """Hard stops in the random house ``house_seed``, planned to keep off the walls.

    The robot starts at the spawn pose with the longest lane ahead. Each leg turns in place
    to a heading along the house's axes (the first leg keeps the spawn heading), drives
    1.2-4.5 m at 0.6-1.0 m/s and stops hard; a leg is only driven where the obstacle
    footprints leave its length plus ``STOP_MARGIN_M`` free. All draws come from a
    generator seeded by ``house_seed``.

    Args:
        house_seed: the random house's seed (also seeds the plan).
        legs: how many hard-stop legs to plan (fewer when the house leaves no room).
    """
    house = random_house(house_seed)
    rng = np.random.default_rng(np.random.SeedSequence([house_seed, 0x5A]))
    obstacles = Obstacles(house.parts())
    spawn = max(range(len(house.spawn_poses)), key=lambda k: house.spawn_poses[k].clear_ahead_m)
    start = house.spawn_poses[spawn]
    xy, yaw = np.array([start.x_m, start.y_m]), start.yaw_rad
    t_s, commands = 1.0, []
    for leg in range(legs):
        headings = yaw + np.array([0.0, math.pi / 2, -math.pi / 2, math.pi])
        clear = obstacles.clearance_m(
            np.repeat(xy[None], 4, axis=0), headings, ROBOT_RADIUS_M + CLEARANCE_MARGIN_M
        )
        usable = np.minimum(clear - STOP_MARGIN_M, MAX_LEG_M)
        choices = np.flatnonzero(usable >= MIN_LEG_M)
        if choices.size == 0:
            break
        pick = 0 if leg == 0 and 0 in choices else int(rng.choice(choices))
        turn = _wrap(float(headings[pick] - yaw))
        if abs(turn) > 1e-9:
            rate = math.copysign(TURN_RATE_RAD_S, turn)
            # with equal ramps up and down, the turned angle is rate * (end - start)
            commands.append(CommandPoint(t_s, 0.0, rate, TURN_RAMP_S, "turn"))
            t_s += abs(turn) / TURN_RATE_RAD_S
            commands.append(CommandPoint(t_s, 0.0, 0.0, TURN_RAMP_S, "stand"))
            t_s += TURN_RAMP_S + SETTLE_S / 2
            yaw = _wrap(yaw + turn)
        distance = float(rng.uniform(MIN_LEG_M, usable[pick]))
        speed = float(rng.uniform(*SPEEDS_MPS))
        # commanded distance: half the ramp at the mean speed, then cruise
        cruise_s = max(distance / speed - ACCEL_RAMP_S / 2, 0.0)
        commands.append(CommandPoint(t_s, speed, 0.0, ACCEL_RAMP_S, "accelerate"))
        t_s += ACCEL_RAMP_S + cruise_s
        commands.append(CommandPoint(t_s, 0.0, 0.0, 0.0, "hard stop"))
        t_s += SETTLE_S
        xy = xy + distance * np.array([math.cos(yaw), math.sin(yaw)])
    name = f"random_{house_seed}_hard_stops"
    scenario = Scenario(
        name=name,
        description=f"{len([c for c in commands if c.label == 'hard stop'])} hard stops "
        f"along the free lanes of random house {house_seed}.",
        duration_s=round(t_s + 1.0, 3),
        house=HouseChoice(name=None, seed=house_seed, spawn=spawn),
        commands=tuple(commands),
        source=f"<hard_stop_sequence({house_seed})>",
    )
    return SlamSequence(name, scenario, house)
