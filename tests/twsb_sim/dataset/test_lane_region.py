"""An episode's collision region: its lane with room to spare; an episode whose robot
leaves it is simulated again, and the data set does not change either way."""

from __future__ import annotations

import math

import numpy as np
import pytest

import twsb_sim.dataset.episode as episode_module
from twsb_sim.collision_region import CollisionRegion, LeftCollisionRegion, RegionGuard
from twsb_sim.dataset.episode import run_episode
from twsb_sim.dataset.lane_region import HEADROOM_M, LANE_SLACK_M, lane_region
from twsb_sim.dataset.motion import Lane


def test_the_region_is_the_lane_grown_by_the_slack():
    region = lane_region((1.0, 2.0, math.pi / 2), Lane(behind_m=0.5, ahead_m=3.0), 0.3)
    guard = RegionGuard(region)
    slack = LANE_SLACK_M - 1e-6
    inside = np.array([[1.0, 2.0, 0.3], [1.0, 5.0 + slack, 0.3], [1.0 - slack, 1.5, 0.0]])
    guard.check(inside)  # ahead is +y here; the slack holds on every side
    assert region.upper_m[2] == 0.3 + HEADROOM_M
    for outside in ([1.0, 5.0 + LANE_SLACK_M + 0.01, 0.3], [2.0 + LANE_SLACK_M, 2.0, 0.3]):
        with pytest.raises(LeftCollisionRegion):
            guard.check(np.array([outside]))


def test_an_episode_that_leaves_its_region_is_simulated_again_the_same(short_settings, monkeypatch):
    ranges = short_settings.randomization
    reference = run_episode(5, 1, ranges)
    runs: list[str] = []

    def tiny(start, lane, lidar_height_m):  # the robot leaves this at its first drive
        x, y, yaw = start
        return CollisionRegion((x, y, 0.0), yaw, (-0.2, -0.2, -1.0), (0.2, 0.2, 1.0))

    def run_scenario(*args, **kwargs):
        try:
            summary = original(*args, **kwargs)
        except LeftCollisionRegion:
            runs.append("left")
            raise
        runs.append("confined" if kwargs.get("collision_region") else "full")
        return summary

    original = episode_module.run_scenario
    monkeypatch.setattr(episode_module, "lane_region", tiny)
    monkeypatch.setattr(episode_module, "run_scenario", run_scenario)
    again = run_episode(5, 1, ranges)
    assert runs == ["left", "full"]
    assert again.table.equals(reference.table)
    assert again.summary == reference.summary
