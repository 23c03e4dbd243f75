"""People: kinematic bodies of two legs and a torso that walk, stand and turn.

A person is three mocap bodies: a torso (with the head) and two legs, each leg a capsule
hanging from its hip. While walking, the legs swing in opposite phase about the hips,
``amplitude * sin(2 pi walked / stride)``, so the gait follows the distance walked and
stops when the person stands; the midpoint of the two legs moves with the hips, at the
walking speed. Sizes scale with the person's height (hip at 0.53 of it).

People are seen, not felt: their geoms have no contacts (the robot passes through a person
its path crosses), so they move only when the LiDAR looks and cost nothing per physics
step. Their beams are labeled DYNAMIC.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from twsb_sim.movers.paths import WalkPath

MOVER_GROUP = 1  # MuJoCo geom group of movers: cast by the LiDAR, shown by default
HIP_HEIGHT_SHARE = 0.53  # hip height / body height
LEG_RADIUS_SHARE = 0.037  # leg (thigh and shin, one capsule) radius / body height
HIP_HALF_WIDTH_SHARE = 0.055  # lateral hip offset / body height
STEP_SHARE = 0.4  # step length / body height at a brisk walk
MAX_SWING_RAD = 0.45  # rad, leg swing amplitude at most
SKIN: tuple[float, float, float, float] = (0.80, 0.62, 0.50, 1.0)
CLOTHES: tuple[float, float, float, float] = (0.25, 0.32, 0.45, 1.0)
TROUSERS: tuple[float, float, float, float] = (0.18, 0.18, 0.22, 1.0)


def quat_yaw_pitch(yaw_rad: float, pitch_rad: float) -> tuple[float, float, float, float]:
    """(w, x, y, z) of a rotation by ``pitch`` about local y, then ``yaw`` about world z."""
    cy, sy = math.cos(yaw_rad / 2), math.sin(yaw_rad / 2)
    cp, sp = math.cos(pitch_rad / 2), math.sin(pitch_rad / 2)
    return (cy * cp, -sy * sp, cy * sp, sy * cp)


def add_visual_geom(body: mujoco.MjsBody, name: str, **attributes: object) -> None:
    """A geom the LiDAR sees but nothing collides with."""
    body.add_geom(name=name, contype=0, conaffinity=0, group=MOVER_GROUP, **attributes)


@dataclass(frozen=True)
class Person:
    """A person walking a path.

    Attributes:
        name: ``person_<k>``; the bodies are ``<name>_torso``, ``<name>_left_leg``,
            ``<name>_right_leg``.
        path: where and when the person walks.
        height_m: body height (m).
    """

    name: str
    path: WalkPath
    height_m: float = 1.75

    def __post_init__(self) -> None:
        if not 1.0 <= self.height_m <= 2.2:
            raise ValueError(f"height_m: expected 1.0 to 2.2 m, got {self.height_m}")

    @property
    def body_names(self) -> tuple[str, ...]:
        return (f"{self.name}_torso", f"{self.name}_left_leg", f"{self.name}_right_leg")

    @property
    def hip_height_m(self) -> float:
        return HIP_HEIGHT_SHARE * self.height_m

    @property
    def step_m(self) -> float:
        """One step (m): half a stride."""
        return STEP_SHARE * self.height_m * min(1.0, 0.5 + 0.4 * self.path.speed_mps)

    def add_to_spec(self, spec: mujoco.MjSpec) -> None:
        """The three mocap bodies and their geoms."""
        h, hip = self.height_m, self.hip_height_m
        torso = spec.worldbody.add_body(name=self.body_names[0], mocap=True)
        trunk_half = (0.82 * h - hip) / 2
        add_visual_geom(torso, f"{self.name}_trunk", type=mujoco.mjtGeom.mjGEOM_BOX,
                        size=[0.06 * h, 0.11 * h, trunk_half], pos=[0, 0, hip + trunk_half],
                        rgba=list(CLOTHES))  # fmt: skip
        add_visual_geom(torso, f"{self.name}_head", type=mujoco.mjtGeom.mjGEOM_SPHERE,
                        size=[0.065 * h, 0, 0], pos=[0, 0, 0.92 * h], rgba=list(SKIN))  # fmt: skip
        radius = LEG_RADIUS_SHARE * h
        for body_name in self.body_names[1:]:
            leg = spec.worldbody.add_body(name=body_name, mocap=True)
            # the leg's frame is at the hip; the capsule hangs down its -z axis
            add_visual_geom(leg, f"{body_name}_capsule", type=mujoco.mjtGeom.mjGEOM_CAPSULE,
                            size=[radius, hip / 2 - radius, 0], pos=[0, 0, -hip / 2],
                            rgba=list(TROUSERS))  # fmt: skip

    def poses(self, t_s: float) -> tuple[np.ndarray, np.ndarray]:
        """Positions (3, 3) and quaternions (3, 4) of torso, left leg, right leg at ``t_s``."""
        state = self.path.at(t_s)
        c, s = math.cos(state.heading_rad), math.sin(state.heading_rad)
        swing = min(MAX_SWING_RAD, math.asin(min(1.0, 0.5 * self.step_m / self.hip_height_m)))
        angle = swing * math.sin(math.pi * state.walked_m / self.step_m)
        hip_z = self.hip_height_m
        half_width = HIP_HALF_WIDTH_SHARE * self.height_m
        positions = np.array(
            [
                (state.x_m, state.y_m, 0.0),
                (state.x_m - s * half_width, state.y_m + c * half_width, hip_z),
                (state.x_m + s * half_width, state.y_m - c * half_width, hip_z),
            ]
        )
        # a leg swung forward by ``a`` turns its -z axis towards +x: pitch -a about y
        quats = np.array(
            [
                quat_yaw_pitch(state.heading_rad, 0.0),
                quat_yaw_pitch(state.heading_rad, -angle),
                quat_yaw_pitch(state.heading_rad, angle),
            ]
        )
        return positions, quats
