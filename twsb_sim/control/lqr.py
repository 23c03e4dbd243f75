"""The LQR balance controller: forward-velocity and yaw-rate tracking on a TWSB robot.

The gains come from :func:`twsb_sim.control.gains.compute_gains`, designed on the
linearization of the MJCF model itself (see :mod:`twsb_sim.control.linearization`).
:meth:`LqrController.apply` runs every physics step: the state is read and the torques
computed in one compiled function (:mod:`twsb_sim.kernel`), which the function
:meth:`LqrController.bind` returns calls with everything looked up once.
"""

from __future__ import annotations

from collections.abc import Callable

import mujoco
import numpy as np

from twsb_sim.control.compiled import compiled_control
from twsb_sim.control.gains import LqrConfig, compute_gains
from twsb_sim.kernel import kernel
from twsb_sim.robot import RobotConfig, RobotHandles, balance_state


class LqrController:
    """Balances the robot and tracks forward-velocity and yaw-rate commands.

    Call :meth:`apply` once per physics step, before ``mj_step``. The integrators of the
    tracking errors stop while a motor saturates (anti-windup).
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        robot_config: RobotConfig | None = None,
        config: LqrConfig | None = None,
    ) -> None:
        """Resolve the robot in ``model`` and design (or fetch cached) gains.

        Args:
            model: a compiled model holding the robot built from ``robot_config``.
            robot_config: the robot's parameters, used to linearize it (default: the
                defaults of :class:`RobotConfig`).
            config: the LQR weights (default: the defaults of :class:`LqrConfig`).

        Raises:
            ValueError: if ``model`` does not match ``robot_config``.
            UnstableClosedLoopError: if the gains do not stabilize the robot.
        """
        robot_config = robot_config if robot_config is not None else RobotConfig()
        config = config if config is not None else LqrConfig()
        handles = RobotHandles(model)
        for name, in_model, in_config in (
            ("wheel_torque_limit_nm", handles.torque_limit_nm, robot_config.wheel_torque_limit_nm),
            ("wheel_radius_m", handles.wheel_radius_m, robot_config.wheel_radius_m),
        ):
            if abs(in_model - in_config) > 1e-9:
                raise ValueError(f"{name}: the model has {in_model}, the config {in_config}")
        self.gains = compute_gains(robot_config, config)
        if abs(self.gains.dt - model.opt.timestep) > 1e-12:
            raise ValueError(
                f"timestep: gains designed for {self.gains.dt} s, the model steps "
                f"{model.opt.timestep} s"
            )
        self.handles = handles
        self._k = self.gains.sagittal
        self._k_yaw = self.gains.yaw
        self._ff_velocity = self.gains.velocity_feedforward
        self._ff_yaw_rate = self.gains.yaw_rate_feedforward
        self._dt = self.gains.dt
        self._limit = handles.torque_limit_nm
        self._bound_data: mujoco.MjData | None = None  # the data self._control is bound to
        self._integrals = np.zeros(2)
        self.reset()

    def reset(self) -> None:
        """Forget the integrated tracking errors (a new run)."""
        self.last_pitch_rad = 0.0  # rad, pitch read by the latest apply()
        # m and rad: the integrated velocity and yaw-rate errors, which the compiled
        # control function updates in place
        self._integrals[:] = 0.0

    def apply(
        self,
        data: mujoco.MjData,
        velocity_command_mps: float = 0.0,
        yaw_rate_command_rad_s: float = 0.0,
    ) -> tuple[float, float]:
        """Compute the wheel torques for this physics step and write them to ``data.ctrl``.

        Args:
            data: the simulation state (reads ``qpos``, ``qvel``; writes ``ctrl``).
            velocity_command_mps: forward velocity wanted, m/s.
            yaw_rate_command_rad_s: yaw rate wanted, rad/s, counter-clockwise positive.

        Returns:
            ``(left, right)`` wheel torques in N·m, saturated at the motor limit.
        """
        return self.bind(data)(velocity_command_mps, yaw_rate_command_rad_s)

    def bind(self, data: mujoco.MjData) -> Callable[[float, float], tuple[float, float]]:
        """:meth:`apply` bound to ``data``: ``control(velocity, yaw_rate)``.

        The gains, limits, ``data``'s arrays and the state reader are bound once, as
        local names of the function: the physics loop calls it every 2 ms step, and it
        runs in about 60 % of the time of an ``apply`` that looks them all up per call.
        """
        if data is not self._bound_data:
            self._bound_data, self._control = data, self._control_function(data)
        return self._control

    def _control_function(
        self, data: mujoco.MjData
    ) -> Callable[[float, float], tuple[float, float]]:
        (k0, k1, k2, k3), (ky0, ky1) = self._k, self._k_yaw
        gains = np.array(
            [k0, k1, k2, k3, ky0, ky1, self._ff_velocity, self._ff_yaw_rate, self._dt, self._limit]
        )
        return compiled_control(self, data, self.handles, _lqr_torques, gains, self._integrals)


@kernel
def _lqr_torques(
    quat: np.ndarray,
    qvel: np.ndarray,
    ctrl: np.ndarray,
    addresses: np.ndarray,
    gains: np.ndarray,
    integrals: np.ndarray,
    velocity_command_mps: float,
    yaw_rate_command_rad_s: float,
) -> tuple[float, float, float]:
    """One step of the LQR: write the wheel torques to ``ctrl``, update ``integrals``.

    Args:
        quat, qvel, ctrl: the base's orientation (a view of ``qpos``), ``qvel``, ``ctrl``.
        addresses: the free joint's first dof, the wheels' dofs, the two motors' ids.
        gains: k0..k3 (pitch, pitch rate, velocity error, its integral), the yaw-rate
            error's and its integral's, the two feed-forwards, dt (s), the limit (N·m).
        integrals: the integrated velocity error (m) and yaw-rate error (rad).

    Returns:
        The left and right torques (N·m, saturated) and the pitch read (rad).
    """
    b, left_dof, right_dof, left_id, right_id = (
        addresses[0], addresses[1], addresses[2], addresses[3], addresses[4]
    )  # fmt: skip
    state = balance_state(quat, qvel, b, left_dof, right_dof)
    pitch, pitch_rate, forward_velocity, yaw_rate = state[0], state[1], state[2], state[4]
    k0, k1, k2, k3, ky0, ky1 = gains[0], gains[1], gains[2], gains[3], gains[4], gains[5]
    ff_velocity, ff_yaw_rate, dt, limit = gains[6], gains[7], gains[8], gains[9]
    velocity_error = forward_velocity - velocity_command_mps
    yaw_rate_error = yaw_rate - yaw_rate_command_rad_s
    common = ff_velocity * velocity_command_mps - (
        k0 * pitch + k1 * pitch_rate + k2 * velocity_error + k3 * integrals[0]
    )
    differential = ff_yaw_rate * yaw_rate_command_rad_s - (
        ky0 * yaw_rate_error + ky1 * integrals[1]
    )
    left = common - differential
    right = common + differential
    if -limit < left < limit and -limit < right < limit:
        integrals[0] += dt * velocity_error
        integrals[1] += dt * yaw_rate_error
    else:
        left = limit if left > limit else (-limit if left < -limit else left)
        right = limit if right > limit else (-limit if right < -limit else right)
    ctrl[left_id] = left
    ctrl[right_id] = right
    return left, right, pitch
