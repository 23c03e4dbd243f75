"""Training and held-out runs for ``twsb tune``: random episodes, simulated once.

Episodes are drawn as ``twsb generate`` draws them (:mod:`twsb_sim.dataset.episode`):
random house, start, robot within the ranges, commands and shoves, all from
``(seed, episode)``. The training episodes and the held-out ones come from two different
data-set seeds, so the held-out houses, robots, motions and LiDAR noise were never seen
while fitting; a held-out episode in a house the training episodes used is skipped.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator

import numpy as np

from pvfilter import Scan
from twsb_sim.dataset.episode import draw_episode
from twsb_sim.dataset.randomization import Randomization
from twsb_sim.filter_args import robot_geometry
from twsb_sim.frame import Frame
from twsb_sim.labels import BeamLabel, is_pitch_variation, with_label
from twsb_sim.runner import run_scenario
from twsb_sim.scenario import scenario_from_table
from twsb_sim.sinks import NullSink


@dataclasses.dataclass(frozen=True, eq=False)
class TuningRun:
    """What the objective needs of one simulated episode.

    Attributes:
        name: ``<data-set seed>/<episode>`` and the house.
        house: the house's name.
        scans: the scans, in time order.
        positive: per scan, bool per beam: a pitch-variation point with a finite range.
        finite: per scan, bool per beam: the range is finite (what the counts run over).
        static: per scan, bool per beam: a STATIC beam with a finite range.
        attitude: per scan, the robot's attitude estimate (pitch, roll) at the stamp, rad:
            what its IMU and filter give, lag and errors included.
        geometry: the robot's geometry as filters take it
            (:func:`twsb_sim.filter_args.robot_geometry`, m).
    """

    name: str
    house: str
    scans: tuple[Scan, ...]
    positive: np.ndarray
    finite: np.ndarray
    static: np.ndarray
    attitude: np.ndarray
    geometry: dict[str, float]


class _Collect(NullSink):
    def __init__(self) -> None:
        self.frames: list[Frame] = []

    def on_frame(self, frame: Frame, filter_result: object) -> None:
        self.frames.append(frame)


def simulate_episode(seed: int, episode: int, ranges: Randomization) -> TuningRun:
    """Draw and simulate one episode (as ``twsb generate`` would) and keep what tuning needs."""
    draw = draw_episode(seed, episode, ranges)
    scenario = scenario_from_table(draw.scenario_table, source=f"episode {episode}")
    collect = _Collect()
    run_scenario(scenario, seed=scenario.seed, sinks=[collect])
    frames = collect.frames
    # scored beams: a finite range, not on a moving object (neither hit nor false alarm)
    finite = np.array(
        [np.isfinite(f.scan.ranges) & ~with_label(f.labels, BeamLabel.DYNAMIC) for f in frames]
    )
    return TuningRun(
        name=f"{seed}/{episode}",
        house=draw.house.name,
        scans=tuple(f.scan for f in frames),
        positive=np.array([is_pitch_variation(f.labels) for f in frames]) & finite,
        finite=finite,
        static=np.array([with_label(f.labels, BeamLabel.STATIC) for f in frames]) & finite,
        attitude=np.array([f.attitude_estimate for f in frames]),
        geometry=robot_geometry(scenario),
    )


def episodes(
    seed: int, count: int, ranges: Randomization, avoid_houses: frozenset[str] = frozenset()
) -> Iterator[TuningRun]:
    """``count`` simulated episodes of data-set ``seed``, skipping houses in ``avoid_houses``."""
    made, episode = 0, 0
    while made < count:
        if draw_episode(seed, episode, ranges).house.name not in avoid_houses:
            yield simulate_episode(seed, episode, ranges)
            made += 1
        episode += 1
