"""Simulate a sequence once and keep its frames: every method then runs on the same data.

A :class:`Recording` is one (sequence, house, seed) run: its frames, the names of the
geoms the beams can hit (so a false alarm can say it hit a door frame), and the robot's
LiDAR height (for the IMU height gate).
"""

from __future__ import annotations

import dataclasses

import mujoco

from twsb_sim.filter_args import robot_geometry
from twsb_sim.frame import Frame
from twsb_sim.house import House
from twsb_sim.runner import build_house, run_scenario, scenario_world
from twsb_sim.scenario import HouseChoice, Scenario, load_scenario
from twsb_sim.scenario_files import resolve_scenario
from twsb_sim.simulation import build_model
from twsb_sim.sinks import NullSink
from twsb_sim.summary import RunSummary


@dataclasses.dataclass(frozen=True, eq=False)
class Recording:
    """The frames of one simulated run, and what is needed to explain them.

    Attributes:
        sequence: scenario name (``normal_sequence``, ...).
        house: house name (``house1``, ``random_3``, ...).
        seed: the run's seed.
        frames: every LiDAR frame, in time order.
        geom_names: name of every geom of the run's model, indexed by geom id.
        geometry: the robot's geometry as filters take it
            (:func:`twsb_sim.filter_args.robot_geometry`: the scanner's height above the
            floor when upright, the axle's height it pitches about, how far ahead of the
            axle the scanner sits; m).
        summary: the run's summary (falls, pitch, label counts).
    """

    sequence: str
    house: str
    seed: int
    frames: tuple[Frame, ...]
    geom_names: tuple[str, ...]
    geometry: dict[str, float]
    summary: RunSummary

    @property
    def run_id(self) -> str:
        return f"{self.sequence}/{self.house}/seed{self.seed}"


class _Collect(NullSink):
    def __init__(self) -> None:
        self.frames: list[Frame] = []

    def on_frame(self, frame: Frame, filter_result: object) -> None:
        self.frames.append(frame)


def widest_lane_spawn(house: House) -> int:
    """Index of the spawn pose with the most room both ahead and behind.

    The sequences drive forward, turn around and drive back, so they want a long lane
    in both directions (house1's is spawn 3, the one the shipped sequences use).
    """
    lanes = [min(p.clear_ahead_m, p.clear_behind_m) for p in house.spawn_poses]
    return max(range(len(lanes)), key=lanes.__getitem__)


def sequence_in_house(
    sequence: str, house_name: str | None, house_seed: int | None, duration_s: float | None
) -> tuple[Scenario, House]:
    """A shipped sequence moved into another house (at its widest lane), optionally cut.

    Args:
        sequence: shipped scenario name.
        house_name: a named layout, or None for a random house.
        house_seed: the random house's seed (with ``house_name`` None).
        duration_s: keep only this many simulated seconds (commands and shoves that end
            later are dropped); None keeps the whole sequence.
    """

    scenario = load_scenario(resolve_scenario(sequence))
    choice = HouseChoice(name=house_name, seed=house_seed)
    house = build_house(choice)
    choice = dataclasses.replace(choice, spawn=widest_lane_spawn(house))
    scenario = dataclasses.replace(scenario, house=choice)
    if duration_s is not None and duration_s < scenario.duration_s:
        scenario = dataclasses.replace(
            scenario,
            duration_s=duration_s,
            commands=tuple(c for c in scenario.commands if c.t_s + c.ramp_s <= duration_s),
            shoves=tuple(s for s in scenario.shoves if s.end_s <= duration_s),
        )
    return scenario, house


def with_robot(scenario: Scenario, overrides: dict[str, dict[str, float]]) -> Scenario:
    """``scenario`` with a different robot: ``overrides`` holds tables ``robot``, ``lidar``
    and ``controller`` of field -> value (as in a scenario file)."""
    changes = {
        table: dataclasses.replace(getattr(scenario, table), **values)
        for table, values in overrides.items()
    }
    return dataclasses.replace(scenario, **changes)


def record(scenario: Scenario, house: House, seed: int, progress: bool = False) -> Recording:
    """Simulate ``scenario`` once (no filter in the loop) and keep every frame.

    Args:
        scenario: the run; ``house`` must be the house it asks for.
        house: its house (built once by the caller; its name names the recording).
        seed: the run's seed.
        progress: show the runner's progress bar.
    """
    collect = _Collect()
    summary = run_scenario(scenario, seed=seed, sinks=[collect], progress=progress)
    # the geoms the beams hit: the house with what the scenario adds, and its movers
    world, movers, _ = scenario_world(scenario)
    model = build_model(world, scenario.robot, movers)
    names = tuple(
        mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, i) or "" for i in range(model.ngeom)
    )
    return Recording(
        sequence=scenario.name,
        house=house.name,
        seed=seed,
        frames=tuple(collect.frames),
        geom_names=names,
        geometry=robot_geometry(scenario),
        summary=summary,
    )
