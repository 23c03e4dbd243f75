"""The sensors in a running simulation: scan timing, the estimate's lag, the streams."""

from __future__ import annotations

import dataclasses
import itertools
import math

import numpy as np
import pytest

from twsb_sim.lidar import LidarConfig
from twsb_sim.runner import run_scenario
from twsb_sim.scenario import load_scenario
from twsb_sim.sensors import ImuConfig
from twsb_sim.sinks import NullSink

HARD_STOP = load_scenario("scenarios/hard_stop.toml")


class Keep(NullSink):
    def __init__(self) -> None:
        self.frames = []

    def on_frame(self, frame, filter_result):
        self.frames.append(frame)


def _run(**changes):
    sink = Keep()
    run_scenario(dataclasses.replace(HARD_STOP, **changes), seed=3, sinks=[sink])
    return sink.frames


@pytest.fixture(scope="module")
def frames():
    return _run()


def test_a_scan_is_stamped_with_its_first_beam_and_handed_out_when_it_ends(frames):
    stamps = np.array([f.stamp_s for f in frames])
    np.testing.assert_allclose(stamps, np.arange(len(frames)) * 0.1 - 0.1, atol=1e-9)
    assert all(f.truth.stamp_s == f.stamp_s for f in frames)  # the truth at the stamp
    np.testing.assert_allclose([f.received_s - f.stamp_s for f in frames], 0.1, atol=1e-12)
    beams = frames[10].beam_times_s
    assert beams[0] == frames[10].stamp_s and beams[-1] == pytest.approx(
        frames[11].stamp_s - 0.1 / 720
    )


def test_clockwise_and_instant_scans_are_stamped_when_handed_out():
    for lidar in (LidarConfig(rotation="clockwise"), LidarConfig(sweep="instant")):
        frames = _run(duration_s=1.0, commands=HARD_STOP.commands[:1], shoves=(), lidar=lidar)
        np.testing.assert_allclose([f.stamp_s for f in frames], np.arange(11) * 0.1, atol=1e-9)
        assert all(f.truth.stamp_s == f.stamp_s and f.received_s == f.stamp_s for f in frames)


def test_streams_arrive_once_in_order_at_their_rates_with_the_latency(frames):
    imu = np.concatenate([f.sensors.imu.stamps_s for f in frames])
    odom = np.concatenate([f.sensors.odometry.stamps_s for f in frames])
    latency = ImuConfig().latency_s
    np.testing.assert_allclose(imu, np.arange(len(imu)) / 200.0 + latency, atol=1e-9)
    np.testing.assert_allclose(odom, np.arange(len(odom)) / 50.0, atol=1e-9)
    for previous, frame in itertools.pairwise(frames):
        arrived = frame.sensors.imu.stamps_s
        assert np.all(arrived > previous.received_s) and np.all(arrived <= frame.received_s + 1e-9)


def test_the_estimate_lags_the_truth_in_a_hard_stop_and_settles_when_still(frames):
    pitch = np.array([f.truth.pitch_rad for f in frames])
    estimate = np.array([f.attitude_estimate.pitch_rad for f in frames])
    peak = int(np.argmax(np.abs(pitch)))
    assert abs(pitch[peak]) > math.radians(5)
    assert abs(estimate[peak]) < 0.8 * abs(pitch[peak])  # the filter is slower than the stop
    # standing at the end: only the BMI088's offsets remain (20 mg ~ 1.2 deg at most)
    assert abs(estimate[-1] - pitch[-1]) < math.radians(1.5)
    ideal = _run(imu=ImuConfig.ideal())
    assert abs(ideal[-1].attitude_estimate.pitch_rad - ideal[-1].truth.pitch_rad) < math.radians(
        0.1
    )


def test_the_lidar_pose_in_odom_is_the_base_pose_and_the_mount(frames):
    frame = frames[-1]
    x, y, yaw = frame.sensors.pose_base_in_odom
    lx, ly, lyaw = frame.lidar_pose_in_odom
    c, s = math.cos(yaw), math.sin(yaw)
    assert (lx, ly, lyaw) == pytest.approx((x + 0.03 * c - 0.02 * s, y + 0.03 * s + 0.02 * c, yaw))
    assert x > 1.5  # the robot drove ahead before the stop
