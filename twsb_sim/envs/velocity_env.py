"""The default variant: the agent commands forward velocity and yaw rate, the LQR balances."""

from __future__ import annotations

import numpy as np
from gymnasium import spaces

from twsb_sim.envs.twsb_env import TwsbEnv


class TwsbVelocityEnv(TwsbEnv):
    """Action: ``[velocity m/s, yaw rate rad/s]`` commands, tracked by the LQR balance
    controller at every physics step and held over the control period.

    The box is ``±max_velocity_mps`` by ``±max_yaw_rate_rad_s`` (±1 each by default);
    actions outside it are clipped. During an injected hard stop the robot is commanded to
    zero whatever the action. See :class:`TwsbEnv` for the options.
    """

    def _make_action_space(self, max_velocity_mps: float, max_yaw_rate_rad_s: float) -> spaces.Box:
        high = np.array([max_velocity_mps, max_yaw_rate_rad_s], dtype=np.float32)
        return spaces.Box(-high, high, dtype=np.float32)

    def _advance(self, action: np.ndarray, n_steps: int, hard_stop: bool) -> None:
        if hard_stop:
            velocity = yaw_rate = 0.0
        else:
            velocity, yaw_rate = np.clip(action, self.action_space.low, self.action_space.high)
        self.sim.step(float(velocity), float(yaw_rate), n_steps)
