"""The robot model: naming, geometry, configuration overrides and state readers."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from twsb_sim.config_errors import ConfigError, apply_overrides
from twsb_sim.robot import (
    LIDAR_SITE,
    MODELS_DIR,
    ROBOT_GEOM_GROUP,
    RobotConfig,
    RobotHandles,
    load_robot_spec,
    set_pose,
)

ELEMENT_KINDS = (
    (mujoco.mjtObj.mjOBJ_BODY, "nbody"),
    (mujoco.mjtObj.mjOBJ_JOINT, "njnt"),
    (mujoco.mjtObj.mjOBJ_GEOM, "ngeom"),
    (mujoco.mjtObj.mjOBJ_SITE, "nsite"),
    (mujoco.mjtObj.mjOBJ_ACTUATOR, "nu"),
    (mujoco.mjtObj.mjOBJ_SENSOR, "nsensor"),
)


def test_model_file_lives_in_models_dir():
    assert (MODELS_DIR / "twsb.xml").is_file()
    assert (MODELS_DIR / "README.md").is_file()


def test_every_element_is_named():
    model = load_robot_spec().compile()
    for kind, count in ELEMENT_KINDS:
        assert getattr(model, count) > 0
        for i in range(getattr(model, count)):
            name = mujoco.mj_id2name(model, kind, i)
            assert name, f"unnamed {kind.name} {i}"


def test_interface_elements_exist_by_name():
    model = load_robot_spec().compile()
    assert model.joint("root").type[0] == mujoco.mjtJoint.mjJNT_FREE
    for side in ("left", "right"):
        assert model.joint(f"{side}_wheel").type[0] == mujoco.mjtJoint.mjJNT_HINGE
        assert model.actuator(f"{side}_wheel_motor").ctrllimited[0]
    assert model.sensor("imu_gyro").type[0] == mujoco.mjtSensor.mjSENS_GYRO
    assert model.sensor("imu_accel").type[0] == mujoco.mjtSensor.mjSENS_ACCELEROMETER
    assert model.sensor("imu_quat").type[0] == mujoco.mjtSensor.mjSENS_FRAMEQUAT
    assert model.opt.timestep == pytest.approx(0.002)
    assert model.key("home")


def test_robot_geoms_are_hidden_from_the_lidar_and_wheels_touch_the_house():
    model = load_robot_spec().compile()
    assert np.all(model.geom_group == ROBOT_GEOM_GROUP)
    for side in ("left", "right"):
        wheel = model.geom(f"{side}_wheel")
        # house geoms keep MuJoCo's defaults: contype = conaffinity = 1
        assert wheel.contype[0] & 1 and wheel.conaffinity[0] & 1


def test_home_is_upright_with_wheels_on_the_floor(robot_on_floor):
    model, data = robot_on_floor()
    handles = RobotHandles(model)
    state = handles.read_balance_state(data)
    assert state.pitch_rad == 0.0 and state.roll_rad == 0.0 and state.yaw_rad == 0.0
    wheel = model.geom("left_wheel")
    assert data.geom_xpos[wheel.id][2] == pytest.approx(wheel.size[0])
    assert data.site(LIDAR_SITE).xpos[2] == pytest.approx(0.25)
    assert 6.0 <= model.body("base").subtreemass[0] <= 8.0


def test_centre_of_mass_is_well_above_the_axle(robot_on_floor):
    model, data = robot_on_floor()
    axle_height = model.geom("left_wheel").size[0]
    body_com = data.xipos[model.body("base").id]
    assert body_com[2] - axle_height > 0.15


def test_lidar_height_override_moves_the_lidar_site(robot_on_floor):
    _, data = robot_on_floor(RobotConfig(lidar_height_m=0.4))
    assert data.site(LIDAR_SITE).xpos[2] == pytest.approx(0.4)
    assert data.geom("lidar_head").xpos[2] == pytest.approx(0.4)


def test_mass_override_changes_the_model_mass():
    default = load_robot_spec().compile()
    heavier = load_robot_spec(RobotConfig(body_mass_kg=7.5)).compile()
    assert heavier.body("base").subtreemass[0] == pytest.approx(
        default.body("base").subtreemass[0] + 2.0
    )
    ratio = heavier.body("base").inertia / default.body("base").inertia
    assert ratio == pytest.approx(np.full(3, 7.5 / 5.5))


def test_com_offset_moves_the_body_centre_of_mass():
    default = load_robot_spec().compile()
    raised = load_robot_spec(RobotConfig(com_height_offset_m=0.05)).compile()
    shift = raised.body("base").ipos - default.body("base").ipos
    assert shift == pytest.approx([0.0, 0.0, 0.05])


def test_motor_limit_friction_and_wheel_radius_overrides(robot_on_floor):
    config = RobotConfig(wheel_torque_limit_nm=2.0, wheel_friction=0.6, wheel_radius_m=0.1)
    model, data = robot_on_floor(config)
    for side in ("left", "right"):
        assert model.actuator(f"{side}_wheel_motor").ctrlrange == pytest.approx([-2.0, 2.0])
        assert model.geom(f"{side}_wheel").friction[0] == pytest.approx(0.6)
        assert data.geom(f"{side}_wheel").xpos[2] == pytest.approx(0.1)
    assert data.site(LIDAR_SITE).xpos[2] == pytest.approx(0.25)


def test_wheel_friction_sets_the_floor_contact_friction(robot_on_floor):
    model, data = robot_on_floor(RobotConfig(wheel_friction=0.6))
    model.geom("floor").friction[0] = 1.5  # a house surface with its own friction
    mujoco.mj_step(model, data, nstep=5)
    assert data.ncon > 0
    assert all(contact.friction[0] == pytest.approx(0.6) for contact in data.contact)


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("lidar_height_m", 0.05),
        ("lidar_height_m", float("nan")),
        ("body_mass_kg", -1.0),
        ("com_height_offset_m", 1.0),
        ("wheel_radius_m", 0.0),
        ("wheel_torque_limit_nm", 0.0),
        ("wheel_friction", "high"),
    ],
)
def test_invalid_config_raises_naming_the_field(field, value):
    with pytest.raises(ValueError, match=rf"^{field}: expected"):
        RobotConfig(**{field: value})


def test_toml_override_errors_name_file_and_key():
    config = apply_overrides(RobotConfig(), {"lidar_height_m": 0.3}, "s.toml", "robot")
    assert config.lidar_height_m == 0.3
    with pytest.raises(ConfigError, match=r"s\.toml: robot\.body_mass_kg: expected"):
        apply_overrides(RobotConfig(), {"body_mass_kg": 0.0}, "s.toml", "robot")


def test_set_pose_places_the_robot_upright_at_rest(robot_on_floor):
    model, data = robot_on_floor()
    data.qvel[:] = 1.0
    set_pose(model, data, 1.5, -2.0, 0.7)
    state = RobotHandles(model).read_balance_state(data)
    assert state.yaw_rad == pytest.approx(0.7)
    assert state.pitch_rad == pytest.approx(0.0) and state.roll_rad == pytest.approx(0.0)
    assert np.all(data.qvel == 0.0)
    assert data.site(LIDAR_SITE).xpos == pytest.approx(
        [1.5, -2.0 + 0.02 * math.cos(0.7), 0.25], abs=0.03
    )
    assert data.body("base").xpos[:2] == pytest.approx([1.5, -2.0])


def test_balance_state_follows_rep103_signs(robot_on_floor):
    model, data = robot_on_floor(RobotConfig(lidar_tilt_pitch_deg=0.0, lidar_tilt_roll_deg=0.0))
    handles = RobotHandles(model)
    a, b = handles.qpos_adr, handles.qvel_adr
    yaw, pitch = 0.5, 0.1  # nose down
    # yaw about world z, then pitch about the new body y
    data.qpos[a + 3 : a + 7] = [
        math.cos(yaw / 2) * math.cos(pitch / 2),
        -math.sin(yaw / 2) * math.sin(pitch / 2),
        math.cos(yaw / 2) * math.sin(pitch / 2),
        math.sin(yaw / 2) * math.cos(pitch / 2),
    ]
    heading = np.array([math.cos(yaw), math.sin(yaw)])
    data.qvel[b : b + 2] = 0.8 * heading  # world frame
    data.qvel[b + 3 : b + 6] = [0.0, 0.2, 0.3]  # body frame: pitching down, turning left
    data.qvel[handles.wheel_qvel_adr[0]] = 4.0
    mujoco.mj_forward(model, data)
    state = handles.read_balance_state(data)
    assert state.pitch_rad == pytest.approx(pitch)
    assert state.yaw_rad == pytest.approx(yaw)
    assert state.forward_velocity_mps == pytest.approx(0.8)
    assert state.pitch_rate_rad_s == pytest.approx(0.2)
    assert state.yaw_rate_rad_s == pytest.approx(0.3 / math.cos(pitch))
    assert state.left_wheel_speed_rad_s == 4.0
    # nose down: the scanner's forward axis points below the horizon
    assert data.site(LIDAR_SITE).xmat.reshape(3, 3)[2, 0] == pytest.approx(-math.sin(pitch))


def test_imu_reads_gravity_and_identity_at_rest(robot_on_floor):
    model, data = robot_on_floor()
    mujoco.mj_step(model, data, nstep=100)  # settle onto the soft floor contact
    gyro, accel, quat = RobotHandles(model).read_imu(data)
    assert gyro == pytest.approx([0.0, 0.0, 0.0])
    assert accel == pytest.approx([0.0, 0.0, 9.81], abs=0.05)
    assert quat == pytest.approx([1.0, 0.0, 0.0, 0.0])
