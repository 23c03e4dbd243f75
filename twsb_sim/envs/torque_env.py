"""The variant for learning balance: the agent sets the wheel torques itself."""

from __future__ import annotations

import numpy as np
from gymnasium import spaces

from twsb_sim.envs.twsb_env import TwsbEnv


class TwsbTorqueEnv(TwsbEnv):
    """Action: ``[left, right]`` wheel torques as fractions of the motor limit, in [-1, 1]
    (clipped), held over the control period. No controller runs: the agent balances.

    The task and its target are those of the velocity variant: an injected hard stop sets
    the target to zero, and the agent has to stop. See :class:`TwsbEnv` for the options.
    """

    def _make_action_space(self, max_velocity_mps: float, max_yaw_rate_rad_s: float) -> spaces.Box:
        return spaces.Box(-1.0, 1.0, shape=(2,), dtype=np.float32)

    def _advance(self, action: np.ndarray, n_steps: int, hard_stop: bool) -> None:
        fractions = np.clip(action, -1.0, 1.0)
        self.sim.step_torques(fractions * self.sim.handles.torque_limit_nm, n_steps)
