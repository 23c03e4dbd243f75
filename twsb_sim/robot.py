"""The robot model: configuration, loading into an ``MjSpec``, and fast state readers.

``models/twsb.xml`` holds the robot alone (no floor): houses add their floor, walls and
ceiling to the spec returned by :func:`load_robot_spec`. The body frame of ``base`` sits
at the wheel axle centre (REP-103: x forward, y left, z up), so pitching the body does
not move the wheels. Positive pitch is a rotation about the body's y axis: nose down.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import NamedTuple

import mujoco
import numpy as np

from twsb_sim.kernel import kernel

MODELS_DIR = Path(__file__).resolve().parent.parent / "models"
ROBOT_XML = MODELS_DIR / "twsb.xml"

ROBOT_GEOM_GROUP = 3  # every robot geom; the LiDAR ray cast excludes this group

BASE_BODY = "base"
FREE_JOINT = "root"
LIDAR_MOUNT_BODY = "lidar_mount"
LIDAR_SITE = "lidar"
IMU_SITE = "imu"
WHEEL_JOINTS = ("left_wheel", "right_wheel")
WHEEL_GEOMS = ("left_wheel", "right_wheel")
WHEEL_MOTORS = ("left_wheel_motor", "right_wheel_motor")
IMU_SENSORS = ("imu_gyro", "imu_accel", "imu_quat")
LIDAR_POSE_SENSORS = ("lidar_pos", "lidar_quat")
ENCODER_SENSORS = ("left_wheel_angle", "right_wheel_angle")
HOME_KEY = "home"


def _check_range(name: str, value: float, low: float, high: float) -> None:
    if not (isinstance(value, int | float) and not isinstance(value, bool)):
        raise ValueError(f"{name}: expected a number, got {value!r}")
    if not (low <= value <= high):
        raise ValueError(f"{name}: expected a value in [{low}, {high}], got {value!r}")


@dataclass(frozen=True)
class RobotConfig:
    """Physical parameters applied on top of ``models/twsb.xml``.

    The defaults reproduce the MJCF file unchanged. The LiDAR mount is a little off the
    axle centre and its scan plane a little off level, as on a real robot; zero offsets
    and tilts give the ideal mount.
    """

    lidar_height_m: float = 0.25  # m, scanner origin above the floor when upright
    body_mass_kg: float = 5.5  # kg, everything but the wheels (inertia scales with it)
    com_height_offset_m: float = 0.0  # m, shift of the body's centre of mass along body z
    wheel_radius_m: float = 0.08  # m
    wheel_torque_limit_nm: float = 3.0  # N·m, per wheel motor
    wheel_friction: float = 1.0  # sliding friction coefficient of the tyres on the floor
    lidar_offset_x_m: float = 0.03  # m, LiDAR origin ahead of the axle centre
    lidar_offset_y_m: float = 0.02  # m, LiDAR origin left of the centre line
    lidar_tilt_pitch_deg: float = 1.0  # deg, scan plane tilt on the robot, + = nose down
    lidar_tilt_roll_deg: float = 0.5  # deg, scan plane tilt on the robot, + = left side up

    def __post_init__(self) -> None:
        _check_range("wheel_radius_m", self.wheel_radius_m, 0.03, 0.2)
        _check_range("lidar_height_m", self.lidar_height_m, self.wheel_radius_m + 0.02, 1.0)
        _check_range("body_mass_kg", self.body_mass_kg, 0.5, 50.0)
        _check_range("com_height_offset_m", self.com_height_offset_m, -0.2, 0.3)
        _check_range("wheel_torque_limit_nm", self.wheel_torque_limit_nm, 0.1, 50.0)
        _check_range("wheel_friction", self.wheel_friction, 0.05, 3.0)
        _check_range("lidar_offset_x_m", self.lidar_offset_x_m, -0.15, 0.15)
        _check_range("lidar_offset_y_m", self.lidar_offset_y_m, -0.15, 0.15)
        _check_range("lidar_tilt_pitch_deg", self.lidar_tilt_pitch_deg, -10.0, 10.0)
        _check_range("lidar_tilt_roll_deg", self.lidar_tilt_roll_deg, -10.0, 10.0)


def load_robot_spec(config: RobotConfig = RobotConfig()) -> mujoco.MjSpec:
    """Load ``models/twsb.xml`` and apply ``config`` by editing the spec.

    Args:
        config: the physical parameters to apply.

    Returns:
        An uncompiled spec of the robot alone (no floor), ready for a house to be added.
    """
    spec = mujoco.MjSpec.from_file(str(ROBOT_XML))
    base = spec.body(BASE_BODY)
    xml_mass = base.mass
    base.mass = config.body_mass_kg
    base.inertia = [i * config.body_mass_kg / xml_mass for i in base.inertia]
    base.ipos = [base.ipos[0], base.ipos[1], base.ipos[2] + config.com_height_offset_m]
    radius = config.wheel_radius_m
    base.pos = [base.pos[0], base.pos[1], radius]
    for name in WHEEL_GEOMS:
        geom = spec.geom(name)
        geom.size = [radius, radius, geom.size[2]]
        geom.friction = [config.wheel_friction, geom.friction[1], geom.friction[2]]
    for name in WHEEL_MOTORS:
        limit = config.wheel_torque_limit_nm
        spec.actuator(name).ctrlrange = [-limit, limit]
    mount = spec.body(LIDAR_MOUNT_BODY)
    mount.pos = [config.lidar_offset_x_m, config.lidar_offset_y_m, config.lidar_height_m - radius]
    mount.quat = mount_quat(config.lidar_tilt_pitch_deg, config.lidar_tilt_roll_deg)
    home = spec.key(HOME_KEY)
    qpos = list(home.qpos)
    qpos[2] = radius
    home.qpos = qpos
    return spec


def mount_quat(pitch_deg: float, roll_deg: float) -> list[float]:
    """The LiDAR mount's orientation on the body, (w, x, y, z): pitch about y (+ = nose
    down), then roll about x (+ = left side up), the Z-Y-X order of the robot's angles."""
    half_pitch, half_roll = math.radians(pitch_deg) / 2, math.radians(roll_deg) / 2
    cp, sp, cr, sr = (
        math.cos(half_pitch),
        math.sin(half_pitch),
        math.cos(half_roll),
        math.sin(half_roll),
    )
    return [cp * cr, cp * sr, sp * cr, -sp * sr]


class BalanceState(NamedTuple):
    """The robot's state as a balance controller sees it (REP-103, SI units)."""

    pitch_rad: float  # rotation about body y, positive = nose down
    pitch_rate_rad_s: float
    forward_velocity_mps: float  # axle velocity along the heading, horizontal plane
    yaw_rad: float  # heading in the world, counter-clockwise from world x
    yaw_rate_rad_s: float
    roll_rad: float  # rotation about body x, positive = left side up
    left_wheel_speed_rad_s: float  # relative to the body, positive = rolling forward
    right_wheel_speed_rad_s: float


_new_tuple = tuple.__new__


@kernel
def balance_state(
    quat: np.ndarray, qvel: np.ndarray, b: int, left: int, right: int
) -> tuple[float, float, float, float, float, float, float, float]:
    """The balance state as a plain tuple in the order of :class:`BalanceState`.

    Args:
        quat: the base's orientation (w, x, y, z), a view of ``qpos``.
        qvel: the model's ``qvel``; ``b`` is the free joint's first dof (vx vy vz in
            the world, wx wy wz in the body frame), ``left`` and ``right`` the wheels'.
    """
    qw, qx, qy, qz = quat[0], quat[1], quat[2], quat[3]
    vx, vy, wy, wz = qvel[b], qvel[b + 1], qvel[b + 4], qvel[b + 5]
    # ZYX (yaw, pitch, roll) angles of the body frame
    sin_pitch = 2.0 * (qw * qy - qx * qz)
    sin_pitch = 1.0 if sin_pitch > 1.0 else (-1.0 if sin_pitch < -1.0 else sin_pitch)
    pitch = math.asin(sin_pitch)
    yaw = math.atan2(2.0 * (qx * qy + qw * qz), 1.0 - 2.0 * (qy * qy + qz * qz))
    roll = math.atan2(2.0 * (qy * qz + qw * qx), 1.0 - 2.0 * (qx * qx + qy * qy))
    sin_roll = math.sin(roll)
    cos_roll = math.cos(roll)
    # Euler-angle rates from the body-frame angular velocity
    pitch_rate = cos_roll * wy - sin_roll * wz
    yaw_rate = (sin_roll * wy + cos_roll * wz) / math.cos(pitch)
    forward_velocity = math.cos(yaw) * vx + math.sin(yaw) * vy
    return (pitch, pitch_rate, forward_velocity, yaw, yaw_rate, roll, qvel[left], qvel[right])


class RobotHandles:
    """Addresses of the robot's elements in a compiled model, resolved once by name.

    The model may hold more than the robot (a house); only the robot's entries are read.
    """

    def __init__(self, model: mujoco.MjModel) -> None:
        root = model.joint(FREE_JOINT)
        self.qpos_adr = int(root.qposadr[0])  # x y z, qw qx qy qz
        self.qvel_adr = int(root.dofadr[0])  # vx vy vz (world), wx wy wz (body)
        left, right = (model.joint(name) for name in WHEEL_JOINTS)
        self.wheel_qpos_adr = (int(left.qposadr[0]), int(right.qposadr[0]))
        self.wheel_qvel_adr = (int(left.dofadr[0]), int(right.dofadr[0]))
        self.actuator_ids = tuple(model.actuator(name).id for name in WHEEL_MOTORS)
        self.torque_limit_nm = float(model.actuator(WHEEL_MOTORS[0]).ctrlrange[1])
        self.wheel_radius_m = float(model.geom(WHEEL_GEOMS[0]).size[0])
        self.track_width_m = float(
            model.body(WHEEL_JOINTS[0]).pos[1] - model.body(WHEEL_JOINTS[1]).pos[1]
        )
        self.base_body_id = model.body(BASE_BODY).id
        self.lidar_site_id = model.site(LIDAR_SITE).id
        self.imu_site_id = model.site(IMU_SITE).id
        self.imu_slices = {
            name: slice(
                int(model.sensor(name).adr[0]),
                int(model.sensor(name).adr[0] + model.sensor(name).dim[0]),
            )
            for name in IMU_SENSORS
        }
        self._data: mujoco.MjData | None = None  # the data self._read is bound to

    def read_balance_state(self, data: mujoco.MjData) -> BalanceState:
        """The balance state now, from ``qpos`` and ``qvel`` alone (cheap: every step)."""
        if data is not self._data:
            self._data, self._read = data, self.state_reader(data)
        # tuple.__new__ skips the NamedTuple's Python-level __new__: 0.2 us of ~1.5 us
        return _new_tuple(BalanceState, self._read())

    def state_reader(self, data: mujoco.MjData) -> Callable[[], tuple[float, ...]]:
        """A function returning ``data``'s balance state as a plain tuple, in the order of
        :class:`BalanceState`. ``data``'s arrays and the addresses are bound once (each
        ``data.qpos`` access builds a new array object)."""
        a, b = self.qpos_adr, self.qvel_adr
        quat, qvel = data.qpos[a + 3 : a + 7], data.qvel
        left, right = self.wheel_qvel_adr

        def read() -> tuple[float, ...]:
            return balance_state(quat, qvel, b, left, right)

        return read

    def read_imu(self, data: mujoco.MjData) -> tuple[list[float], list[float], list[float]]:
        """The IMU's readings (``data.sensordata``, valid after ``mj_forward``/``mj_step``).

        Returns:
            ``(gyro, accel, quat)``: angular velocity in rad/s and specific force in m/s²
            (gravity included: +9.81 on z at rest), both in the imu frame; orientation of
            the imu frame in the world as (w, x, y, z).
        """
        s = data.sensordata
        return tuple(s[self.imu_slices[name]].tolist() for name in IMU_SENSORS)


def set_pose(
    model: mujoco.MjModel, data: mujoco.MjData, x_m: float, y_m: float, yaw_rad: float
) -> None:
    """Place the robot upright at a world pose with zero velocity, wheels on the floor.

    Only the robot's joints are touched; derived quantities are updated (``mj_forward``).

    Args:
        x_m, y_m: axle centre position in the world, m.
        yaw_rad: heading, counter-clockwise from world x, rad.
    """
    handles = RobotHandles(model)
    a = handles.qpos_adr
    half = 0.5 * yaw_rad
    data.qpos[a : a + 7] = [
        x_m,
        y_m,
        handles.wheel_radius_m,
        math.cos(half),
        0.0,
        0.0,
        math.sin(half),
    ]
    for adr in handles.wheel_qpos_adr:
        data.qpos[adr] = 0.0
    b = handles.qvel_adr
    data.qvel[b : b + 6] = 0.0
    for adr in handles.wheel_qvel_adr:
        data.qvel[adr] = 0.0
    mujoco.mj_forward(model, data)
