"""The robot's own dynamics, linearized around upright, and its two reduced subsystems.

Linearization. The robot spec (``load_robot_spec``) plus a flat floor plane is compiled
and put in its ``home`` keyframe: upright, at rest, zero torque. The axle height is
first settled onto the soft floor contact (bisection on the height with zero vertical
acceleration), so the linearization point is an equilibrium. ``mujoco.mjd_transitionFD``
(centred differences) then gives the discrete-time transition of one physics step::

    x[k+1] = A x[k] + B u[k],   x = (dq, dv) in R^16,   u = (tau_left, tau_right) N·m

with ``dq`` the position tangent (free joint: x y z, then rotation about body x y z; the
two wheel angles) and ``dv`` the matching velocities (free joint: linear velocity in the
world, angular velocity in the body frame; wheel speeds relative to the body). The body
frame sits at the axle, so pitching does not move the wheels.

Reduction. Upright, the body axes coincide with the world axes, so ``dq[4]`` is the
pitch, ``dv[4]`` the pitch rate, ``dv[0]`` the forward velocity and ``dv[5]`` the yaw
rate. Each subsystem is cut out with three matrices: ``S`` selects its states from a
full state, ``T`` embeds them back as the full state they stand for (wheels rolling
without slip: their speed relative to the body follows from the body's motion), and
``M`` mixes its single input into the two wheel torques. Its model is ``Ar = S A T``,
``Br = S B M``.

- sagittal: ``(pitch, pitch_rate, forward_velocity)``; input the common torque ``us``
  (both wheels ``us``); ``T`` also sets both wheel speeds to ``v / r - pitch_rate``;
- yaw: ``(yaw_rate,)``; input the differential torque ``ud`` (left ``-ud``, right
  ``+ud``, so positive turns left); ``T`` sets the wheel speeds to
  ``-/+ yaw_rate * w / (2 r)``.

(r: wheel radius, w: track width.) What is left out: x, y, the yaw angle and the wheel
angles are pure integrators on a flat floor with round wheels (checked: their columns of
``A`` are those of the identity), and height, roll and lateral velocity are held by the
contacts.
"""

from __future__ import annotations

from typing import NamedTuple

import mujoco
import numpy as np

from twsb_sim.robot import HOME_KEY, RobotConfig, RobotHandles, load_robot_spec

# Indices into the 16-dimensional tangent state (dq, dv) of the robot alone.
NV = 8  # free joint (6) + two wheels
I_PITCH = 4  # dq: rotation about body y
I_VX = NV + 0  # dv: axle velocity along world x
I_PITCH_RATE = NV + 4  # dv: angular velocity about body y
I_YAW_RATE = NV + 5  # dv: angular velocity about body z
I_WHEEL_SPEED = (NV + 6, NV + 7)  # dv: left, right wheel speed relative to the body
# Coordinates that are pure integrators (flat floor, round wheels): x, y, yaw, wheel angles.
MARGINAL_COORDINATES = (0, 1, 5, 6, 7)

FD_EPS = 1e-6  # finite-difference step of mjd_transitionFD


class LinearModel(NamedTuple):
    """``x[k+1] = a x[k] + b u[k]`` for one physics step around upright."""

    a: np.ndarray  # 16x16
    b: np.ndarray  # 16x2, columns: left, right wheel torque in N·m
    dt: float  # s
    wheel_radius_m: float
    track_width_m: float  # m, between the wheels' mid-planes


class Reduction(NamedTuple):
    """Selection ``s``, embedding ``t`` and input mixing ``m`` of one subsystem."""

    s: np.ndarray  # k x 16
    t: np.ndarray  # 16 x k
    m: np.ndarray  # 2 x 1


def linearize(robot_config: RobotConfig) -> LinearModel:
    """Linearize the robot on a flat floor around ``home`` (see the module docstring).

    Raises:
        RuntimeError: if the model is not the expected free-joint + two-wheel robot, or
            the coordinates assumed marginal turn out to affect the dynamics.
    """
    spec = load_robot_spec(robot_config)
    spec.worldbody.add_geom(
        name="linearization_floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[10.0, 10.0, 0.1]
    )
    model = spec.compile()
    if model.nv != NV or model.na != 0:
        raise RuntimeError(f"linearize: expected nv={NV} and no activations, got {model.nv}")
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key(HOME_KEY).id)
    handles = RobotHandles(model)
    # Free fall above the contact's equilibrium height, pushed up below it.
    z_adr = handles.qpos_adr + 2
    low, high = handles.wheel_radius_m - 0.01, handles.wheel_radius_m
    for _ in range(50):
        data.qpos[z_adr] = 0.5 * (low + high)
        mujoco.mj_forward(model, data)
        if data.qacc[handles.qvel_adr + 2] > 0.0:
            low = data.qpos[z_adr]
        else:
            high = data.qpos[z_adr]
    a = np.zeros((2 * NV, 2 * NV))
    b = np.zeros((2 * NV, model.nu))
    mujoco.mjd_transitionFD(model, data, FD_EPS, True, a, b, None, None)
    marginal = list(MARGINAL_COORDINATES)
    if np.max(np.abs(a[:, marginal] - np.eye(2 * NV)[:, marginal])) > 1e-6:
        raise RuntimeError(
            "linearize: x, y, yaw or wheel angles affect the dynamics; "
            "the reduction assumes a flat floor and round wheels"
        )
    return LinearModel(a, b, model.opt.timestep, handles.wheel_radius_m, handles.track_width_m)


def sagittal_reduction(linear: LinearModel) -> Reduction:
    """States ``(pitch, pitch_rate, forward_velocity)``, input the common wheel torque."""
    s = np.zeros((3, 2 * NV))
    s[[0, 1, 2], [I_PITCH, I_PITCH_RATE, I_VX]] = 1.0
    t = s.T.copy()
    for i in I_WHEEL_SPEED:
        t[i, 1] = -1.0
        t[i, 2] = 1.0 / linear.wheel_radius_m
    return Reduction(s, t, np.array([[1.0], [1.0]]))


def yaw_reduction(linear: LinearModel) -> Reduction:
    """State ``(yaw_rate,)``, input the differential torque (right minus left, halved)."""
    s = np.zeros((1, 2 * NV))
    s[0, I_YAW_RATE] = 1.0
    t = s.T.copy()
    wheel_per_yaw = 0.5 * linear.track_width_m / linear.wheel_radius_m
    t[I_WHEEL_SPEED[0], 0] = -wheel_per_yaw
    t[I_WHEEL_SPEED[1], 0] = wheel_per_yaw
    return Reduction(s, t, np.array([[-1.0], [1.0]]))


def reduce(linear: LinearModel, reduction: Reduction) -> tuple[np.ndarray, np.ndarray]:
    """The subsystem's discrete model ``(S A T, S B M)``."""
    s, t, m = reduction
    return s @ linear.a @ t, s @ linear.b @ m
