"""LQR balance and tracking: design checks, and the closed loop on the MuJoCo model."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from twsb_sim.control import (
    LqrConfig,
    LqrController,
    UnstableClosedLoopError,
    compute_gains,
    linearize,
)
from twsb_sim.control.linearization import I_PITCH, I_PITCH_RATE, I_VX
from twsb_sim.robot import LIDAR_SITE, RobotConfig

DT = 0.002  # s, physics step
FALL_PITCH_RAD = math.radians(45.0)


def simulate(model, data, controller, duration_s, velocity_mps=0.0, yaw_rate_rad_s=0.0):
    """Run the closed loop; return per-step arrays of the state and the torques."""
    handles = controller.handles
    steps = round(duration_s / DT)
    states = np.empty((steps, 8))
    torques = np.empty((steps, 2))
    for k in range(steps):
        torques[k] = controller.apply(data, velocity_mps, yaw_rate_rad_s)
        mujoco.mj_step(model, data)
        states[k] = handles.read_balance_state(data)
    return states, torques


PITCH, PITCH_RATE, VELOCITY, YAW, YAW_RATE = 0, 1, 2, 3, 4  # columns of BalanceState


def test_closed_loop_eigenvalues_are_inside_the_unit_circle():
    gains = compute_gains(RobotConfig(), LqrConfig())
    assert len(gains.sagittal_eigenvalues) == 4
    assert len(gains.yaw_eigenvalues) == 2
    assert len(gains.full_eigenvalues) == 13  # 16 + 2 integrators - 5 marginal coordinates
    for eigenvalues in (gains.sagittal_eigenvalues, gains.yaw_eigenvalues, gains.full_eigenvalues):
        assert max(abs(e) for e in eigenvalues) < 1.0
    # balancing: a nose-down pitch drives the wheels forward
    assert gains.sagittal[0] < 0.0


def test_upright_robot_without_control_is_unstable():
    a, _, _, _, _ = linearize(RobotConfig())
    assert max(abs(np.linalg.eigvals(a))) > 1.001


def test_an_unweighted_integrator_is_rejected():
    # a zero weight leaves the velocity integrator out of the cost: it stays marginal
    with pytest.raises(UnstableClosedLoopError, match="sagittal model"):
        compute_gains(RobotConfig(), LqrConfig(velocity_integral_weight=0.0))


def test_gains_are_cached_per_configuration():
    assert compute_gains(RobotConfig(), LqrConfig()) is compute_gains(RobotConfig(), LqrConfig())


@pytest.mark.parametrize(
    ("field", "value"),
    [("pitch_weight", -1.0), ("torque_weight", 0.0), ("aggressiveness", float("inf"))],
)
def test_invalid_config_raises_naming_the_field(field, value):
    with pytest.raises(ValueError, match=rf"^{field}: expected"):
        LqrConfig(**{field: value})


def test_controller_rejects_a_model_built_from_another_config(robot_on_floor):
    model, _ = robot_on_floor(RobotConfig(wheel_torque_limit_nm=2.0))
    with pytest.raises(ValueError, match=r"^wheel_torque_limit_nm:"):
        LqrController(model, RobotConfig())


def test_one_second_from_home_with_bounded_controls_and_no_warnings(robot_on_floor):
    model, data = robot_on_floor()
    controller = LqrController(model)
    _, torques = simulate(model, data, controller, 1.0, 0.3, 0.2)
    assert np.all(np.abs(torques) <= 3.0)
    assert np.all(np.isfinite(data.qpos))
    assert all(warning.number == 0 for warning in data.warning)


def test_standing_still_for_60_s_keeps_pitch_below_one_degree(robot_on_floor):
    model, data = robot_on_floor()
    controller = LqrController(model)
    data.qvel[controller.handles.qvel_adr + 4] = 0.05  # rad/s: a nudge, so it must act
    states, _ = simulate(model, data, controller, 60.0)
    assert np.max(np.abs(states[:, PITCH])) < math.radians(1.0)
    assert np.max(np.abs(states[-5000:, PITCH])) < math.radians(0.01)
    assert np.linalg.norm(data.body("base").xpos[:2]) < 0.05


def test_tracks_forward_velocity_and_yaw_rate_in_steady_state(robot_on_floor):
    model, data = robot_on_floor()
    states, _ = simulate(model, data, LqrController(model), 10.0, 1.0, 0.6)
    last_two_seconds = states[-1000:]
    assert np.max(np.abs(last_two_seconds[:, VELOCITY] - 1.0)) < 0.03
    assert np.max(np.abs(last_two_seconds[:, YAW_RATE] - 0.6)) < 0.02
    assert np.max(np.abs(states[:, PITCH])) < FALL_PITCH_RAD


def test_tracks_velocity_alone_and_yaw_rate_alone(robot_on_floor):
    model, data = robot_on_floor()
    controller = LqrController(model)
    forward, _ = simulate(model, data, controller, 8.0, 1.0, 0.0)
    assert np.mean(forward[-1000:, VELOCITY]) == pytest.approx(1.0, abs=0.03)
    assert np.max(np.abs(forward[-1000:, YAW_RATE])) < 0.01
    turning, _ = simulate(model, data, controller, 8.0, 0.0, -0.6)
    assert np.mean(turning[-1000:, YAW_RATE]) == pytest.approx(-0.6, abs=0.02)
    assert np.max(np.abs(turning[-1000:, VELOCITY])) < 0.03


def test_hard_stop_from_1_mps_pitches_several_degrees_without_falling(robot_on_floor):
    model, data = robot_on_floor()
    controller = LqrController(model)
    simulate(model, data, controller, 6.0, 1.0)
    states, _ = simulate(model, data, controller, 4.0, 0.0)
    peak = np.max(np.abs(states[:, PITCH]))
    assert math.radians(8.0) <= peak < math.radians(30.0)
    assert np.max(np.abs(states[:, PITCH])) < FALL_PITCH_RAD
    # braking leans the robot back (nose up): the scan plane meets the floor behind it
    assert np.min(states[:, PITCH]) == -peak
    lidar_height = data.site(LIDAR_SITE).xpos[2]
    assert 0.3 <= lidar_height / math.tan(peak) <= 2.0
    assert np.max(np.abs(states[-500:, VELOCITY])) < 0.05
    assert np.max(np.abs(states[-500:, PITCH])) < math.radians(1.0)


def test_torques_saturate_at_the_motor_limit(robot_on_floor):
    config = RobotConfig(wheel_torque_limit_nm=2.0)
    model, data = robot_on_floor(config)
    controller = LqrController(model, config)
    data.qvel[controller.handles.qvel_adr + 4] = 3.0  # rad/s: a shove that pitches it down
    left, right = controller.apply(data, 0.0, 0.0)
    assert (left, right) == (2.0, 2.0)
    assert data.ctrl[list(controller.handles.actuator_ids)] == pytest.approx([2.0, 2.0])
    _, torques = simulate(model, data, controller, 2.0, -1.0, 0.6)
    assert np.max(np.abs(torques)) == 2.0


def _linear_step_response(command_mps: float, steps: int) -> np.ndarray:
    """Pitch and velocity of the linearized closed loop after a velocity step."""
    a, b, dt, _, _ = linearize(RobotConfig())
    gains = compute_gains(RobotConfig(), LqrConfig())
    k0, k1, k2, k3 = gains.sagittal
    x = np.zeros(a.shape[0])
    integral = 0.0
    out = np.empty((steps, 2))
    for k in range(steps):
        error = x[I_VX] - command_mps
        common = gains.velocity_feedforward * command_mps - (
            k0 * x[I_PITCH] + k1 * x[I_PITCH_RATE] + k2 * error + k3 * integral
        )
        integral += dt * error
        x = a @ x + b @ np.array([common, common])
        out[k] = x[I_PITCH], x[I_VX]
    return out


def test_small_velocity_step_matches_the_linear_closed_loop(robot_on_floor):
    model, data = robot_on_floor()
    controller = LqrController(model)
    simulate(model, data, controller, 1.0)  # settle on the soft contact
    controller.reset()
    command = 0.1  # m/s: small enough to stay linear and unsaturated
    states, torques = simulate(model, data, controller, 3.0, command)
    predicted = _linear_step_response(command, len(states))
    assert np.max(np.abs(torques)) < 3.0
    peak_pitch = np.max(np.abs(predicted[:, 0]))
    assert peak_pitch > math.radians(1.0)
    # within 1 % of the pitch peak and of the command, at every step
    assert np.max(np.abs(states[:, PITCH] - predicted[:, 0])) < 0.01 * peak_pitch
    assert np.max(np.abs(states[:, VELOCITY] - predicted[:, 1])) < 0.01 * command
