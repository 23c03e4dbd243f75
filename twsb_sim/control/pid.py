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

from twsb_sim.control.balance import BalanceConfig, ControlFunction
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
        self._limit = self.handles.torque_limit_nm
        self._left_id, self._right_id = self.handles.actuator_ids
        self._dt = float(model.opt.timestep)
        self._bound_data: mujoco.MjData | None = None  # the data self._control is bound to
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
        return self.bind(data)(velocity_command_mps, yaw_rate_command_rad_s)

    def bind(self, data: mujoco.MjData) -> ControlFunction:
        """:meth:`apply` bound to ``data``, the gains and ``data``'s arrays looked up once
        (the physics loop calls it every step)."""
        if data is not self._bound_data:
            self._bound_data, self._control = data, self._control_function(data)
        return self._control

    def _control_function(self, data: mujoco.MjData) -> ControlFunction:
        c, read, ctrl = self.config, self.handles.state_reader(data), data.ctrl
        kv, ki, max_lean = c.pid_kv_rad_s_per_m, c.pid_ki_rad_per_m, c.pid_max_lean_rad
        kp, kd, kw, kwi = (
            c.pid_kp_nm_per_rad,
            c.pid_kd_nm_s_per_rad,
            c.pid_kw_nm_s_per_rad,
            c.pid_kwi_nm_per_rad,
        )
        dt, limit, left_id, right_id = self._dt, self._limit, self._left_id, self._right_id

        def control(
            velocity_command_mps: float, yaw_rate_command_rad_s: float
        ) -> tuple[float, float]:
            pitch, pitch_rate, forward_velocity, _, yaw_rate, _, _, _ = read()
            self.last_pitch_rad = pitch
            velocity_error = velocity_command_mps - forward_velocity
            yaw_rate_error = yaw_rate_command_rad_s - yaw_rate
            lean = kv * velocity_error + ki * self.velocity_error_integral_m
            lean = max(-max_lean, min(max_lean, lean))
            common = kp * (pitch - lean) + kd * pitch_rate
            differential = kw * yaw_rate_error + kwi * self.yaw_rate_error_integral_rad
            left, right = common - differential, common + differential
            if -limit < left < limit and -limit < right < limit:
                self.velocity_error_integral_m += dt * velocity_error
                self.yaw_rate_error_integral_rad += dt * yaw_rate_error
            else:
                left = max(-limit, min(limit, left))
                right = max(-limit, min(limit, right))
            ctrl[left_id] = left
            ctrl[right_id] = right
            return left, right

        return control
