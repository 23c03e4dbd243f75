"""Which balance controller a robot runs, and whether its motors brake on a stop.

Two controllers keep the robot up: the LQR of :mod:`twsb_sim.control.lqr` (the default)
and the cascaded PID of :mod:`twsb_sim.control.pid`, the kind hobby and low-cost robots
run. Either can sit behind a **stop brake** (:mod:`twsb_sim.control.braking`): when the
velocity command falls fast, the motor driver brakes the wheels for a moment before the
balance controller takes over again. The two tip the body opposite ways on a hard stop:
the LQR first drives the wheels ahead to lean the body back (nose up, the floor behind
enters the scan), a brake stops the wheels and the body pitches nose-down into the floor
ahead (the paper's Fig. 1).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Literal, Protocol

import mujoco

from twsb_sim.control.gains import LqrConfig
from twsb_sim.robot import RobotConfig


class BalanceController(Protocol):
    """What the simulation loop calls every physics step."""

    last_pitch_rad: float  # the pitch read by the latest apply()

    def apply(
        self, data: mujoco.MjData, velocity_command_mps: float, yaw_rate_command_rad_s: float
    ) -> tuple[float, float]:
        """Write this step's wheel torques to ``data.ctrl``; return them (N·m)."""
        ...

    def reset(self) -> None:
        """Forget the controller's state (a new run)."""
        ...


ControlFunction = Callable[[float, float], tuple[float, float]]  # (v, w) -> (left, right) N·m


def bound_control(controller: BalanceController, data: mujoco.MjData) -> ControlFunction:
    """``controller.apply`` bound to ``data``: the function the controller's ``bind(data)``
    returns (everything it needs looked up once), or ``apply`` with ``data`` given."""
    bind = getattr(controller, "bind", None)
    return bind(data) if bind is not None else functools.partial(controller.apply, data)


def _check(name: str, value: float, low: float, high: float) -> None:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise ValueError(f"{name}: expected a number, got {value!r}")
    if not low <= value <= high:
        raise ValueError(f"{name}: expected {low:g} to {high:g}, got {value:g}")


@dataclass(frozen=True)
class BalanceConfig:
    """The balance controller and the stop brake (a scenario's ``[balance]`` table).

    The PID gains act as ``pitch_ref = clip(kv (v_cmd - v) + ki integral, max_lean)`` and
    ``torque = kp (pitch - pitch_ref) + kd pitch_rate`` (common to both wheels), with
    ``kw (w_cmd - w) + kwi integral`` as the differential torque for the yaw rate.
    """

    kind: Literal["lqr", "pid"] = "lqr"
    brake_torque_nm: float = 0.0  # N·m per wheel of the stop brake; 0 = no brake
    brake_s: float = 0.25  # s, how long the brake acts at most
    brake_trigger_mps2: float = 4.0  # m/s², a command falling faster than this brakes
    pid_kp_nm_per_rad: float = 16.0  # N·m per rad of pitch error
    pid_kd_nm_s_per_rad: float = 1.2  # N·m per rad/s of pitch rate
    pid_kv_rad_s_per_m: float = 0.12  # rad of lean per m/s of velocity error
    pid_ki_rad_per_m: float = 0.03  # rad of lean per m of integrated velocity error
    pid_max_lean_rad: float = 0.35  # rad, the lean the outer loop may ask for
    pid_kw_nm_s_per_rad: float = 0.6  # N·m per rad/s of yaw-rate error
    pid_kwi_nm_per_rad: float = 0.3  # N·m per rad of integrated yaw-rate error

    def __post_init__(self) -> None:
        if self.kind not in ("lqr", "pid"):
            raise ValueError(f"kind: expected 'lqr' or 'pid', got {self.kind!r}")
        _check("brake_torque_nm", self.brake_torque_nm, 0.0, 50.0)
        _check("brake_s", self.brake_s, 0.01, 2.0)
        _check("brake_trigger_mps2", self.brake_trigger_mps2, 0.1, 1000.0)
        for name in ("pid_kp_nm_per_rad", "pid_kd_nm_s_per_rad", "pid_kw_nm_s_per_rad"):
            _check(name, getattr(self, name), 0.01, 1000.0)
        for name in ("pid_kv_rad_s_per_m", "pid_ki_rad_per_m", "pid_kwi_nm_per_rad"):
            _check(name, getattr(self, name), 0.0, 100.0)
        _check("pid_max_lean_rad", self.pid_max_lean_rad, 0.01, 1.0)


def make_balance_controller(
    model: mujoco.MjModel,
    robot: RobotConfig,
    lqr: LqrConfig,
    balance: BalanceConfig | None = None,
) -> BalanceController:
    """The controller ``balance`` asks for, behind a stop brake when it has one."""
    from twsb_sim.control.braking import StopBrake
    from twsb_sim.control.lqr import LqrController
    from twsb_sim.control.pid import PidController

    balance = balance or BalanceConfig()
    inner: BalanceController = (
        LqrController(model, robot, lqr) if balance.kind == "lqr" else PidController(model, balance)
    )
    if balance.brake_torque_nm > 0.0:
        return StopBrake(model, inner, balance)
    return inner
