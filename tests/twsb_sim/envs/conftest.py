"""Shared fixtures of the environment tests."""

from __future__ import annotations

import pytest

from twsb_sim.envs import register


@pytest.fixture(autouse=True, scope="session")
def registered_envs() -> None:
    """Register the ids once for every test of this folder."""
    register()
