"""A stop brake in front of a balance controller: the motors brake the wheels first.

Many motor drivers stop a robot by braking its wheels when the velocity command falls
(a stop button, a planner's emergency stop). On a balancing robot the brake torque that
slows the wheels pushes the body forward by reaction, and the body keeps its momentum:
it pitches nose-down, towards the floor ahead, until the balance controller takes over
and drives the wheels under it again.

:class:`StopBrake` watches the velocity command: when it falls by more than
``brake_trigger_mps2 * dt`` within one physics step against the motion (a stop, or a
reversal), the wheels are braked
against their turning, up to ``brake_torque_nm`` (the motor limit at most), for
``brake_s`` (holding them once they have stopped, as a shorted motor does); then the
wrapped controller runs again, its state reset so its integrators do not carry what the
brake did.
"""

from __future__ import annotations

import mujoco

from twsb_sim.control.balance import (
    BalanceConfig,
    BalanceController,
    ControlFunction,
    bound_control,
)
from twsb_sim.robot import RobotHandles

# N·m·s/rad: a shorted motor's torque per rad/s of wheel spin relative to the body; small
# enough for the explicit torque to stay stable at the 2 ms physics step
BRAKE_DAMPING_NM_S = 0.5


class StopBrake:
    """Brakes the wheels on a falling velocity command, then hands back to ``inner``.

    Args:
        model: a compiled model holding the robot.
        inner: the balance controller.
        config: ``brake_torque_nm``, ``brake_s`` and ``brake_trigger_mps2``.
    """

    def __init__(
        self, model: mujoco.MjModel, inner: BalanceController, config: BalanceConfig
    ) -> None:
        handles = RobotHandles(model)
        self.inner = inner
        self._read = handles.read_balance_state
        self._left_id, self._right_id = handles.actuator_ids
        self._torque = min(config.brake_torque_nm, handles.torque_limit_nm)
        self._steps = max(1, round(config.brake_s / model.opt.timestep))
        self._drop = config.brake_trigger_mps2 * model.opt.timestep  # m/s per step
        self._bound_data: mujoco.MjData | None = None  # the data self._control is bound to
        self.reset()

    def reset(self) -> None:
        self.inner.reset()
        self.last_pitch_rad = 0.0
        self._previous_command = 0.0
        self._braking_steps = 0  # steps of braking left
        self.brakes = 0  # brake events since the reset

    def apply(
        self,
        data: mujoco.MjData,
        velocity_command_mps: float = 0.0,
        yaw_rate_command_rad_s: float = 0.0,
    ) -> tuple[float, float]:
        """Brake, or let the balance controller act."""
        return self.bind(data)(velocity_command_mps, yaw_rate_command_rad_s)

    def bind(self, data: mujoco.MjData) -> ControlFunction:
        """:meth:`apply` bound to ``data``, with the wrapped controller's own bound
        function (the physics loop calls it every step)."""
        if data is not self._bound_data:
            self._bound_data, self._control = data, self._control_function(data)
        return self._control

    def _control_function(self, data: mujoco.MjData) -> ControlFunction:
        inner, inner_control = self.inner, bound_control(self.inner, data)
        read, ctrl, left_id, right_id = self._read, data.ctrl, self._left_id, self._right_id
        drop, brake_steps, brake_torque = self._drop, self._steps, self._torque

        def control(
            velocity_command_mps: float, yaw_rate_command_rad_s: float
        ) -> tuple[float, float]:
            previous, self._previous_command = self._previous_command, velocity_command_mps
            # the command falls against the motion (a stop, or a reversal) faster than the
            # trigger
            falling = (previous - velocity_command_mps) * (1.0 if previous > 0 else -1.0) > drop
            if previous != 0.0 and falling and self._braking_steps == 0:
                self._braking_steps = brake_steps
                self.brakes += 1
            if self._braking_steps > 0:
                state = read(data)
                self.last_pitch_rad = state.pitch_rad
                self._braking_steps -= 1
                # the driver shorts the motors: a torque against the wheels' turning
                # relative to the body, saturating at the brake torque (a hold once they
                # have stopped)
                spin = 0.5 * (state.left_wheel_speed_rad_s + state.right_wheel_speed_rad_s)
                torque = max(-brake_torque, min(brake_torque, -BRAKE_DAMPING_NM_S * spin))
                ctrl[left_id] = torque
                ctrl[right_id] = torque
                if self._braking_steps == 0:
                    inner.reset()  # the brake's work is not a tracking error to integrate
                return torque, torque
            left, right = inner_control(velocity_command_mps, yaw_rate_command_rad_s)
            self.last_pitch_rad = inner.last_pitch_rad
            return left, right

        return control
