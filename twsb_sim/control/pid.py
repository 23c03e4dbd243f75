"""A cascaded PID balance controller, as low-cost self-balancing robots run.

The outer loop turns the velocity error into a lean (``pitch_ref``, clipped); the inner
loop drives the wheels under the body to reach it (a PD on pitch). It is softer than the
LQR (its gains are hand-set, not designed on the model), so the robot pitches more for
the same disturbance and recovers more slowly. Like :class:`~twsb_sim.control.lqr.
LqrController` it runs every physics step on scalars, and its integrators pause while a
motor saturates.
"""

from __future__ import annotations

import mujoco

from twsb_sim.control.balance import BalanceConfig
from twsb_sim.robot import RobotHandles


class PidController:
    """Balances the robot and tracks forward-velocity and yaw-rate commands with PIDs.

    Args:
        model: a compiled model holding the robot.
        config: the gains (``pid_*`` fields).
    """

    def __init__(self, model: mujoco.MjModel, config: BalanceConfig) -> None:
        self.handles = RobotHandles(model)
        self.config = config
        self._read = self.handles.read_balance_state
        self._limit = self.handles.torque_limit_nm
        self._left_id, self._right_id = self.handles.actuator_ids
        self._dt = float(model.opt.timestep)
        self.reset()

    def reset(self) -> None:
        """Forget the integrated errors."""
        self.last_pitch_rad = 0.0
        self.velocity_error_integral_m = 0.0  # m
        self.yaw_rate_error_integral_rad = 0.0  # rad

    def apply(
        self,
        data: mujoco.MjData,
        velocity_command_mps: float = 0.0,
        yaw_rate_command_rad_s: float = 0.0,
    ) -> tuple[float, float]:
        """Compute and write this step's wheel torques (N·m, saturated)."""
        c, s = self.config, self._read(data)
        self.last_pitch_rad = s.pitch_rad
        velocity_error = velocity_command_mps - s.forward_velocity_mps
        yaw_rate_error = yaw_rate_command_rad_s - s.yaw_rate_rad_s
        lean = c.pid_kv_rad_s_per_m * velocity_error + c.pid_ki_rad_per_m * (
            self.velocity_error_integral_m
        )
        lean = max(-c.pid_max_lean_rad, min(c.pid_max_lean_rad, lean))
        common = c.pid_kp_nm_per_rad * (s.pitch_rad - lean) + c.pid_kd_nm_s_per_rad * (
            s.pitch_rate_rad_s
        )
        differential = (
            c.pid_kw_nm_s_per_rad * yaw_rate_error
            + c.pid_kwi_nm_per_rad * self.yaw_rate_error_integral_rad
        )
        left, right = common - differential, common + differential
        limit = self._limit
        if -limit < left < limit and -limit < right < limit:
            self.velocity_error_integral_m += self._dt * velocity_error
            self.yaw_rate_error_integral_rad += self._dt * yaw_rate_error
        else:
            left = max(-limit, min(limit, left))
            right = max(-limit, min(limit, right))
        data.ctrl[self._left_id] = left
        data.ctrl[self._right_id] = right
        return left, right
