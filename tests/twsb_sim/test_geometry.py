"""The simulated LiDAR on the real robot against closed-form geometry (noise off).

A level robot in a rectangular room must read the analytic distances to the walls; a
robot held at a known pitch must hit the floor where a tilted plane meets it: a beam at
azimuth ``a`` on a sensor pitched nose-down by ``p`` descends at elevation
``e = asin(sin p cos a)`` and meets the floor at slant range ``h / sin e``, that is at
horizontal distance ``h / tan e``.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from pvfilter.improved import ImprovedParams
from pvfilter.improved.geometry import floor_distance
from twsb_sim.house import Room
from twsb_sim.house.floorplan import assemble_house
from twsb_sim.labels import BeamLabel
from twsb_sim.lidar import LidarConfig
from twsb_sim.robot import RobotConfig
from twsb_sim.simulation import Simulation

ROOM_X_M, ROOM_Y_M = 8.0, 6.0  # wall centre lines
CEILING_M = 2.5
TOLERANCE_M = 1e-3


def box_simulation(lidar_ahead_m: float = 0.0) -> Simulation:
    """The robot in the box room, to be held at a pose: a global-shutter scanner without
    reading errors, mounted level on the axle's centre line (``lidar_ahead_m`` ahead of
    the axle) as the closed forms assume."""
    house = assemble_house(
        "box", None, CEILING_M, (Room("room", 0.0, 0.0, ROOM_X_M, ROOM_Y_M),), (), ()
    )
    robot = RobotConfig(
        lidar_offset_x_m=lidar_ahead_m,
        lidar_offset_y_m=0.0,
        lidar_tilt_pitch_deg=0.0,
        lidar_tilt_roll_deg=0.0,
    )
    return Simulation(house, robot=robot, lidar=LidarConfig.ideal(sweep="instant"), seed=0)


@pytest.fixture(scope="module")
def sim() -> Simulation:
    return box_simulation()


def hold_at(sim: Simulation, x_m: float, y_m: float, yaw_rad: float, pitch_rad: float) -> None:
    """Place the robot at a pose with a given pitch (about its axle), not stepping physics."""
    sim.reset((x_m, y_m, yaw_rad))
    adr = sim.handles.qpos_adr
    # body orientation: yaw about z, then pitch about the body's y axis (REP-103 ZYX)
    cy, sy = math.cos(yaw_rad / 2), math.sin(yaw_rad / 2)
    cp, sp = math.cos(pitch_rad / 2), math.sin(pitch_rad / 2)
    sim.data.qpos[adr + 3 : adr + 7] = [cy * cp, -sy * sp, cy * sp, sy * cp]
    mujoco.mj_forward(sim.model, sim.data)


def analytic_wall_ranges(
    origin_xy: np.ndarray, azimuths_world: np.ndarray, half_wall_m: float
) -> np.ndarray:
    """Distance from a point inside the room to its inner wall faces along each azimuth."""
    lo = np.array([half_wall_m, half_wall_m])
    hi = np.array([ROOM_X_M - half_wall_m, ROOM_Y_M - half_wall_m])
    d = np.stack([np.cos(azimuths_world), np.sin(azimuths_world)], axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(d > 0, (hi - origin_xy) / d, np.where(d < 0, (lo - origin_xy) / d, np.inf))
    return t.min(axis=1)


def test_level_robot_reads_the_walls_of_a_rectangular_room(sim):
    hold_at(sim, 3.0, 2.2, yaw_rad=0.4, pitch_rad=0.0)
    frame = sim.frame(0)
    sensor = frame.truth.position_sensor_in_world
    assert sensor[2] == pytest.approx(0.25, abs=1e-9)  # the default LiDAR height
    useful = frame.labels != BeamLabel.OCCLUDED
    azimuths = 0.4 + frame.scan.angles()[useful]
    expected = analytic_wall_ranges(sensor[:2], azimuths, sim.house.wall_thickness_m / 2)
    np.testing.assert_allclose(frame.scan.ranges[useful], expected, atol=TOLERANCE_M, rtol=0)
    assert (frame.labels[useful] == BeamLabel.STATIC).all()
    # the blocked sector (120 deg on the right, centred on -90 deg) reads -inf
    assert np.count_nonzero(~useful) == 240
    assert np.isneginf(frame.scan.ranges[~useful]).all()


@pytest.mark.parametrize("pitch_deg", [6.0, 12.0, 20.0])
def test_pitched_robot_hits_the_floor_at_h_over_tan_elevation(sim, pitch_deg):
    pitch = math.radians(pitch_deg)
    hold_at(sim, 4.0, 3.0, yaw_rad=0.0, pitch_rad=pitch)
    frame = sim.frame(0)
    assert frame.truth.pitch_rad == pytest.approx(pitch, abs=1e-9)
    sensor = frame.truth.position_sensor_in_world
    h = sensor[2]
    angles = frame.scan.angles()
    elevation = np.arcsin(np.sin(pitch) * np.cos(angles))
    floor = frame.labels == BeamLabel.FLOOR
    assert floor.sum() > 20
    assert (elevation[floor] > 0).all()  # only descending beams reach the floor
    np.testing.assert_allclose(
        frame.scan.ranges[floor], h / np.sin(elevation[floor]), atol=TOLERANCE_M, rtol=0
    )
    horizontal = np.linalg.norm(frame.hit_points_world[floor, :2] - sensor[:2], axis=1)
    np.testing.assert_allclose(horizontal, h / np.tan(elevation[floor]), atol=TOLERANCE_M, rtol=0)
    np.testing.assert_allclose(frame.hit_points_world[floor, 2], 0.0, atol=TOLERANCE_M)
    # every descending beam whose floor hit is nearer than the walls is labeled FLOOR
    front = (elevation > 0) & (frame.labels != BeamLabel.OCCLUDED)
    wall = analytic_wall_ranges(sensor[:2], angles, sim.house.wall_thickness_m / 2)
    reaches_floor = front & (h / np.tan(np.maximum(elevation, 1e-9)) < wall - 0.05)
    np.testing.assert_array_equal(floor[reaches_floor], True)


def test_nose_up_robot_sees_the_floor_behind_it(sim):
    hold_at(sim, 4.0, 3.0, yaw_rad=0.0, pitch_rad=math.radians(-15.0))
    frame = sim.frame(0)
    floor = frame.labels == BeamLabel.FLOOR
    assert floor.any()
    assert (np.cos(frame.scan.angles()[floor]) < 0).all()


@pytest.mark.parametrize("pitch_deg", [20.0, -20.0])
def test_a_lidar_ahead_of_the_axle_meets_the_floor_where_the_filter_puts_it(pitch_deg):
    # nose down lowers a LiDAR mounted ahead of the axle: the floor line ahead comes that
    # much nearer, the one behind (nose up) that much farther, as lidar_ahead_m tells the filter
    sim = box_simulation(lidar_ahead_m=0.12)
    robot = sim.robot_config
    pitch = math.radians(pitch_deg)
    hold_at(sim, 4.0, 3.0, yaw_rad=0.0, pitch_rad=pitch)
    frame = sim.frame(0)
    params = ImprovedParams(
        lidar_height_m=robot.lidar_height_m,
        axle_height_m=robot.wheel_radius_m,
        lidar_ahead_m=robot.lidar_offset_x_m,
    )
    side = math.copysign(1.0, pitch)  # the floor ahead when nose down
    angles = frame.scan.angles()
    beam = int(np.argmin(np.abs(np.angle(np.exp(1j * (angles - (0.0 if side > 0 else math.pi)))))))
    assert frame.labels[beam] == BeamLabel.FLOOR
    over_axle = float(floor_distance(abs(pitch), params))
    assert frame.scan.ranges[beam] == pytest.approx(over_axle - side * 0.12, abs=TOLERANCE_M)
    sensor_height = frame.truth.position_sensor_in_world[2]
    assert sensor_height == pytest.approx(
        float(params.scanner_height_m(pitch)) - 0.12 * math.sin(pitch), abs=1e-6
    )
