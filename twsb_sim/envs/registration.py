"""Registration of the environments with Gymnasium under stable ids.

Importing :mod:`twsb_sim.envs` registers nothing; call :func:`register` once (calling it
again is harmless)::

    import gymnasium as gym
    import twsb_sim.envs

    twsb_sim.envs.register()
    env = gym.make("TwsbVelocity-v0")
"""

from __future__ import annotations

import gymnasium as gym

VELOCITY_ID = "TwsbVelocity-v0"
TORQUE_ID = "TwsbTorque-v0"
EPISODE_S = 20.0  # s, simulated time of an episode before TimeLimit truncates it

# id: (entry point, constructor defaults); an episode is EPISODE_S at each id's control period
_ENVS = {
    VELOCITY_ID: ("twsb_sim.envs.velocity_env:TwsbVelocityEnv", {"control_period_s": 0.1}),
    # 10 Hz torque updates cannot balance a robot whose fall time constant is ~0.15 s
    TORQUE_ID: ("twsb_sim.envs.torque_env:TwsbTorqueEnv", {"control_period_s": 0.01}),
}
ENV_IDS = tuple(_ENVS)


def register() -> None:
    """Register every id of :data:`ENV_IDS` with Gymnasium, unless already registered."""
    for env_id, (entry_point, kwargs) in _ENVS.items():
        if env_id in gym.registry:
            continue
        gym.register(
            id=env_id,
            entry_point=entry_point,
            max_episode_steps=round(EPISODE_S / kwargs["control_period_s"]),
            kwargs=dict(kwargs),
        )
