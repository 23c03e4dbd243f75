"""Wheel odometry: dead reckoning in closed form, encoder ticks, calibration errors, slip."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from twsb_sim.runner import run_scenario
from twsb_sim.scenario import load_scenario
from twsb_sim.sensors.odometry import EncoderOdometry, OdometryConfig
from twsb_sim.sinks import NullSink


def test_straight_run_and_turn_in_place():
    odometry = EncoderOdometry(OdometryConfig.ideal(), wheel_radius_m=0.1, track_width_m=0.4)
    odometry.reset(np.array([5.0, -2.0]))  # encoders need not start at zero
    quarter = math.pi / 2 * 0.2 / 0.1  # wheel rad for a quarter turn in place
    poses, twists = odometry.update(np.array([[15.0, 8.0], [15.0 - quarter, 8.0 + quarter]]))
    np.testing.assert_allclose(poses[0], [1.0, 0.0, 0.0], atol=1e-12)  # both wheels 10 rad
    np.testing.assert_allclose(poses[1], [1.0, 0.0, math.pi / 2], atol=1e-12)
    np.testing.assert_allclose(twists[0], [1.0 * 50.0, 0.0], atol=1e-9)  # 1 m in 1/50 s
    np.testing.assert_allclose(twists[1], [0.0, math.pi / 2 * 50.0], atol=1e-9)


def test_an_arc_is_integrated_exactly():
    odometry = EncoderOdometry(OdometryConfig.ideal(), wheel_radius_m=0.1, track_width_m=0.4)
    odometry.reset(np.zeros(2))
    radius, turn = 1.0, math.pi / 3  # m, rad: an arc of the base around a centre on its left
    steps = 7
    left = (radius - 0.2) * turn / 0.1 * np.arange(1, steps + 1) / steps
    right = (radius + 0.2) * turn / 0.1 * np.arange(1, steps + 1) / steps
    poses, _ = odometry.update(np.column_stack((left, right)))
    np.testing.assert_allclose(
        poses[-1], [radius * math.sin(turn), radius * (1 - math.cos(turn)), turn], atol=1e-12
    )


def test_ticks_quantise_and_a_wrong_radius_scales_the_distance():
    config = OdometryConfig(encoder_counts_per_rev=100, left_wheel_radius_error=0.02,
                            right_wheel_radius_error=0.02)  # fmt: skip
    odometry = EncoderOdometry(config, wheel_radius_m=0.1, track_width_m=0.4)
    odometry.reset(np.zeros(2))
    tick = 2 * math.pi / 100
    poses, _ = odometry.update(np.array([[0.9 * tick, 0.9 * tick], [10.5 * tick, 10.5 * tick]]))
    assert poses[0, 0] == 0.0  # less than a tick: no motion yet
    assert poses[1, 0] == pytest.approx(10 * tick * 0.1 * 1.02)


def test_config_errors_start_with_the_field_name():
    for field, value in (("rate_hz", 0.0), ("encoder_counts_per_rev", 12.5),
                         ("left_wheel_radius_error", 0.5)):  # fmt: skip
        with pytest.raises(ValueError, match=rf"^{field}: expected"):
            OdometryConfig(**{field: value})


class _Last(NullSink):
    def on_frame(self, frame, result):
        self.first = getattr(self, "first", frame)
        self.last = frame


def _odometry_error_m(wheel_friction: float) -> float:
    """Position error of exact encoders after the hard-stop scenario, m."""
    base = load_scenario("scenarios/hard_stop.toml")
    robot = dataclasses.replace(base.robot, wheel_friction=wheel_friction)
    sink = _Last()
    run_scenario(dataclasses.replace(base, robot=robot, odometry=OdometryConfig.ideal()),
                 sinks=[sink])  # fmt: skip
    start, end = sink.first.truth, sink.last.truth
    c, s = math.cos(start.yaw_rad), math.sin(start.yaw_rad)
    dx, dy = end.position_base_in_world[:2] - start.position_base_in_world[:2]
    true_in_odom = np.array([c * dx + s * dy, -s * dx + c * dy])
    return float(np.linalg.norm(sink.last.sensors.pose_base_in_odom[:2] - true_in_odom))


def test_wheels_slip_on_a_slippery_floor_and_odometry_drifts():
    grippy, slippery = _odometry_error_m(1.0), _odometry_error_m(0.3)
    assert grippy < 0.02  # the body's pitch swing alone leaks in
    assert slippery > 3 * grippy
