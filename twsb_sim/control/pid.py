"""A cascaded PID balance controller, as low-cost self-balancing robots run.

The outer loop turns the velocity error into a lean (``pitch_ref``, clipped); the inner
loop drives the wheels under the body to reach it (a PD on pitch). It is softer than the
LQR (its gains are hand-set, not designed on the model), so the robot pitches more for
the same disturbance and recovers more slowly. Like :class:`~twsb_sim.control.lqr.
LqrController` it runs every physics step as one compiled function
(:mod:`twsb_sim.kernel`), and its integrators pause while a motor saturates.
"""

from __future__ import annotations

import mujoco
import numpy as np

from twsb_sim.control.balance import BalanceConfig, ControlFunction
from twsb_sim.control.compiled import compiled_control
from twsb_sim.kernel import kernel
from twsb_sim.robot import RobotHandles, balance_state


class PidController:
    """Balances the robot and tracks forward-velocity and yaw-rate commands with PIDs.

    Args:
        model: a compiled model holding the robot.
        config: the gains (``pid_*`` fields).
    """

    def __init__(self, model: mujoco.MjModel, config: BalanceConfig) -> None:
        self.handles = RobotHandles(model)
        self.config = config
        self._limit = self.handles.torque_limit_nm
        self._dt = float(model.opt.timestep)
        self._bound_data: mujoco.MjData | None = None  # the data self._control is bound to
        self._integrals = np.zeros(2)
        self.reset()

    def reset(self) -> None:
        """Forget the integrated errors."""
        self.last_pitch_rad = 0.0
        # m and rad: the integrated velocity and yaw-rate errors, which the compiled
        # control function updates in place
        self._integrals[:] = 0.0

    def apply(
        self,
        data: mujoco.MjData,
        velocity_command_mps: float = 0.0,
        yaw_rate_command_rad_s: float = 0.0,
    ) -> tuple[float, float]:
        """Compute and write this step's wheel torques (N·m, saturated)."""
        return self.bind(data)(velocity_command_mps, yaw_rate_command_rad_s)

    def bind(self, data: mujoco.MjData) -> ControlFunction:
        """:meth:`apply` bound to ``data``, the gains and ``data``'s arrays looked up once
        (the physics loop calls it every step)."""
        if data is not self._bound_data:
            self._bound_data, self._control = data, self._control_function(data)
        return self._control

    def _control_function(self, data: mujoco.MjData) -> ControlFunction:
        c = self.config
        gains = np.array(
            [
                c.pid_kv_rad_s_per_m, c.pid_ki_rad_per_m, c.pid_max_lean_rad,
                c.pid_kp_nm_per_rad, c.pid_kd_nm_s_per_rad, c.pid_kw_nm_s_per_rad,
                c.pid_kwi_nm_per_rad, self._dt, self._limit,
            ]
        )  # fmt: skip
        return compiled_control(self, data, self.handles, _pid_torques, gains, self._integrals)


@kernel
def _pid_torques(
    quat: np.ndarray,
    qvel: np.ndarray,
    ctrl: np.ndarray,
    addresses: np.ndarray,
    gains: np.ndarray,
    integrals: np.ndarray,
    velocity_command_mps: float,
    yaw_rate_command_rad_s: float,
) -> tuple[float, float, float]:
    """One step of the cascaded PID: write the wheel torques to ``ctrl``, update
    ``integrals`` (velocity error, m; yaw-rate error, rad).

    ``addresses``: the free joint's first dof, the wheels' dofs, the two motors' ids;
    ``gains``: kv, ki, the lean limit, kp, kd, kw, kwi, dt (s), the torque limit (N·m).
    Returns the left and right torques (N·m, saturated) and the pitch read (rad).
    """
    b, left_dof, right_dof, left_id, right_id = (
        addresses[0], addresses[1], addresses[2], addresses[3], addresses[4]
    )  # fmt: skip
    state = balance_state(quat, qvel, b, left_dof, right_dof)
    pitch, pitch_rate, forward_velocity, yaw_rate = state[0], state[1], state[2], state[4]
    kv, ki, max_lean, kp, kd = gains[0], gains[1], gains[2], gains[3], gains[4]
    kw, kwi, dt, limit = gains[5], gains[6], gains[7], gains[8]
    velocity_error = velocity_command_mps - forward_velocity
    yaw_rate_error = yaw_rate_command_rad_s - yaw_rate
    lean = kv * velocity_error + ki * integrals[0]
    # max(-max_lean, min(max_lean, lean)) as Python's min and max pick among equals
    lean = lean if lean < max_lean else max_lean
    lean = lean if lean > -max_lean else -max_lean
    common = kp * (pitch - lean) + kd * pitch_rate
    differential = kw * yaw_rate_error + kwi * integrals[1]
    left, right = common - differential, common + differential
    if -limit < left < limit and -limit < right < limit:
        integrals[0] += dt * velocity_error
        integrals[1] += dt * yaw_rate_error
    else:
        left = left if left < limit else limit
        left = left if left > -limit else -limit
        right = right if right < limit else limit
        right = right if right > -limit else -limit
    ctrl[left_id] = left
    ctrl[right_id] = right
    return left, right, pitch
