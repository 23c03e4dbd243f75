"""Shared fixtures of the simulator tests."""

from __future__ import annotations

from collections.abc import Callable

import mujoco
import pytest

from twsb_sim.robot import HOME_KEY, RobotConfig, load_robot_spec


def _robot_on_floor(
    robot_config: RobotConfig | None = None,
) -> tuple[mujoco.MjModel, mujoco.MjData]:
    spec = load_robot_spec(robot_config if robot_config is not None else RobotConfig())
    spec.worldbody.add_geom(
        name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[100.0, 100.0, 0.1]
    )
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key(HOME_KEY).id)
    mujoco.mj_forward(model, data)
    return model, data


@pytest.fixture
def robot_on_floor() -> Callable[..., tuple[mujoco.MjModel, mujoco.MjData]]:
    """Build the robot (optionally from a ``RobotConfig``) on a flat floor, at ``home``."""
    return _robot_on_floor
