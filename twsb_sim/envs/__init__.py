"""Gymnasium environments of the TWSB robot with its labeled LiDAR (see the README).

Nothing is registered on import: call :func:`register`, then
``gymnasium.make("TwsbVelocity-v0")`` or ``gymnasium.make("TwsbTorque-v0")``.
"""

from twsb_sim.envs.disturbances import Disturbances
from twsb_sim.envs.registration import ENV_IDS, TORQUE_ID, VELOCITY_ID, register
from twsb_sim.envs.render import OffscreenUnavailableError
from twsb_sim.envs.reward import REWARD_TERMS, RewardConfig
from twsb_sim.envs.torque_env import TwsbTorqueEnv
from twsb_sim.envs.twsb_env import TwsbEnv
from twsb_sim.envs.velocity_env import TwsbVelocityEnv

__all__ = [
    "ENV_IDS",
    "REWARD_TERMS",
    "TORQUE_ID",
    "VELOCITY_ID",
    "Disturbances",
    "OffscreenUnavailableError",
    "RewardConfig",
    "TwsbEnv",
    "TwsbTorqueEnv",
    "TwsbVelocityEnv",
    "register",
]
