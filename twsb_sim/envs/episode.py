"""What the environment tracks within one episode: its state, falls, and the ``info``."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np

from twsb_sim.frame import Frame, RobotTruth
from twsb_sim.simulation import Simulation

_UNSTABLE_WARNINGS = (mujoco.mjtWarning.mjWARN_BADQACC, mujoco.mjtWarning.mjWARN_BADQPOS)


@dataclass
class EpisodeState:
    """The mutable state of one episode (physics steps counted from its reset)."""

    target: tuple[float, float]  # (m/s, rad/s), the task's velocity and yaw-rate target
    step: int = 0  # physics steps since reset
    shove_end_step: int | None = None  # when the active shove ends, None when none is on
    hard_stop_end_step: int | None = None  # when the active hard stop ends
    frame: Frame | None = None  # the latest scan with its ground truth
    filter_result: Any | None = None  # the filter's result for that scan
    frames: int = 0  # scans taken
    fall_reason: str = ""  # why the robot fell, "" while it stands

    @property
    def hard_stop_active(self) -> bool:
        return self.hard_stop_end_step is not None

    @property
    def effective_target(self) -> tuple[float, float]:
        """The target in force: zero during a hard stop."""
        return (0.0, 0.0) if self.hard_stop_active else self.target


def fall_reason(
    truth: RobotTruth, data: mujoco.MjData, fall_pitch_rad: float, fall_roll_rad: float
) -> str:
    """Why the robot counts as fallen now, or "" when it does not.

    Args:
        truth: the robot's state now.
        data: the simulation state (for MuJoCo's instability warnings).
        fall_pitch_rad, fall_roll_rad: the limits on |pitch| and |roll|.
    """
    if any(data.warning[w].number > 0 for w in _UNSTABLE_WARNINGS) or not np.all(
        np.isfinite(truth.position_base_in_world)
    ):
        return "unstable: the physics diverged"
    if abs(truth.pitch_rad) > fall_pitch_rad:
        return (
            f"pitch: |pitch| {abs(math.degrees(truth.pitch_rad)):.1f} deg"
            f" > {math.degrees(fall_pitch_rad):g} deg"
        )
    if abs(truth.roll_rad) > fall_roll_rad:
        return (
            f"roll: |roll| {abs(math.degrees(truth.roll_rad)):.1f} deg"
            f" > {math.degrees(fall_roll_rad):g} deg"
        )
    return ""


def step_info(
    episode: EpisodeState, truth: RobotTruth, sim: Simulation, with_filter: bool
) -> dict[str, Any]:
    """The ``info`` of a reset or a step (without the reward terms): ground truth of the
    latest scan and of the robot now, each array a new copy."""
    frame = episode.frame
    info: dict[str, Any] = {
        "time_s": sim.time_s,
        "house": sim.house.name,
        "pose_world": np.array([*truth.position_base_in_world[:2], truth.yaw_rad]),
        "pitch_rad": truth.pitch_rad,
        "roll_rad": truth.roll_rad,
        "pitch_rate_rad_s": truth.pitch_rate_rad_s,
        "forward_velocity_mps": truth.forward_velocity_mps,
        "yaw_rate_rad_s": truth.yaw_rate_rad_s,
        "labels": frame.labels.copy(),
        "scan_ranges_m": frame.scan.ranges.copy(),
        "scan_stamp_s": frame.stamp_s,
        "shove_active": episode.shove_end_step is not None,
        "hard_stop_active": episode.hard_stop_active,
        "fall_reason": episode.fall_reason,
    }
    if with_filter:
        info["filter_removed"] = np.array(episode.filter_result.removed, dtype=bool)
    return info
