"""The physics loop's call into a compiled balance controller.

Both balance controllers (:mod:`twsb_sim.control.lqr`, :mod:`twsb_sim.control.pid`) run
one compiled kernel per 2 ms physics step. The kernel reads the base's orientation and
velocities from ``data``, writes the wheel torques to ``data.ctrl`` and updates the
controller's integrals in place; what differs between them is the kernel and its gains.
The arrays it works on are bound once, as local names of the function the loop calls.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol

import mujoco
import numpy as np

from twsb_sim.robot import RobotHandles

ControlFunction = Callable[[float, float], tuple[float, float]]


class PitchRecord(Protocol):
    """A controller that keeps the body pitch of its latest step."""

    last_pitch_rad: float


def compiled_control(
    controller: PitchRecord,
    data: mujoco.MjData,
    handles: RobotHandles,
    torques: Callable[..., tuple[float, float, float]],
    gains: np.ndarray,
    integrals: np.ndarray,
) -> ControlFunction:
    """``control(velocity m/s, yaw rate rad/s) -> (left, right)`` torques, N·m.

    Args:
        controller: where each step's body pitch goes (``last_pitch_rad``, rad).
        data: the simulation's data the kernel reads and writes.
        handles: the robot's addresses in the model.
        torques: the compiled kernel: ``(quat, qvel, ctrl, addresses, gains, integrals,
            velocity, yaw_rate) -> (left, right, pitch)``.
        gains: the kernel's gains and limits, in its order.
        integrals: the controller's integral states, updated in place.
    """
    h = handles
    quat, qvel, ctrl = data.qpos[h.qpos_adr + 3 : h.qpos_adr + 7], data.qvel, data.ctrl
    left_id, right_id = h.actuator_ids
    addresses = np.array([h.qvel_adr, *h.wheel_qvel_adr, left_id, right_id])

    def control(velocity_command_mps: float, yaw_rate_command_rad_s: float) -> tuple[float, float]:
        left, right, controller.last_pitch_rad = torques(
            quat, qvel, ctrl, addresses, gains, integrals,
            velocity_command_mps, yaw_rate_command_rad_s,
        )  # fmt: skip
        return left, right

    return control
