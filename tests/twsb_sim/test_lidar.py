"""The LiDAR against closed-form geometry, in a one-room house with a stand-in sensor.

The stand-in is a mocap body carrying the ``lidar`` site, placed and tilted by each test.
The room's walls are centred on x = +-3 m, y = +-2 m, 0.1 m thick, so their inner faces
are at x = +-2.95 m and y = +-1.95 m; the ceiling is at 2.5 m.
"""

from __future__ import annotations

import dataclasses
import math
import time

import mujoco
import numpy as np
import pytest

from twsb_sim.house import Room, add_house_to_spec, make_house
from twsb_sim.house.floorplan import assemble_house
from twsb_sim.house.furniture import make_furniture
from twsb_sim.labels import BeamLabel
from twsb_sim.lidar import Lidar, LidarConfig

INNER_X, INNER_Y, CEILING = 2.95, 1.95, 2.5  # m
NOISELESS = LidarConfig.ideal()  # no reading errors; the default has a cheap scanner's
MM = 1e-3  # m


def _room(furniture=()):
    return assemble_house("test_room", None, CEILING, [Room("room", -3, -2, 3, 2)], [], furniture)


def _model(house=None, extra=None):
    """The room plus a mocap probe carrying the ``lidar`` site."""
    spec = mujoco.MjSpec()
    add_house_to_spec(spec, house or _room())
    probe = spec.worldbody.add_body(name="probe", mocap=True)
    probe.add_site(name="lidar")
    if extra:
        extra(spec, probe)
    model = spec.compile()
    return model, mujoco.MjData(model)


def _place(model, data, xyz, roll=0.0, pitch=0.0, yaw=0.0):
    """Put the probe at ``xyz``, turned by yaw, then pitch (positive = nose down), then roll."""
    quat = np.empty(4)
    mujoco.mju_euler2Quat(quat, [yaw, pitch, roll], "zyx")
    data.mocap_pos[0] = xyz
    data.mocap_quat[0] = quat
    mujoco.mj_forward(model, data)


def _level_ranges(x, y, world_angles):
    """Distance from (x, y) to the room's inner wall faces along each direction."""
    c, s = np.cos(world_angles), np.sin(world_angles)
    with np.errstate(divide="ignore"):
        tx = np.where(c > 0, (INNER_X - x) / c, (-INNER_X - x) / c)
        ty = np.where(s > 0, (INNER_Y - y) / s, (-INNER_Y - y) / s)
    return np.minimum(np.where(np.isfinite(tx), tx, np.inf), np.where(np.isfinite(ty), ty, np.inf))


def test_level_scan_reads_analytic_wall_ranges():
    model, data = _model()
    x, y, yaw = 0.4, -0.3, math.radians(30)
    _place(model, data, [x, y, 0.25], yaw=yaw)
    lidar = Lidar(model, NOISELESS)
    reading = lidar.scan(data, np.random.default_rng(0))
    useful = lidar.useful
    expected = _level_ranges(x, y, yaw + lidar.angles)
    np.testing.assert_allclose(reading.ranges[useful], expected[useful], atol=MM)
    assert np.all(reading.labels[useful] == BeamLabel.STATIC)


def test_laserscan_intrinsics():
    model, _ = _model()
    lidar = Lidar(model)
    assert lidar.num_beams == 720
    assert lidar.angle_min == -math.pi
    assert lidar.angle_increment == pytest.approx(math.radians(0.5))
    assert lidar.angle_max == pytest.approx(math.pi - math.radians(0.5))
    assert lidar.scan_time == pytest.approx(0.1)
    # a rotating scanner by default: beams one after the other over the revolution
    assert lidar.time_increment == pytest.approx(0.1 / 720)
    assert lidar.stamp_offset_s == pytest.approx(-0.1)
    assert (lidar.range_min, lidar.range_max) == (0.15, 12.0)  # RPLIDAR A1
    instant = Lidar(model, LidarConfig(sweep="instant"))
    assert (instant.time_increment, instant.stamp_offset_s) == (0.0, 0.0)
    clockwise = Lidar(model, LidarConfig(rotation="clockwise"))
    assert clockwise.time_increment == pytest.approx(-0.1 / 720)
    assert clockwise.stamp_offset_s == 0.0


def _floor_hits(h, origin_xy, dirs):
    """Beams (unit world directions) that hit the floor well inside the room, and where."""
    t = np.where(dirs[:, 2] < -1e-9, h / np.maximum(-dirs[:, 2], 1e-12), np.inf)
    with np.errstate(invalid="ignore"):  # inf * 0 for beams running parallel to an axis
        hit_xy = origin_xy + dirs[:, :2] * t[:, None]
    inside = (np.abs(hit_xy[:, 0]) < INNER_X - 0.05) & (np.abs(hit_xy[:, 1]) < INNER_Y - 0.05)
    return inside & np.isfinite(t), t


def test_pitched_down_scan_hits_floor_at_h_over_tan_elevation():
    model, data = _model()
    h, pitch = 0.25, math.radians(6)  # nose down
    _place(model, data, [0.0, 0.0, h], pitch=pitch)
    lidar = Lidar(model, NOISELESS)
    reading = lidar.scan(data, np.random.default_rng(0))
    a = lidar.angles
    elevation_down = np.arcsin(np.sin(pitch) * np.cos(a))
    dirs = np.stack((np.cos(pitch) * np.cos(a), np.sin(a), -np.sin(pitch) * np.cos(a)), -1)
    on_floor, _ = _floor_hits(h, np.zeros(2), dirs)
    on_floor &= lidar.useful
    assert on_floor.sum() > 50 and np.all(np.abs(a[on_floor]) < math.pi / 2)  # the front
    assert np.all(reading.labels[on_floor] == BeamLabel.FLOOR)
    # slant range h / sin(e); horizontal distance of the hit h / tan(e)
    np.testing.assert_allclose(
        reading.ranges[on_floor], h / np.sin(elevation_down[on_floor]), atol=MM
    )
    horizontal = np.linalg.norm(reading.hit_points_world[on_floor, :2], axis=1)
    np.testing.assert_allclose(horizontal, h / np.tan(elevation_down[on_floor]), atol=MM)
    np.testing.assert_allclose(reading.hit_points_world[on_floor, 2], 0.0, atol=1e-9)
    # everything else that returns hits a wall
    rest = lidar.useful & ~on_floor & (reading.labels != BeamLabel.FLOOR)
    assert np.all(reading.labels[rest] == BeamLabel.STATIC)


def test_pitched_up_scan_hits_floor_behind():
    model, data = _model()
    h, pitch = 0.25, math.radians(-6)  # nose up: the back beams go down
    _place(model, data, [0.0, 0.0, h], pitch=pitch)
    lidar = Lidar(model, NOISELESS)
    reading = lidar.scan(data, np.random.default_rng(0))
    a = lidar.angles
    dirs = np.stack((np.cos(pitch) * np.cos(a), np.sin(a), -np.sin(pitch) * np.cos(a)), -1)
    on_floor, t = _floor_hits(h, np.zeros(2), dirs)
    on_floor &= lidar.useful
    assert on_floor.sum() > 50 and np.all(np.abs(a[on_floor]) > math.pi / 2)  # the back
    assert np.all(reading.labels[on_floor] == BeamLabel.FLOOR)
    np.testing.assert_allclose(reading.ranges[on_floor], t[on_floor], atol=MM)


def test_pitched_up_scan_near_the_ceiling_hits_ceiling_ahead():
    model, data = _model()
    h, pitch = 2.2, math.radians(-15)
    _place(model, data, [0.0, 0.0, h], pitch=pitch)
    lidar = Lidar(model, NOISELESS)
    reading = lidar.scan(data, np.random.default_rng(0))
    a = lidar.angles
    elevation_up = np.arcsin(np.sin(-pitch) * np.cos(a))
    t = np.where(
        elevation_up > 1e-9, (CEILING - h) / np.maximum(np.sin(elevation_up), 1e-12), np.inf
    )
    hit_x = np.cos(pitch) * np.cos(a) * t
    hit_y = np.sin(a) * t
    on_ceiling = (np.abs(hit_x) < INNER_X - 0.05) & (np.abs(hit_y) < INNER_Y - 0.05) & lidar.useful
    assert on_ceiling.sum() > 50
    assert np.all(reading.labels[on_ceiling] == BeamLabel.CEILING)
    np.testing.assert_allclose(reading.ranges[on_ceiling], t[on_ceiling], atol=MM)


def test_roll_tilts_the_scan_plane_sideways():
    model, data = _model()
    h, roll = 0.25, math.radians(-8)  # left side down
    _place(model, data, [0.0, 0.0, h], roll=roll)
    lidar = Lidar(model, NOISELESS)
    reading = lidar.scan(data, np.random.default_rng(0))
    left = int(np.argmin(np.abs(lidar.angles - math.pi / 2)))
    assert reading.labels[left] == BeamLabel.FLOOR
    assert reading.ranges[left] == pytest.approx(h / math.sin(-roll), abs=MM)


def test_table_top_from_above_is_horizontal_and_its_side_static():
    table = make_furniture("table", 0, 1.3, 0.0, 0.0, (1.2, 0.8, 0.75))  # top: x 0.7..1.9
    model, data = _model(_room([table]))
    top_id = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, "table_0_top")
    lidar = Lidar(model, NOISELESS)
    ahead = int(np.argmin(np.abs(lidar.angles)))

    _place(model, data, [0.0, 0.0, 1.0], pitch=math.radians(15))
    reading = lidar.scan(data, np.random.default_rng(0))
    assert reading.geom_ids[ahead] == top_id
    assert reading.labels[ahead] == BeamLabel.HORIZONTAL
    assert reading.ranges[ahead] == pytest.approx(0.25 / math.sin(math.radians(15)), abs=MM)

    _place(model, data, [0.0, 0.0, 0.73], pitch=0.0)  # level, through the top's edge
    reading = lidar.scan(data, np.random.default_rng(0))
    assert reading.geom_ids[ahead] == top_id
    assert reading.labels[ahead] == BeamLabel.STATIC
    assert reading.ranges[ahead] == pytest.approx(0.7, abs=MM)


def test_blocked_sector_is_occluded_and_minus_inf():
    model, data = _model()
    _place(model, data, [0.0, 0.0, 0.25])
    lidar = Lidar(model)
    reading = lidar.scan(data, np.random.default_rng(0))
    blocked = ~lidar.useful
    assert blocked.sum() == 240 and lidar.useful.sum() == 480
    degrees = np.degrees(lidar.angles[blocked])
    assert degrees.min() == pytest.approx(-150.0) and degrees.max() == pytest.approx(-30.5)
    assert np.all(reading.labels[blocked] == BeamLabel.OCCLUDED)
    assert np.all(reading.ranges[blocked] == -np.inf)
    assert np.all(reading.geom_ids[blocked] == -1)
    assert np.all(np.isnan(reading.hit_points_world[blocked]))
    assert lidar.useful[np.argmin(np.abs(lidar.angles))]  # ahead is seen
    assert lidar.useful[0]  # and straight behind


def test_blocked_sector_follows_config():
    model, _ = _model()
    lidar = Lidar(model, LidarConfig(useful_fov_deg=270.0, blocked_sector_center_deg=90.0))
    assert (~lidar.useful).sum() == 180
    assert not lidar.useful[np.argmin(np.abs(lidar.angles - math.pi / 2))]


def test_out_of_range_is_plus_inf_no_return_and_too_close_is_minus_inf():
    model, data = _model()
    _place(model, data, [0.0, 0.0, 0.25])
    lidar = Lidar(model, dataclasses.replace(NOISELESS, range_max_m=1.5))
    reading = lidar.scan(data, np.random.default_rng(0))
    useful = lidar.useful
    assert np.all(reading.ranges[useful] == np.inf)
    assert np.all(reading.labels[useful] == BeamLabel.NO_RETURN)
    assert np.all(reading.geom_ids[useful] == -1)
    assert np.all(np.isnan(reading.hit_points_world[useful]))

    _place(model, data, [INNER_X - 0.02, 0.0, 0.25])  # 2 cm from the east wall
    reading = Lidar(model).scan(data, np.random.default_rng(0))  # with noise
    ahead = int(np.argmin(np.abs(lidar.angles)))
    assert reading.ranges[ahead] == -np.inf
    assert reading.labels[ahead] == BeamLabel.STATIC


def _robot_parts(spec, probe):
    probe.add_geom(name="probe_shell", type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[0.15, 0, 0],
                   group=3, contype=0, conaffinity=0)  # fmt: skip
    spec.worldbody.add_geom(name="robot_screen", type=mujoco.mjtGeom.mjGEOM_BOX,
                            size=[0.01, 1.0, 1.0], pos=[1.0, 0, 0.5], group=3)  # fmt: skip


def test_geoms_in_group_3_are_never_hit():
    model, data = _model(extra=_robot_parts)
    _place(model, data, [0.0, 0.0, 0.25])
    lidar = Lidar(model, NOISELESS)
    reading = lidar.scan(data, np.random.default_rng(0))
    hit = reading.geom_ids[reading.geom_ids >= 0]
    assert not np.any(model.geom_group[hit] == 3)
    expected = _level_ranges(0.0, 0.0, lidar.angles)
    np.testing.assert_allclose(reading.ranges[lidar.useful], expected[lidar.useful], atol=MM)


def test_moving_body_is_dynamic():
    def cart(spec, probe):
        body = spec.worldbody.add_body(name="cart", pos=[1.5, 0, 0.5], mocap=True)
        body.add_geom(name="cart_box", type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.2, 0.2, 0.5])

    model, data = _model(extra=cart)
    _place(model, data, [0.0, 0.0, 0.25])
    lidar = Lidar(model, NOISELESS)
    reading = lidar.scan(data, np.random.default_rng(0))
    ahead = int(np.argmin(np.abs(lidar.angles)))
    assert reading.labels[ahead] == BeamLabel.DYNAMIC
    assert reading.ranges[ahead] == pytest.approx(1.3, abs=MM)


def test_same_seed_same_scan_other_seed_other_scan():
    model, data = _model()
    _place(model, data, [0.2, 0.1, 0.25], pitch=0.05)
    lidar = Lidar(model, LidarConfig.ideal(range_noise_std_m=0.02))
    first = lidar.scan(data, np.random.default_rng(7))
    again = lidar.scan(data, np.random.default_rng(7))
    other = lidar.scan(data, np.random.default_rng(8))
    np.testing.assert_array_equal(first.ranges, again.ranges)
    np.testing.assert_array_equal(first.labels, again.labels)
    assert not np.array_equal(first.ranges, other.ranges)
    np.testing.assert_array_equal(first.labels, other.labels)  # noise never changes labels


def test_noise_std_matches_config():
    model, data = _model()
    _place(model, data, [0.0, 0.0, 0.25])
    lidar = Lidar(model, LidarConfig.ideal(range_noise_std_m=0.03))
    rng = np.random.default_rng(1)
    expected = _level_ranges(0.0, 0.0, lidar.angles)[lidar.useful]
    errors = np.concatenate(
        [lidar.scan(data, rng).ranges[lidar.useful] - expected for _ in range(20)]
    )
    assert errors.std() == pytest.approx(0.03, rel=0.05)
    assert abs(errors.mean()) < 0.002


def test_noise_never_turns_a_return_into_inf():
    model, data = _model()
    _place(model, data, [0.0, 0.0, 0.25])
    # every wall lies within 1.95..3.6 m; range_max just above the farthest corner
    lidar = Lidar(model, LidarConfig.ideal(range_max_m=3.6, range_noise_std_m=0.5))
    rng = np.random.default_rng(2)
    for _ in range(10):
        reading = lidar.scan(data, rng)
        ranges = reading.ranges[lidar.useful]
        assert np.all(np.isfinite(ranges))
        assert ranges.min() >= 0.05 and ranges.max() <= 3.6
        assert np.all(reading.labels[lidar.useful] == BeamLabel.STATIC)


def test_reading_carries_the_sensor_pose():
    model, data = _model()
    _place(model, data, [0.5, -0.4, 0.3], pitch=0.1, yaw=0.7)
    reading = Lidar(model).scan(data, np.random.default_rng(0))
    np.testing.assert_allclose(reading.position_sensor_in_world, [0.5, -0.4, 0.3], atol=1e-12)
    np.testing.assert_allclose(reading.rotation_sensor_to_world, data.site_xmat[0].reshape(3, 3))


@pytest.mark.parametrize(
    ("field", "value"),
    [("beams_per_revolution", 0), ("beams_per_revolution", 720.0), ("rate_hz", 0.0),
     ("useful_fov_deg", 400.0), ("range_min_m", -1.0), ("range_max_m", 0.01),
     ("range_noise_std_m", -0.1), ("horizontal_normal_min_z", 1.5),
     ("sweep", "global"), ("rotation", "left"), ("dropout_probability", 1.5),
     ("grazing_dropout_start_deg", 95.0), ("range_noise_fraction", -0.01), ("ray_groups", 0),
     ("mixed_pixel_probability", 2.0), ("range_resolution_m", -0.001),
     ("blocked_sector_center_deg", float("nan")), ("rate_hz", True)],
)  # fmt: skip
def test_config_errors_start_with_the_field_name(field, value):
    with pytest.raises(ValueError, match=rf"^{field}: expected"):
        LidarConfig(**{field: value})


def test_missing_site_is_a_clear_error():
    model = mujoco.MjModel.from_xml_string("<mujoco><worldbody/></mujoco>")
    with pytest.raises(ValueError, match=r"^site:"):
        Lidar(model)


def test_scan_in_house_is_fast():
    spec = mujoco.MjSpec()
    house = make_house("house1")
    add_house_to_spec(spec, house)
    spec.worldbody.add_body(name="probe", mocap=True).add_site(name="lidar")
    model = spec.compile()
    data = mujoco.MjData(model)
    pose = house.spawn_poses[0]
    _place(model, data, [pose.x_m, pose.y_m, 0.25], pitch=0.05, yaw=pose.yaw_rad)
    lidar, rng = Lidar(model), np.random.default_rng(0)
    start = time.perf_counter()
    for _ in range(50):
        lidar.scan(data, rng)
    assert (time.perf_counter() - start) / 50 < 5e-3  # ~0.3 ms here; loose for busy CI
