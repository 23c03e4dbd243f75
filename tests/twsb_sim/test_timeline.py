"""Command timelines sampled at the physics rate, and heading-frame shoves."""

import math

import numpy as np
import pytest

from twsb_sim.timeline import CommandPoint, heading_force_to_world, phase_at, sample_commands


def test_no_points_commands_zero():
    samples = sample_commands((), dt_s=0.1, n_steps=5)
    assert not samples.velocity_mps.any() and not samples.yaw_rate_rad_s.any()


def test_ramp_is_linear_then_held():
    points = (CommandPoint(t_s=1.0, velocity_mps=1.0, ramp_s=1.0),)
    v = sample_commands(points, dt_s=0.25, n_steps=13).velocity_mps
    assert v[:5].tolist() == [0.0] * 5  # until t = 1.0
    assert v[6] == pytest.approx(0.5)  # t = 1.5, half way up the ramp
    assert v[8:].tolist() == pytest.approx([1.0] * 5)


def test_hard_stop_is_a_step_from_the_value_in_force():
    points = (
        CommandPoint(t_s=0.0, velocity_mps=1.0, yaw_rate_rad_s=0.6),
        CommandPoint(t_s=1.0, velocity_mps=0.0),
    )
    samples = sample_commands(points, dt_s=0.5, n_steps=4)
    assert samples.velocity_mps[1] == pytest.approx(1.0)
    assert samples.velocity_mps[2] == 0.0  # a step takes effect at its own time
    assert samples.velocity_mps[3] == 0.0
    assert samples.yaw_rate_rad_s[1] == pytest.approx(0.6)
    assert samples.yaw_rate_rad_s[3] == 0.0


def test_ramp_starts_from_an_unfinished_value():
    points = (
        CommandPoint(t_s=0.0, velocity_mps=1.0),
        CommandPoint(t_s=2.0, velocity_mps=-1.0, ramp_s=2.0),
    )
    v = sample_commands(points, dt_s=1.0, n_steps=5).velocity_mps
    np.testing.assert_allclose(v, [1.0, 1.0, 1.0, 0.0, -1.0], atol=1e-9)


def test_phase_labels():
    points = (
        CommandPoint(t_s=1.0, velocity_mps=1.0, label="accelerate"),
        CommandPoint(t_s=3.0, label="hard stop"),
    )
    assert phase_at(points, 0.5) == ""
    assert phase_at(points, 2.0) == "accelerate"
    assert phase_at(points, 3.0) == "hard stop"


def test_heading_force_rotates_with_yaw():
    force = heading_force_to_world((10.0, 0.0, 1.0), yaw_rad=math.pi / 2)
    np.testing.assert_allclose(force, [0.0, 10.0, 1.0], atol=1e-12)
