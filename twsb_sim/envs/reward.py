"""The reward of the environments' task: track a velocity command, stay upright and calm.

Every term is a rate per simulated second, multiplied by the step's duration, so the
return of an episode does not depend on the control period (a 20 s episode that tracks
perfectly and never pitches returns about ``20 * (velocity + yaw_rate)``). Each weighted
term is reported in ``info`` as ``reward_<name>``, and they sum to the reward::

    reward_velocity   =  velocity   * exp(-(v - v_target)^2 / velocity_scale^2) * dt
    reward_yaw_rate   =  yaw_rate   * exp(-(w - w_target)^2 / yaw_rate_scale^2) * dt
    reward_pitch      = -pitch      * pitch^2 * dt
    reward_pitch_rate = -pitch_rate * pitch_rate^2 * dt
    reward_torque     = -torque     * sum((tau / tau_max)^2) * dt
    reward_fall       = -fall       (once, on the step the robot falls)

The tracking terms are bounded kernels (as in legged-robot locomotion rewards), so a
large error is not punished without limit and the fall penalty stays the worst outcome.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from twsb_sim.envs.options import check_non_negative

REWARD_TERMS = ("velocity", "yaw_rate", "pitch", "pitch_rate", "torque", "fall")


@dataclass(frozen=True)
class RewardConfig:
    """Weights of the reward terms (see the module docstring for the formulas)."""

    velocity: float = 1.0  # 1/s, weight of the forward-velocity tracking kernel
    velocity_scale_mps: float = 0.25  # m/s, error at which that kernel falls to 1/e
    yaw_rate: float = 0.5  # 1/s, weight of the yaw-rate tracking kernel
    yaw_rate_scale_rad_s: float = 0.25  # rad/s, error at which that kernel falls to 1/e
    pitch: float = 1.0  # 1/(rad²·s), penalty on pitch away from upright
    pitch_rate: float = 0.05  # 1/((rad/s)²·s), penalty on pitch rate
    torque: float = 0.01  # 1/s, penalty on the squared wheel torques as fractions of the limit
    fall: float = 10.0  # one-off penalty when the robot falls

    def __post_init__(self) -> None:
        check_non_negative(self)
        for name in ("velocity_scale_mps", "yaw_rate_scale_rad_s"):
            if getattr(self, name) == 0:
                raise ValueError(f"{name}: expected a value > 0, got 0")


def reward_terms(
    config: RewardConfig,
    dt_s: float,
    velocity_error_mps: float,
    yaw_rate_error_rad_s: float,
    pitch_rad: float,
    pitch_rate_rad_s: float,
    torque_fractions: np.ndarray,
    fell: bool,
) -> dict[str, float]:
    """The weighted reward terms of one step, keyed ``reward_<name>``; their sum is the reward.

    Args:
        config: the weights.
        dt_s: duration of the step, s.
        velocity_error_mps: forward velocity minus its target, m/s.
        yaw_rate_error_rad_s: yaw rate minus its target, rad/s.
        pitch_rad, pitch_rate_rad_s: the body's pitch and pitch rate at the step's end.
        torque_fractions: wheel torques divided by the motor limit, (2,).
        fell: whether the robot fell during this step.
    """
    c = config
    velocity_kernel = math.exp(-((velocity_error_mps / c.velocity_scale_mps) ** 2))
    yaw_rate_kernel = math.exp(-((yaw_rate_error_rad_s / c.yaw_rate_scale_rad_s) ** 2))
    torque_square = float(np.dot(torque_fractions, torque_fractions))
    return {
        "reward_velocity": c.velocity * velocity_kernel * dt_s,
        "reward_yaw_rate": c.yaw_rate * yaw_rate_kernel * dt_s,
        "reward_pitch": -c.pitch * pitch_rad**2 * dt_s,
        "reward_pitch_rate": -c.pitch_rate * pitch_rate_rad_s**2 * dt_s,
        "reward_torque": -c.torque * torque_square * dt_s,
        "reward_fall": -c.fall if fell else 0.0,
    }
