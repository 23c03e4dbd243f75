"""LQR gains designed on the linearized MJCF model, with closed-loop checks.

Each reduced subsystem of :mod:`twsb_sim.control.linearization` is augmented with the
discrete integral of its tracking error (``z[k+1] = z[k] + dt * e[k]``) and
``control.dlqr`` gives its gains, for the control laws::

    us = ff_v * v_cmd - ks . (pitch, pitch_rate, v - v_cmd, z_v)
    ud = ff_w * w_cmd - ky . (yaw_rate - w_cmd, z_w)
    tau_left = us - ud,   tau_right = us + ud

The feedforward ``ff`` comes from the reduced model's equilibrium at a unit command (the
pitch and torque that hold a constant velocity or yaw rate against the wheel damping),
so the integrators only trim what the linear model gets wrong. Their weights are small
on purpose: the velocity integrator would otherwise store the distance lost in the
non-minimum-phase start of every acceleration and overshoot afterwards.

Checks. The closed loop of each augmented subsystem must have every eigenvalue strictly
inside the unit circle. The gains are then mapped onto the full 16-state model plus the
two integrators, and its closed loop is checked too, with the rows and columns of the
five marginal coordinates (x, y, yaw angle, both wheel angles) removed: nothing depends
on them, so each only adds an eigenvalue of exactly 1 that no controller can move, and
the remaining 13 eigenvalues are the rest of the spectrum. A failing check raises
:class:`UnstableClosedLoopError`.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from twsb_sim.control.linearization import (
    I_PITCH,
    I_PITCH_RATE,
    I_VX,
    I_YAW_RATE,
    MARGINAL_COORDINATES,
    LinearModel,
    linearize,
    reduce,
    sagittal_reduction,
    yaw_reduction,
)
from twsb_sim.robot import RobotConfig

MAX_STABLE_EIGENVALUE = 1.0 - 1e-9  # discrete time: strictly inside the unit circle
# weights beyond these only make the Riccati equation ill-conditioned: the gains saturate
# the motors long before, so no robot is served by more
MAX_WEIGHT = 1e6
AGGRESSIVENESS_BOUNDS = (0.01, 100.0)  # the span twsb generate draws from


class UnstableClosedLoopError(RuntimeError):
    """LQR gains that do not stabilize the linearized robot."""


@dataclass(frozen=True)
class LqrConfig:
    """Weights of the LQR cost summed over physics steps, ``x' Q x + u' R u``.

    Larger state weights (or ``aggressiveness``) give a stiffer robot that corrects
    faster and brakes in a shorter distance; the pitch excursion of a hard stop is set
    mostly by the physics and changes little.
    """

    pitch_weight: float = 100.0  # 1/rad², pitch away from upright
    pitch_rate_weight: float = 1.0  # 1/(rad/s)², pitch rate
    velocity_weight: float = 300.0  # 1/(m/s)², forward velocity minus command
    velocity_integral_weight: float = 0.1  # 1/m², time integral of that error (> 0)
    yaw_rate_weight: float = 10.0  # 1/(rad/s)², yaw rate minus command
    yaw_integral_weight: float = 1.0  # 1/rad², time integral of that error (> 0)
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
            _check_weight(name, getattr(self, name), 0.0, MAX_WEIGHT, allow_low=True)
        _check_weight("torque_weight", self.torque_weight, 0.0, MAX_WEIGHT, allow_low=False)
        _check_weight("aggressiveness", self.aggressiveness, *AGGRESSIVENESS_BOUNDS, allow_low=True)


def _check_weight(name: str, value: object, low: float, high: float, allow_low: bool) -> None:
    number = isinstance(value, int | float) and not isinstance(value, bool)
    if not number or not (low <= value <= high) or (value == low and not allow_low):
        bound = f"in [{low:g}, {high:g}]" if allow_low else f"in ({low:g}, {high:g}]"
        raise ValueError(f"{name}: expected a number {bound}, got {value!r}")


@dataclass(frozen=True)
class LqrGains:
    """Gains and feedforward of the control laws in the module docstring."""

    sagittal: tuple[float, float, float, float]  # N·m/rad, N·m·s/rad, N·m·s/m, N·m/m
    yaw: tuple[float, float]  # N·m·s/rad, N·m/rad
    velocity_feedforward: float  # N·m per m/s commanded
    yaw_rate_feedforward: float  # N·m per rad/s commanded
    dt: float  # s, the physics step the gains are designed for
    sagittal_eigenvalues: tuple[complex, ...]  # 4: pitch, pitch rate, velocity, integral
    yaw_eigenvalues: tuple[complex, ...]  # 2: yaw rate, integral
    full_eigenvalues: tuple[complex, ...]  # 13: all but the marginal coordinates


def _augment(
    ar: np.ndarray, br: np.ndarray, error_row: int, dt: float
) -> tuple[np.ndarray, np.ndarray]:
    """Append the discrete integral of state ``error_row`` to a reduced model."""
    n = ar.shape[0]
    aa = np.eye(n + 1)
    aa[:n, :n] = ar
    aa[n, error_row] = dt
    return aa, np.vstack([br, np.zeros((1, br.shape[1]))])


def _check_spectrum(what: str, eigenvalues: np.ndarray) -> None:
    worst = float(np.max(np.abs(eigenvalues)))
    if worst > MAX_STABLE_EIGENVALUE:
        raise UnstableClosedLoopError(
            f"{what}: closed-loop eigenvalue of magnitude {worst:.9f} (must be < 1): the "
            "LQR gains do not stabilize the robot (is an integral weight 0?); change the "
            "LqrConfig weights"
        )


def closed_loop_full(linear: LinearModel, sagittal: np.ndarray, yaw: np.ndarray) -> np.ndarray:
    """The full linear closed loop with both integrators, marginal coordinates removed.

    Args:
        linear: the model from :func:`linearize`.
        sagittal: the 4 sagittal gains; yaw: the 2 yaw gains.

    Returns:
        The 13x13 closed-loop transition matrix (zero commands).
    """
    n = linear.a.shape[0]
    zv, zw = n, n + 1  # the integrators' rows
    aa = np.eye(n + 2)
    aa[:n, :n] = linear.a
    aa[zv, I_VX] = aa[zw, I_YAW_RATE] = linear.dt
    ba = np.vstack([linear.b, np.zeros((2, linear.b.shape[1]))])
    ks = np.zeros(n + 2)
    ks[[I_PITCH, I_PITCH_RATE, I_VX, zv]] = sagittal
    ky = np.zeros(n + 2)
    ky[[I_YAW_RATE, zw]] = yaw
    closed = aa - ba @ np.vstack([ks - ky, ks + ky])  # left = us - ud, right = us + ud
    keep = [i for i in range(n + 2) if i not in MARGINAL_COORDINATES]
    return closed[np.ix_(keep, keep)]


@functools.lru_cache(maxsize=32)
def compute_gains(robot_config: RobotConfig, lqr_config: LqrConfig) -> LqrGains:
    """Design the LQR gains on the linearized MJCF model and check the closed loop.

    Cached: equal configurations return the same gains without recomputation.

    Raises:
        UnstableClosedLoopError: if a reduced or the full closed loop is unstable.
    """
    import control  # slow to import (matplotlib): only where gains are designed

    linear = linearize(robot_config)
    a_sag, b_sag = _augment(*reduce(linear, sagittal_reduction(linear)), 2, linear.dt)
    a_yaw, b_yaw = _augment(*reduce(linear, yaw_reduction(linear)), 0, linear.dt)

    c = lqr_config
    q_sag = np.diag(
        [c.pitch_weight, c.pitch_rate_weight, c.velocity_weight, c.velocity_integral_weight]
    )
    q_yaw = np.diag([c.yaw_rate_weight, c.yaw_integral_weight])
    r = np.array([[c.torque_weight]])
    try:
        k_sag = np.asarray(control.dlqr(a_sag, b_sag, c.aggressiveness * q_sag, r)[0])[0]
        k_yaw = np.asarray(control.dlqr(a_yaw, b_yaw, c.aggressiveness * q_yaw, r)[0])[0]
    except (np.linalg.LinAlgError, ValueError) as error:  # no stabilizing Riccati solution
        raise UnstableClosedLoopError(
            f"no LQR solution for these weights ({error}); change the LqrConfig weights"
        ) from error

    eig_sag = np.linalg.eigvals(a_sag - b_sag @ k_sag[None, :])
    _check_spectrum("sagittal model", eig_sag)
    eig_yaw = np.linalg.eigvals(a_yaw - b_yaw @ k_yaw[None, :])
    _check_spectrum("yaw model", eig_yaw)
    eig_full = np.linalg.eigvals(closed_loop_full(linear, k_sag, k_yaw))
    _check_spectrum("full model", eig_full)

    # Equilibrium at v = 1 m/s: solve (Ar - I)(pitch, rate, 1) + Br torque = 0.
    ar = a_sag[:3, :3] - np.eye(3)
    pitch, rate, torque = np.linalg.solve(
        np.column_stack([ar[:, 0], ar[:, 1], b_sag[:3, 0]]), -ar[:, 2]
    )
    return LqrGains(
        sagittal=tuple(float(g) for g in k_sag),
        yaw=tuple(float(g) for g in k_yaw),
        velocity_feedforward=float(k_sag[0] * pitch + k_sag[1] * rate + torque),
        yaw_rate_feedforward=float((1.0 - a_yaw[0, 0]) / b_yaw[0, 0]),
        dt=linear.dt,
        sagittal_eigenvalues=tuple(complex(e) for e in eig_sag),
        yaw_eigenvalues=tuple(complex(e) for e in eig_yaw),
        full_eigenvalues=tuple(complex(e) for e in eig_full),
    )
