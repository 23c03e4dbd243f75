"""LQR balance with forward-velocity and yaw-rate tracking, designed on the MJCF model.

Linearization. The robot spec (``load_robot_spec``) plus a flat floor plane is compiled
and put in its ``home`` keyframe: upright, at rest, zero torque. The axle height is first
settled onto the soft floor contact (Newton iterations on the vertical acceleration), so
the linearization point is an equilibrium. ``mujoco.mjd_transitionFD`` (centred
differences) then gives the discrete-time transition of one physics step ``dt``::

    x[k+1] = A x[k] + B u[k],   x = (dq, dv) in R^16,   u = (tau_left, tau_right) N·m

with ``dq`` the position tangent (free joint: x y z, then rotation about body x y z;
the two wheel angles) and ``dv`` the matching velocities (free joint linear velocity in
the world, angular velocity in the body frame; wheel speeds relative to the body).

Reduction. Upright and at rest, the body axes coincide with the world axes, so
``dq[4]`` is the pitch, ``dv[4]`` the pitch rate, ``dv[0]`` the forward velocity and
``dv[5]`` the yaw rate. Two subsystems are cut out with a selection matrix ``S`` (reads
reduced states from a full state) and an embedding ``T`` (builds the full state that a
reduced state stands for, with the wheels rolling without slipping):

- sagittal, ``xs = (pitch, pitch_rate, forward_velocity)``, input the common torque
  ``us`` (both wheels get ``us``): ``T`` sets ``dq[4] = pitch``, ``dv[4] = pitch_rate``,
  ``dv[0] = v`` and both wheel speeds ``v / r - pitch_rate`` (r: wheel radius);
- yaw, ``xy = (yaw_rate,)``, input the differential torque ``ud`` (left ``-ud``, right
  ``+ud``): ``T`` sets ``dv[5] = yaw_rate`` and wheel speeds ``-/+ yaw_rate * w / (2 r)``
  (w: track width).

The reduced models are ``Ar = S A T`` and ``Br = S B M`` (``M`` mixes ``us`` or ``ud``
into the two wheel torques). Each is augmented with the discrete integral of its
tracking error (``z[k+1] = z[k] + dt * e[k]``), and ``control.dlqr`` gives the gains.

Checks. The closed loop of each reduced model must have all eigenvalues strictly inside
the unit circle. The gains are then mapped back onto the full 16-state model (plus the
two integrators) and its closed loop checked too, after removing the five coordinates
no controller can affect and that affect nothing: world x and y, yaw angle and the two
wheel angles. On a flat floor with round wheels these are pure integrators (their
columns of ``A`` are checked to be zero), so each contributes an eigenvalue of exactly
1 and the rest of the spectrum is that of the remaining 13 states. Either check failing
raises :class:`UnstableClosedLoopError`.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import mujoco
import numpy as np

from twsb_sim.robot import HOME_KEY, RobotConfig, RobotHandles, load_robot_spec

# Indices into the 16-dimensional tangent state (dq, dv) of the robot alone.
NV = 8
I_PITCH = 4  # dq: rotation about body y
I_VX = NV + 0  # dv: axle velocity along world x
I_PITCH_RATE = NV + 4  # dv: angular velocity about body y
I_YAW_RATE = NV + 5  # dv: angular velocity about body z
I_WHEEL_SPEED = (NV + 6, NV + 7)  # dv: left, right wheel speed relative to the body
# Coordinates that are pure integrators (flat floor, round wheels): x, y, yaw, wheel angles.
MARGINAL_COORDINATES = (0, 1, 5, 6, 7)

MAX_STABLE_EIGENVALUE = 1.0 - 1e-9  # discrete-time: strictly inside the unit circle


class UnstableClosedLoopError(RuntimeError):
    """LQR gains that do not stabilize the linearized robot."""


@dataclass(frozen=True)
class LqrConfig:
    """Weights of the LQR cost, per physics step: ``sum x' Q x + u' R u``.

    Larger state weights (or ``aggressiveness``) give a stiffer robot that corrects
    faster, pitches more sharply and saturates its motors more often.
    """

    pitch_weight: float = 100.0  # 1/rad², pitch away from upright
    pitch_rate_weight: float = 1.0  # 1/(rad/s)², pitch rate
    velocity_weight: float = 300.0  # 1/(m/s)², forward velocity minus command
    velocity_integral_weight: float = 0.1  # 1/m², time integral of that error
    yaw_rate_weight: float = 10.0  # 1/(rad/s)², yaw rate minus command
    yaw_integral_weight: float = 0.1  # 1/rad², time integral of that error
    torque_weight: float = 10.0  # 1/(N·m)², common and differential wheel torque
    aggressiveness: float = 1.0  # multiplies every state weight

    def __post_init__(self) -> None:
        for name in (
            "pitch_weight",
            "pitch_rate_weight",
            "velocity_weight",
            "velocity_integral_weight",
            "yaw_rate_weight",
            "yaw_integral_weight",
        ):
            value = getattr(self, name)
            if not _is_number(value) or not (0.0 <= value < math.inf):
                raise ValueError(f"{name}: expected a finite number >= 0, got {value!r}")
        for name in ("torque_weight", "aggressiveness"):
            value = getattr(self, name)
            if not _is_number(value) or not (0.0 < value < math.inf):
                raise ValueError(f"{name}: expected a finite number > 0, got {value!r}")


def _is_number(value: object) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


@dataclass(frozen=True)
class LqrGains:
    """Gains of ``us = -sagittal . (pitch, pitch_rate, v - v_cmd, int(v - v_cmd))`` and
    ``ud = -yaw . (yaw_rate - cmd, int(yaw_rate - cmd))``, with the closed-loop spectra."""

    sagittal: tuple[float, float, float, float]  # N·m/rad, N·m·s/rad, N·m·s/m, N·m/m
    yaw: tuple[float, float]  # N·m·s/rad, N·m/rad
    velocity_feedforward: float  # N·m per m/s commanded, added to the common torque
    yaw_rate_feedforward: float  # N·m per rad/s commanded, added to the differential torque
    dt: float  # s, the physics step the gains are designed for
    sagittal_eigenvalues: tuple[complex, ...]
    yaw_eigenvalues: tuple[complex, ...]
    full_eigenvalues: tuple[complex, ...]  # 13 states: all but the marginal coordinates


def linearize(robot_config: RobotConfig) -> tuple[np.ndarray, np.ndarray, float, float, float]:
    """Linearize the robot on a flat floor around ``home``.

    Returns:
        ``(A, B, dt, wheel_radius_m, track_width_m)``: the discrete transition (16x16 and
        16x2) of one physics step of ``dt`` s.
    """
    spec = load_robot_spec(robot_config)
    spec.worldbody.add_geom(
        name="linearization_floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[10.0, 10.0, 0.1]
    )
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key(HOME_KEY).id)
    handles = RobotHandles(model)
    # Settle the axle onto the soft contact: bisect for the height with zero vertical
    # acceleration (free fall above it, pushed up below it).
    z_adr = handles.qpos_adr + 2
    az_adr = handles.qvel_adr + 2
    low, high = handles.wheel_radius_m - 0.01, handles.wheel_radius_m
    for _ in range(50):
        data.qpos[z_adr] = 0.5 * (low + high)
        mujoco.mj_forward(model, data)
        if data.qacc[az_adr] > 0.0:
            low = data.qpos[z_adr]
        else:
            high = data.qpos[z_adr]
    mujoco.mj_forward(model, data)
    n = 2 * model.nv + model.na
    a = np.zeros((n, n))
    b = np.zeros((n, model.nu))
    mujoco.mjd_transitionFD(model, data, 1e-6, True, a, b, None, None)
    return a, b, model.opt.timestep, handles.wheel_radius_m, handles.track_width_m


def _check_spectrum(what: str, eigenvalues: np.ndarray) -> None:
    worst = float(np.max(np.abs(eigenvalues)))
    if worst > MAX_STABLE_EIGENVALUE:
        raise UnstableClosedLoopError(
            f"{what}: closed-loop eigenvalue of magnitude {worst:.9f} (must be < 1): "
            "the LQR gains do not stabilize the robot; change the LqrConfig weights"
        )


def _augment(
    ar: np.ndarray, br: np.ndarray, error_row: int, dt: float
) -> tuple[np.ndarray, np.ndarray]:
    """Append the discrete integral of state ``error_row``."""
    n = ar.shape[0]
    aa = np.zeros((n + 1, n + 1))
    aa[:n, :n] = ar
    aa[n, error_row] = dt
    aa[n, n] = 1.0
    ba = np.vstack([br, np.zeros((1, br.shape[1]))])
    return aa, ba


def closed_loop_full(
    a: np.ndarray, b: np.ndarray, gains_s: np.ndarray, gains_y: np.ndarray, dt: float
) -> np.ndarray:
    """The full linear closed loop (16 states + 2 integrators) with the marginal
    coordinates removed (see the module docstring).

    Args:
        a, b: the full discrete model from :func:`linearize`.
        gains_s: the 4 sagittal gains; gains_y: the 2 yaw gains.

    Returns:
        The 13x13 closed-loop transition matrix.
    """
    n = a.shape[0]
    # Integrators: zs += dt * v, zy += dt * yaw_rate (zero commands).
    aa = np.zeros((n + 2, n + 2))
    aa[:n, :n] = a
    aa[n, I_VX] = dt
    aa[n + 1, I_YAW_RATE] = dt
    aa[n, n] = aa[n + 1, n + 1] = 1.0
    ba = np.vstack([b, np.zeros((2, b.shape[1]))])
    # Gains on the full state: us = -ks . (pitch, pitch_rate, v, zs); ud = -ky . (yaw_rate, zy)
    k = np.zeros((2, n + 2))
    ks = np.zeros(n + 2)
    ks[[I_PITCH, I_PITCH_RATE, I_VX, n]] = gains_s
    ky = np.zeros(n + 2)
    ky[[I_YAW_RATE, n + 1]] = gains_y
    k[0] = ks - ky  # left = us - ud
    k[1] = ks + ky  # right = us + ud
    closed = aa - ba @ k
    keep = [i for i in range(n + 2) if i not in MARGINAL_COORDINATES]
    return closed[np.ix_(keep, keep)]


@functools.lru_cache(maxsize=32)
def compute_gains(robot_config: RobotConfig, lqr_config: LqrConfig) -> LqrGains:
    """Design the LQR gains on the linearized MJCF model and check the closed loop.

    Cached: the same configurations return the same gains without recomputation.

    Raises:
        UnstableClosedLoopError: if the reduced or the full closed loop is unstable.
    """
    import control  # slow to import (matplotlib): only where gains are designed

    a, b, dt, radius, track = linearize(robot_config)
    n = a.shape[0]
    marginal_columns = a[:, list(MARGINAL_COORDINATES)].copy()
    marginal_columns[list(MARGINAL_COORDINATES), range(len(MARGINAL_COORDINATES))] -= 1.0
    if np.max(np.abs(marginal_columns)) > 1e-6:
        raise UnstableClosedLoopError(
            "linearization: x, y, yaw or wheel angles affect the dynamics; "
            "the reduction assumes a flat floor and round wheels"
        )

    # Sagittal: xs = (pitch, pitch_rate, v), us common torque.
    s_sag = np.zeros((3, n))
    s_sag[[0, 1, 2], [I_PITCH, I_PITCH_RATE, I_VX]] = 1.0
    t_sag = s_sag.T.copy()
    for i in I_WHEEL_SPEED:
        t_sag[i, 1] = -1.0
        t_sag[i, 2] = 1.0 / radius
    m_sag = np.array([[1.0], [1.0]])
    a_sag, b_sag = _augment(s_sag @ a @ t_sag, s_sag @ b @ m_sag, 2, dt)

    # Yaw: xy = (yaw_rate,), ud differential torque (left -ud, right +ud).
    s_yaw = np.zeros((1, n))
    s_yaw[0, I_YAW_RATE] = 1.0
    t_yaw = s_yaw.T.copy()
    t_yaw[I_WHEEL_SPEED[0], 0] = -0.5 * track / radius
    t_yaw[I_WHEEL_SPEED[1], 0] = 0.5 * track / radius
    m_yaw = np.array([[-1.0], [1.0]])
    a_yaw, b_yaw = _augment(s_yaw @ a @ t_yaw, s_yaw @ b @ m_yaw, 0, dt)

    c = lqr_config
    q_sag = c.aggressiveness * np.diag(
        [c.pitch_weight, c.pitch_rate_weight, c.velocity_weight, c.velocity_integral_weight]
    )
    q_yaw = c.aggressiveness * np.diag([c.yaw_rate_weight, c.yaw_integral_weight])
    r = np.array([[c.torque_weight]])
    k_sag, _, _ = control.dlqr(a_sag, b_sag, q_sag, r)
    k_yaw, _, _ = control.dlqr(a_yaw, b_yaw, q_yaw, r)
    k_sag = np.asarray(k_sag)[0]
    k_yaw = np.asarray(k_yaw)[0]

    # Feedforward: the reduced model's equilibrium at a unit command (pitch, pitch rate
    # and torque that hold v = 1 m/s, or yaw rate = 1 rad/s, against the wheel damping).
    # The controller regulates the deviation from it; the integrators only correct for
    # what the linear model gets wrong.
    ar = a_sag[:3, :3] - np.eye(3)
    pitch_ss, rate_ss, torque_ss = np.linalg.solve(
        np.column_stack([ar[:, 0], ar[:, 1], b_sag[:3, 0]]), -ar[:, 2]
    )
    velocity_feedforward = k_sag[0] * pitch_ss + k_sag[1] * rate_ss + torque_ss
    yaw_rate_feedforward = (1.0 - a_yaw[0, 0]) / b_yaw[0, 0]

    eig_sag = np.linalg.eigvals(a_sag - b_sag @ k_sag[None, :])
    eig_yaw = np.linalg.eigvals(a_yaw - b_yaw @ k_yaw[None, :])
    _check_spectrum("sagittal model", eig_sag)
    _check_spectrum("yaw model", eig_yaw)
    eig_full = np.linalg.eigvals(closed_loop_full(a, b, k_sag, k_yaw, dt))
    _check_spectrum("full model", eig_full)
    return LqrGains(
        sagittal=tuple(float(g) for g in k_sag),
        yaw=tuple(float(g) for g in k_yaw),
        velocity_feedforward=float(velocity_feedforward),
        yaw_rate_feedforward=float(yaw_rate_feedforward),
        dt=dt,
        sagittal_eigenvalues=tuple(complex(e) for e in eig_sag),
        yaw_eigenvalues=tuple(complex(e) for e in eig_yaw),
        full_eigenvalues=tuple(complex(e) for e in eig_full),
    )


class LqrController:
    """Balances the robot and tracks forward-velocity and yaw-rate commands.

    Call :meth:`apply` once per physics step, before ``mj_step``. The integrators of the
    tracking errors stop while a motor saturates (anti-windup).
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        robot_config: RobotConfig | None = None,
        config: LqrConfig | None = None,
    ) -> None:
        """Resolve the robot in ``model`` and design (or fetch cached) gains.

        Args:
            model: a compiled model holding the robot built from ``robot_config``.
            robot_config: the robot's parameters, used to linearize it (default: the
                defaults of :class:`RobotConfig`).
            config: the LQR weights (default: the defaults of :class:`LqrConfig`).

        Raises:
            ValueError: if ``model`` does not match ``robot_config``.
            UnstableClosedLoopError: if the gains do not stabilize the robot.
        """
        robot_config = robot_config if robot_config is not None else RobotConfig()
        config = config if config is not None else LqrConfig()
        handles = RobotHandles(model)
        for name, in_model, in_config in (
            ("wheel_torque_limit_nm", handles.torque_limit_nm, robot_config.wheel_torque_limit_nm),
            ("wheel_radius_m", handles.wheel_radius_m, robot_config.wheel_radius_m),
        ):
            if abs(in_model - in_config) > 1e-9:
                raise ValueError(f"{name}: the model has {in_model}, the config {in_config}")
        self.gains = compute_gains(robot_config, config)
        if abs(self.gains.dt - model.opt.timestep) > 1e-12:
            raise ValueError(
                f"timestep: gains designed for {self.gains.dt} s, the model steps "
                f"{model.opt.timestep} s"
            )
        self.handles = handles
        self._read = handles.read_balance_state
        self._k = self.gains.sagittal
        self._k_yaw = self.gains.yaw
        self._ff_velocity = self.gains.velocity_feedforward
        self._ff_yaw_rate = self.gains.yaw_rate_feedforward
        self._dt = self.gains.dt
        self._limit = handles.torque_limit_nm
        self._left_id, self._right_id = handles.actuator_ids
        self.reset()

    def reset(self) -> None:
        """Forget the integrated tracking errors (a new run)."""
        self.velocity_error_integral_m = 0.0  # m
        self.yaw_rate_error_integral_rad = 0.0  # rad

    def apply(
        self,
        data: mujoco.MjData,
        velocity_command_mps: float = 0.0,
        yaw_rate_command_rad_s: float = 0.0,
    ) -> tuple[float, float]:
        """Compute the wheel torques for this physics step and write them to ``data.ctrl``.

        Args:
            data: the simulation state (reads ``qpos``, ``qvel``; writes ``ctrl``).
            velocity_command_mps: forward velocity wanted, m/s.
            yaw_rate_command_rad_s: yaw rate wanted, rad/s, counter-clockwise positive.

        Returns:
            ``(left, right)`` wheel torques in N·m, saturated at the motor limit.
        """
        s = self._read(data)
        k0, k1, k2, k3 = self._k
        ky0, ky1 = self._k_yaw
        velocity_error = s.forward_velocity_mps - velocity_command_mps
        yaw_rate_error = s.yaw_rate_rad_s - yaw_rate_command_rad_s
        common = self._ff_velocity * velocity_command_mps - (
            k0 * s.pitch_rad
            + k1 * s.pitch_rate_rad_s
            + k2 * velocity_error
            + k3 * self.velocity_error_integral_m
        )
        differential = self._ff_yaw_rate * yaw_rate_command_rad_s - (
            ky0 * yaw_rate_error + ky1 * self.yaw_rate_error_integral_rad
        )
        left = common - differential
        right = common + differential
        limit = self._limit
        if -limit < left < limit and -limit < right < limit:
            self.velocity_error_integral_m += self._dt * velocity_error
            self.yaw_rate_error_integral_rad += self._dt * yaw_rate_error
        else:
            left = limit if left > limit else (-limit if left < -limit else left)
            right = limit if right > limit else (-limit if right < -limit else right)
        ctrl = data.ctrl
        ctrl[self._left_id] = left
        ctrl[self._right_id] = right
        return left, right
