"""Simulate a sequence once and keep its frames: every filter and SLAM system then runs
on the same data."""

from __future__ import annotations

from twsb_sim.frame import Frame
from twsb_sim.runner import run_scenario
from twsb_sim.scenario import Scenario
from twsb_sim.sinks import NullSink
from twsb_sim.summary import RunSummary


class FrameCollector(NullSink):
    """A sink that keeps every frame of a run."""

    def __init__(self) -> None:
        self.frames: list[Frame] = []

    def on_frame(self, frame: Frame, filter_result: object) -> None:
        self.frames.append(frame)


def record_frames(scenario: Scenario, seed: int) -> tuple[list[Frame], RunSummary]:
    """Simulate ``scenario`` with ``seed`` (no filter in the loop); its frames and summary."""
    collector = FrameCollector()
    summary = run_scenario(scenario, seed=seed, sinks=[collector])
    return collector.frames, summary
