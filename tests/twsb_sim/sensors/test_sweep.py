"""The rotating LiDAR against closed form: each beam sees the world from its own instant.

The sensor follows a pose track written down analytically (yaw, pitch or position as a
known function of time), sampled at the 2 ms physics steps as the simulator records it,
so the expected range of every beam is a formula of its time ``stamp + i * dt_beam``.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from twsb_sim.labels import BeamLabel
from twsb_sim.lidar import Lidar, LidarConfig
from twsb_sim.sensors.sweep import PoseTrack

DT = 0.002  # s, the physics step
ROOM_RADIUS = 4.0  # m, inner radius of the round room
SEGMENTS = 360  # wall segments of the round room
MM = 1e-3  # m


def _model(round_room: bool) -> tuple[mujoco.MjModel, mujoco.MjData]:
    """A floor, optionally a round room of thin wall boxes, and a mocap probe with the site."""
    spec = mujoco.MjSpec()
    spec.worldbody.add_geom(name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[50, 50, 0.1])
    if round_room:
        half_width = ROOM_RADIUS * math.tan(math.pi / SEGMENTS) * 1.01  # segments overlap
        for k in range(SEGMENTS):
            angle = 2 * math.pi * k / SEGMENTS
            centre = (ROOM_RADIUS + 0.05) * np.array([math.cos(angle), math.sin(angle)])
            quat = [math.cos(angle / 2), 0.0, 0.0, math.sin(angle / 2)]
            spec.worldbody.add_geom(
                name=f"wall_{k}", type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.05, half_width, 1.5],
                pos=[*centre, 1.5], quat=quat,
            )  # fmt: skip
    probe = spec.worldbody.add_body(name="probe", mocap=True)
    probe.add_site(name="lidar")
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return model, data


def _track(t_first: float, n: int, position, yaw, pitch) -> PoseTrack:
    """Poses at the physics steps from functions of time (yaw, then pitch nose down)."""
    times = t_first + DT * np.arange(n)
    quats = np.empty((n, 4))
    for k, t in enumerate(times):
        mujoco.mju_euler2Quat(quats[k], [yaw(t), pitch(t), 0.0], "zyx")
    positions = np.array([position(t) for t in times])
    return PoseTrack.from_quats(t_first, DT, positions, quats)


def _circle_ranges(p_xy: np.ndarray, headings: np.ndarray) -> np.ndarray:
    """Distance from ``p_xy`` inside a circle of ``ROOM_RADIUS`` to its rim, per heading."""
    u = np.column_stack((np.cos(headings), np.sin(headings)))
    along = u @ p_xy
    return -along + np.sqrt(ROOM_RADIUS**2 - p_xy @ p_xy + along**2)


@pytest.mark.parametrize("rotation", ["counter-clockwise", "clockwise"])
def test_turning_robot_in_a_round_room_sees_the_skew_omega_t_predicts(rotation):
    model, data = _model(round_room=True)
    lidar = Lidar(model, LidarConfig.ideal(rotation=rotation, ray_groups=1))
    omega, yaw0 = 2.0, 0.3  # rad/s, rad
    position = np.array([1.2, -0.7, 0.25])  # m: off-centre, so range depends on heading
    end = 1.0
    track = _track(end - 0.1, 51, lambda t: position, lambda t: yaw0 + omega * t, lambda t: 0.0)
    reading = lidar.sweep(data, np.random.default_rng(0), track, end + lidar.stamp_offset_s)

    times = reading.stamp_s + np.arange(lidar.num_beams) * lidar.time_increment
    sign = 1 if rotation == "counter-clockwise" else -1  # clockwise: beam 0 comes last
    assert lidar.time_increment == pytest.approx(sign * 0.1 / 720)
    assert times.min() == pytest.approx(
        end - 0.1, abs=1e-9 if rotation == "counter-clockwise" else 2e-4
    )
    assert times.max() <= end + 1e-9
    useful = lidar.useful
    headings = yaw0 + omega * times + lidar.angles
    expected = _circle_ranges(position[:2], headings)
    # the rim is a 360-gon: up to 0.15 mm outside the circle, more along oblique beams
    np.testing.assert_allclose(reading.ranges[useful], expected[useful], atol=0.5 * MM)
    # the hit points lie along each beam's own heading
    hits = reading.hit_points_world[useful] - position
    bearing = np.arctan2(hits[:, 1], hits[:, 0])
    np.testing.assert_allclose(np.angle(np.exp(1j * (bearing - headings[useful]))), 0, atol=1e-7)
    # a global-shutter scan at the stamp would be off by centimetres: the skew is real
    at_stamp = _circle_ranges(position[:2], yaw0 + omega * reading.stamp_s + lidar.angles)
    assert np.max(np.abs(reading.ranges[useful] - at_stamp[useful])) > 0.05


def test_pitching_robot_sees_the_floor_at_h_over_sin_pitch_of_each_beam_time():
    model, data = _model(round_room=False)
    lidar = Lidar(model, LidarConfig.ideal(ray_groups=1))
    height, pitch0, rate = 0.3, math.radians(3.0), math.radians(20.0)  # m, rad, rad/s
    end = 0.1
    track = _track(0.0, 51, lambda t: [0, 0, height], lambda t: 0.0, lambda t: pitch0 + rate * t)
    reading = lidar.sweep(data, np.random.default_rng(0), track, end + lidar.stamp_offset_s)

    times = reading.stamp_s + np.arange(lidar.num_beams) * lidar.time_increment
    assert reading.stamp_s == pytest.approx(0.0)
    pitch = pitch0 + rate * times
    cos_angle = np.cos(lidar.angles)
    floor = reading.labels == BeamLabel.FLOOR
    expected = height / (np.sin(pitch) * cos_angle)
    ahead = lidar.useful & (cos_angle > 0) & (expected < lidar.range_max)
    assert np.array_equal(floor, ahead)
    np.testing.assert_allclose(reading.ranges[floor], expected[floor], rtol=1e-6)
    # straight ahead: the floor comes closer as the nose goes down during the sweep
    front = np.argmin(np.abs(lidar.angles))
    assert reading.ranges[front] == pytest.approx(height / math.sin(pitch[front]), rel=1e-6)
    assert reading.ranges[front] < height / math.sin(pitch0) - 0.5


@pytest.mark.parametrize("groups", [1, 2, 5])
def test_moving_sensor_ranges_are_taken_from_each_beams_own_origin(groups):
    """A sensor driving at 1 m/s: the plane correction moves every range to its beam's
    origin, exactly for the flat walls (away from the room's corners)."""
    model, data = _model(round_room=False)
    spec_walls = [(2.0, None), (-2.0, None), (None, 1.5), (None, -1.5)]  # x = +-2, y = +-1.5
    spec = mujoco.MjSpec()
    spec.worldbody.add_geom(name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[50, 50, 0.1])
    for k, (x, y) in enumerate(spec_walls):
        size = [0.05, 3.0, 1.0] if x is not None else [3.0, 0.05, 1.0]
        pos = (
            [x + math.copysign(0.05, x), 0, 1.0]
            if x is not None
            else [0, y + math.copysign(0.05, y), 1.0]
        )
        spec.worldbody.add_geom(
            name=f"wall_{k}", type=mujoco.mjtGeom.mjGEOM_BOX, size=size, pos=pos
        )
    spec.worldbody.add_body(name="probe", mocap=True).add_site(name="lidar")
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    lidar = Lidar(model, LidarConfig.ideal(ray_groups=groups))
    velocity = np.array([1.0, 0.4, 0.0])  # m/s
    start = np.array([-0.5, 0.2, 0.25])
    track = _track(0.0, 51, lambda t: start + velocity * t, lambda t: 0.0, lambda t: 0.0)
    reading = lidar.sweep(data, np.random.default_rng(0), track, 0.0)

    times = reading.stamp_s + np.arange(lidar.num_beams) * lidar.time_increment
    origins = start + velocity * times[:, None]
    u = np.column_stack((np.cos(lidar.angles), np.sin(lidar.angles)))
    with np.errstate(divide="ignore"):
        tx = np.where(u[:, 0] > 0, 2.0 - origins[:, 0], -2.0 - origins[:, 0]) / u[:, 0]
        ty = np.where(u[:, 1] > 0, 1.5 - origins[:, 1], -1.5 - origins[:, 1]) / u[:, 1]
    expected = np.minimum(np.abs(tx), np.abs(ty))
    hits = origins[:, :2] + expected[:, None] * u
    near_corner = (np.abs(np.abs(hits[:, 0]) - 2.0) < 0.06) & (
        np.abs(np.abs(hits[:, 1]) - 1.5) < 0.06
    )
    check = lidar.useful & ~near_corner
    np.testing.assert_allclose(reading.ranges[check], expected[check], atol=1e-6)
    np.testing.assert_allclose(reading.origins_world[check], origins[check], atol=1e-9)


def test_instant_sweep_has_no_time_increment_and_stamps_now():
    model, data = _model(round_room=True)
    data.time = 2.5
    lidar = Lidar(model, LidarConfig.ideal(sweep="instant"))
    assert lidar.time_increment == 0.0 and lidar.stamp_offset_s == 0.0
    assert lidar.scan(data, np.random.default_rng(0)).stamp_s == 2.5
