"""What the environment tracks within one episode, and how it decides that the robot fell."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np

from twsb_sim.frame import Frame, RobotTruth

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
            f"pitch: |pitch| {abs(math.degrees(truth.pitch_rad)):.0f} deg"
            f" > {math.degrees(fall_pitch_rad):.0f} deg"
        )
    if abs(truth.roll_rad) > fall_roll_rad:
        return (
            f"roll: |roll| {abs(math.degrees(truth.roll_rad)):.0f} deg"
            f" > {math.degrees(fall_roll_rad):.0f} deg"
        )
    return ""
