"""Ceilings and sloped surfaces against closed form: where a tilted scan plane meets them,
and how the level-scanner rule labels them."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from twsb_sim.house import FloorFeature, HouseExtras, Room, add_house_to_spec, with_extras
from twsb_sim.house.ceilings import AtticSlope, Staircase
from twsb_sim.house.extras import WallShelf
from twsb_sim.house.floorplan import assemble_house
from twsb_sim.labels import BeamLabel
from twsb_sim.level_view import LevelView
from twsb_sim.lidar import Lidar, LidarConfig

NOISELESS = LidarConfig.ideal(sweep="instant", useful_fov_deg=360.0)
LONG_ROOM = Room("hall", -20.0, -3.0, 20.0, 3.0)  # walls 20 m away along x


def _scanner_in(house, xyz, pitch=0.0, yaw=0.0):
    """A mocap probe carrying the ``lidar`` site in ``house``, turned by yaw then pitch."""
    spec = mujoco.MjSpec()
    add_house_to_spec(spec, house)
    spec.worldbody.add_body(name="probe", mocap=True).add_site(name="lidar")
    model = spec.compile()
    data = mujoco.MjData(model)
    quat = np.empty(4)
    mujoco.mju_euler2Quat(quat, [yaw, pitch, 0.0], "zyx")
    data.mocap_pos[0], data.mocap_quat[0] = xyz, quat
    mujoco.mj_forward(model, data)
    lidar = Lidar(model, NOISELESS)
    reading = lidar.scan(data, np.random.default_rng(0))
    return reading, LevelView(model, lidar).relabel(data, reading), lidar


def _beam(lidar: Lidar, angle_rad: float) -> int:
    return int(
        np.argmin(np.abs(np.remainder(lidar.angles - angle_rad + math.pi, math.tau) - math.pi))
    )


@pytest.mark.parametrize(
    ("ceiling_m", "sensor_m", "tilt_deg"), [(2.0, 0.25, 15.0), (3.0, 0.4, 20.0)]
)
def test_ceiling_is_hit_at_height_over_sine_of_tilt_and_labeled_ceiling(
    ceiling_m, sensor_m, tilt_deg
):
    house = assemble_house("long", None, ceiling_m, [LONG_ROOM], [], [])
    tilt = math.radians(tilt_deg)
    reading, labels, lidar = _scanner_in(house, [0.0, 0.0, sensor_m], pitch=-tilt)  # nose up
    ahead, behind = _beam(lidar, 0.0), _beam(lidar, math.pi)
    assert reading.ranges[ahead] == pytest.approx((ceiling_m - sensor_m) / math.sin(tilt), abs=1e-6)
    assert labels[ahead] == BeamLabel.CEILING
    assert reading.ranges[behind] == pytest.approx(sensor_m / math.sin(tilt), abs=1e-6)
    assert labels[behind] == BeamLabel.FLOOR


def test_attic_slope_is_where_its_knee_and_pitch_put_it():
    room = Room("attic", 0.0, 0.0, 8.0, 6.0)
    plain = assemble_house("attic", None, 2.6, [room], [], [])
    house = with_extras(plain, HouseExtras(attic_slopes=(AtticSlope("attic", "north", 1.0, 40.0),)))
    spec = mujoco.MjSpec()
    add_house_to_spec(spec, house)
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    geom = np.zeros(1, np.int32)
    wall = 6.0 - 0.05  # the north wall's inner face
    for d in (0.2, 0.8, 1.5):  # metres out from the wall, under the slope
        dist = mujoco.mj_ray(model, data, np.array([4.0, wall - d, 0.1]), np.array([0, 0, 1.0]),
                             None, 1, -1, geom)  # fmt: skip
        assert 0.1 + dist == pytest.approx(1.0 + d * math.tan(math.radians(40.0)), abs=1e-6)
        assert model.geom(int(geom[0])).name == "ceiling_attic_0"


def test_stair_soffit_seen_level_is_structure_and_seen_tilted_is_ceiling():
    """Facing the flight's foot, the level scanner's beam ends on the soffit (a surface in
    its plane, like a wall): STATIC. Tilted nose up by 15 deg, the same beam meets the
    soffit far higher than level: a CEILING point."""
    room = Room("hall", 0.0, 0.0, 12.0, 4.0)
    plain = assemble_house("stairs", None, 2.5, [room], [], [])
    stairs = Staircase("hall", "south", 6.0, 1.0, True)  # foot at x = 6.05, rising east
    house = with_extras(plain, HouseExtras(staircases=(stairs,)))
    soffit = house.features[-1]
    assert soffit.name == "ceiling_stairs_0_soffit"
    across = 0.05 + 0.5  # the flight's centreline (m from the south wall's centre line)
    start = [8.5, across, 0.25]  # under the flight, looking back down at its foot
    level, level_labels, lidar = _scanner_in(house, start, yaw=math.pi)
    toward_foot = _beam(lidar, 0.0)
    assert level_labels[toward_foot] == BeamLabel.STATIC
    assert level.labels[toward_foot] == BeamLabel.CEILING  # before the rule
    tilted, tilted_labels, _ = _scanner_in(house, start, pitch=math.radians(-25.0), yaw=math.pi)
    assert tilted.ranges[toward_foot] < level.ranges[toward_foot] * 0.8
    assert tilted_labels[toward_foot] == BeamLabel.CEILING


def test_a_level_scanner_never_sees_a_low_ramp_so_tilted_hits_on_it_are_floor():
    house = with_extras(
        assemble_house("ramp", None, 2.5, [LONG_ROOM], [], []),
        HouseExtras(floor_features=(FloorFeature("ramp", 1.5, 0.0, 0.0, 0.08, 3.0, 0.4, 8.0),)),
    )
    reading, labels, lidar = _scanner_in(house, [0.0, 0.0, 0.25], pitch=math.radians(10.0))
    ahead = _beam(lidar, 0.0)
    assert labels[ahead] == BeamLabel.FLOOR
    assert reading.ranges[ahead] < 0.25 / math.sin(math.radians(10.0))  # the ramp, before the floor


def test_wall_shelf_underside_is_a_horizontal_point():
    room = Room("room", 0.0, 0.0, 6.0, 4.0)
    plain = assemble_house("shelf", None, 2.5, [room], [], [])
    shelf = WallShelf("room", "east", 2.0, 1.0, 0.3, 0.8)
    house = with_extras(plain, HouseExtras(wall_shelves=(shelf,)))
    tilt = math.radians(15.0)
    # the board's underside at 0.775 m, from x = 5.65 m to the wall's face at 5.95 m: the
    # tilted beam rises to it at x = 5.8 m
    start_x = 5.8 - (0.775 - 0.25) / math.tan(tilt)
    reading, labels, lidar = _scanner_in(house, [start_x, 2.0, 0.25], pitch=-tilt)
    ahead = _beam(lidar, 0.0)
    assert labels[ahead] == BeamLabel.HORIZONTAL
    assert reading.ranges[ahead] == pytest.approx((0.775 - 0.25) / math.sin(tilt), abs=1e-6)


def test_a_lower_ceiling_lowers_the_walls_and_keeps_doorways_under_it():
    from twsb_sim.house import make_house
    from twsb_sim.house.named import plain_house

    house = with_extras(plain_house("house1"), HouseExtras(ceiling_height_m=2.0))
    assert house.ceiling_height_m == 2.0
    assert all(p.z_max_m <= 2.0 + 1e-9 for p in house.walls)
    assert all(d.height_m <= 1.9 + 1e-9 for d in house.doorways)
    assert house.spawn_poses == make_house("house1").spawn_poses
