"""The survivable envelope of a robot: how hard it can be pushed and how far it can tilt.

Measured on the nonlinear MuJoCo model, physics only (no LiDAR), in an empty room:

- **tilt recovery**: the largest initial pitch (nose down and nose up, the robot at rest)
  from which it gets back up, by bisection;
- **shoves standing**: per direction (from behind, the front, the left, the right) and
  height above the axle, the largest push of ``SHOVE_DURATION_S`` it survives, by
  bisection on the force; reported as linear impulse (N·s), angular impulse about the
  axle (N·m·s) and the peak pitch (roll, from a side) it then reaches;
- **shoves driving**: the same from behind and the front while it drives at
  ``DRIVE_SPEED_MPS``;
- **hard stop**: the peak nose-down and nose-up pitch of a step from
  ``HARD_STOP_SPEED_MPS`` to rest.

"Survives" means |pitch| and |roll| stay below the fall limit for ``SETTLE_S`` after the
disturbance. The whole measurement is deterministic: no noise, no random draws.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from dataclasses import dataclass

import mujoco
import numpy as np

from twsb_sim.control.balance import BalanceConfig
from twsb_sim.control.gains import LqrConfig
from twsb_sim.house import Room
from twsb_sim.house.floorplan import assemble_house
from twsb_sim.robot import RobotConfig
from twsb_sim.simulation import Shove, Simulation
from twsb_sim.timeline import heading_force_to_world

SHOVE_DURATION_S = 0.1  # s
SETTLE_S = 3.0  # s, a robot still up this long after the push has survived it
DRIVE_SPEED_MPS = 0.8  # m/s
HARD_STOP_SPEED_MPS = 1.0  # m/s
DRIVE_SHOVE_AT_S = 2.5  # s, after the start of the drive (speed reached by then)
HEIGHTS_M = (0.15, 0.3, 0.45)  # m above the axle
DIRECTIONS: dict[str, tuple[float, float]] = {  # unit force in the heading frame
    "behind": (1.0, 0.0),  # pushes the robot forward
    "front": (-1.0, 0.0),
    "left": (0.0, -1.0),  # a push from the left moves it to its right
    "right": (0.0, 1.0),
}
MAX_FORCE_N = 1000.0  # N, the bisection's upper end
BISECTION_STEPS = 12
ARENA_M = 40.0  # m, side of the empty room the robot is pushed around in
CHECK_EVERY = 10  # physics steps between two fall checks (20 ms)


@dataclass(frozen=True)
class RobotUnderTest:
    """The robot whose envelope is measured (the tables of a scenario file)."""

    robot: RobotConfig = dataclasses.field(default_factory=RobotConfig)
    controller: LqrConfig = dataclasses.field(default_factory=LqrConfig)
    balance: BalanceConfig = dataclasses.field(default_factory=BalanceConfig)
    fall_deg: float = 45.0  # deg


@dataclass(frozen=True)
class ShoveLimit:
    """The largest survived push of one direction and height."""

    direction: str
    height_m: float
    force_n: float
    impulse_n_s: float
    angular_impulse_n_m_s: float
    peak_deg: float  # |pitch| (|roll| from a side) reached when pushed at the limit


class Bench:
    """One robot in an empty room, reset for every trial."""

    def __init__(self, under_test: RobotUnderTest) -> None:
        half = ARENA_M / 2
        room = Room("arena", -half, -half, half, half)
        house = assemble_house("arena", None, 3.0, [room], [], [])
        self.sim = Simulation(
            house, under_test.robot, controller=under_test.controller,
            fall_pitch_deg=under_test.fall_deg, balance=under_test.balance,
        )  # fmt: skip
        self.steps_per_s = round(1.0 / self.sim.dt_s)

    def _run(self, velocity: np.ndarray, shove_at: int | None = None, shove: Shove | None = None):
        """Run a command profile; returns (survived, peak |pitch| deg, peak |roll| deg)."""
        sim = self.sim
        sim.reset((0.0, 0.0, 0.0))
        shove_end = None
        if shove_at is not None:
            shove_end = shove_at + round(SHOVE_DURATION_S * self.steps_per_s)
        marks = sorted({0, len(velocity), *range(0, len(velocity), CHECK_EVERY)}
                       | ({shove_at, shove_end} - {None}))  # fmt: skip
        zeros = np.zeros(len(velocity))
        peak_roll = 0.0
        for k, k_next in itertools.pairwise(marks):
            if k == shove_at:
                sim.set_shove(shove)
            if k == shove_end:
                sim.set_shove(None)
            sim.run_commands(velocity[k:k_next], zeros[k:k_next])
            peak_roll = max(peak_roll, abs(sim.handles.read_balance_state(sim.data).roll_rad))
            if sim.has_fallen():
                return False, math.degrees(sim.max_abs_pitch_rad), math.degrees(peak_roll)
        return True, math.degrees(sim.max_abs_pitch_rad), math.degrees(peak_roll)

    def shove_trial(self, direction: str, height_m: float, force_n: float, driving: bool):
        fx, fy = DIRECTIONS[direction]
        force = heading_force_to_world((fx * force_n, fy * force_n, 0.0), 0.0)
        shove = Shove(force_world_n=force, point_body_m=np.array([0.0, 0.0, height_m]))
        if driving:
            ramp = np.minimum(
                np.arange(round((DRIVE_SHOVE_AT_S + SETTLE_S) * self.steps_per_s))
                / self.steps_per_s,
                1.0,
            )
            velocity = DRIVE_SPEED_MPS * ramp
            shove_at = round(DRIVE_SHOVE_AT_S * self.steps_per_s)
        else:
            velocity = np.zeros(round((0.2 + SETTLE_S) * self.steps_per_s))
            shove_at = round(0.2 * self.steps_per_s)
        return self._run(velocity, shove_at, shove)

    def tilt_trial(self, pitch_rad: float) -> bool:
        """Whether the robot recovers from rest at ``pitch_rad``."""
        sim = self.sim
        sim.reset((0.0, 0.0, 0.0))
        a = sim.handles.qpos_adr
        sim.data.qpos[a + 3 : a + 7] = [math.cos(pitch_rad / 2), 0.0, math.sin(pitch_rad / 2), 0.0]
        mujoco.mj_forward(sim.model, sim.data)
        zeros = np.zeros(CHECK_EVERY)
        for _ in range(round(SETTLE_S * self.steps_per_s) // CHECK_EVERY):
            sim.run_commands(zeros, zeros)
            if sim.has_fallen():
                return False
        return True


def _bisect(survives, low: float, high: float, steps: int = BISECTION_STEPS) -> float:
    """The largest value in [low, high] for which ``survives`` holds (monotone)."""
    if survives(high):
        return high
    for _ in range(steps):
        middle = 0.5 * (low + high)
        low, high = (middle, high) if survives(middle) else (low, middle)
    return low


def shove_limit(bench: Bench, direction: str, height_m: float, driving: bool = False) -> ShoveLimit:
    """The largest push of one direction and height the robot survives."""

    def survives(force_n: float) -> bool:
        return bench.shove_trial(direction, height_m, force_n, driving)[0]

    force = _bisect(survives, 0.0, MAX_FORCE_N)
    _, pitch, roll = bench.shove_trial(direction, height_m, force, driving)
    impulse = force * SHOVE_DURATION_S
    peak = roll if direction in ("left", "right") else pitch
    angular = impulse * height_m
    return ShoveLimit(
        direction, height_m, round(force, 2), round(impulse, 3), round(angular, 3), round(peak, 2)
    )


def tilt_limits_deg(bench: Bench) -> dict[str, float]:
    """The largest initial pitch (deg) it recovers from, nose down and nose up."""
    top = bench.sim.fall_pitch_rad
    return {
        "nose_down": round(math.degrees(_bisect(bench.tilt_trial, 0.0, top)), 2),
        "nose_up": round(math.degrees(_bisect(lambda p: bench.tilt_trial(-p), 0.0, top)), 2),
    }


def hard_stop_deg(bench: Bench) -> dict[str, float]:
    """Peak nose-down (+) and nose-up (-) pitch of a step from cruise to rest (deg)."""
    per_s = bench.steps_per_s
    t = np.arange(round(8.0 * per_s)) / per_s
    velocity = np.where(t < 4.0, HARD_STOP_SPEED_MPS * np.minimum(t / 1.5, 1.0), 0.0)
    sim, stop = bench.sim, round(4.0 * per_s)
    sim.reset((0.0, 0.0, 0.0))
    sim.run_commands(velocity[:stop], np.zeros(stop))
    pitches = []
    for v in velocity[stop:].tolist():
        sim.run_commands(np.array([v]), np.zeros(1))
        pitches.append(sim.handles.read_balance_state(sim.data).pitch_rad)
        if sim.has_fallen():
            break
    after = np.degrees(pitches)
    return {"nose_down": round(float(after.max()), 2), "nose_up": round(float(after.min()), 2),
            "fell": bool(sim.has_fallen())}  # fmt: skip


def measure_envelope(
    under_test: RobotUnderTest,
    heights_m: tuple[float, ...] = HEIGHTS_M,
    directions: tuple[str, ...] = tuple(DIRECTIONS),
    driving: bool = True,
    tilt: bool = True,
) -> dict:
    """The measurements of the module docstring for one robot, JSON-ready."""
    bench = Bench(under_test)
    standing = [dataclasses.asdict(shove_limit(bench, d, h)) for d in directions for h in heights_m]
    moving = []
    if driving:
        moving = [dataclasses.asdict(shove_limit(bench, d, 0.3, True)) for d in ("behind", "front")]
    return {
        "tilt_recovery_deg": tilt_limits_deg(bench) if tilt else None,
        "hard_stop_deg": hard_stop_deg(bench),
        "shoves_standing": standing,
        "shoves_driving": moving,
    }
