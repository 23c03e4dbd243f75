"""A pet-sized mover: a dog or cat of boxes and capsules that trots along a path.

One mocap body (``pet_<k>``): a body, a head, four legs and a tail, sized from the
pet's shoulder height; it moves along a :class:`~twsb_sim.movers.paths.WalkPath`, without
a gait (the legs are too thin for a 0.5 deg scanner to resolve their swing). No contacts;
labeled DYNAMIC.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from twsb_sim.movers.paths import WalkPath
from twsb_sim.movers.people import add_visual_geom, quat_yaw_pitch

FUR: tuple[float, float, float, float] = (0.55, 0.40, 0.25, 1.0)


@dataclass(frozen=True)
class Pet:
    """A pet running a path.

    Attributes:
        name: ``pet_<k>``.
        path: where and when it moves.
        shoulder_height_m: its height at the shoulder (m): ~0.25 for a cat, 0.3-0.6 for a dog.
    """

    name: str
    path: WalkPath
    shoulder_height_m: float = 0.4

    def __post_init__(self) -> None:
        if not 0.15 <= self.shoulder_height_m <= 0.8:
            raise ValueError(
                f"shoulder_height_m: expected 0.15 to 0.8 m, got {self.shoulder_height_m}"
            )

    @property
    def body_names(self) -> tuple[str, ...]:
        return (self.name,)

    def add_to_spec(self, spec: mujoco.MjSpec) -> None:
        """The pet's mocap body: trunk, head, legs and tail, facing local +x."""
        h = self.shoulder_height_m
        length, depth = 1.4 * h, 0.45 * h  # trunk length and height
        body = spec.worldbody.add_body(name=self.name, mocap=True)
        trunk_z = h - depth / 2
        add_visual_geom(body, f"{self.name}_trunk", type=mujoco.mjtGeom.mjGEOM_BOX,
                        size=[length / 2, 0.18 * h, depth / 2], pos=[0, 0, trunk_z],
                        rgba=list(FUR))  # fmt: skip
        add_visual_geom(body, f"{self.name}_head", type=mujoco.mjtGeom.mjGEOM_SPHERE,
                        size=[0.22 * h, 0, 0], pos=[length / 2 + 0.1 * h, 0, h + 0.1 * h],
                        rgba=list(FUR))  # fmt: skip
        leg_half = (h - depth) / 2
        for j, (sx, sy) in enumerate(((1, 1), (1, -1), (-1, 1), (-1, -1))):
            add_visual_geom(body, f"{self.name}_leg_{j}", type=mujoco.mjtGeom.mjGEOM_CAPSULE,
                            size=[0.06 * h, max(leg_half - 0.06 * h, 0.005), 0],
                            pos=[sx * 0.4 * length, sy * 0.12 * h, leg_half],
                            rgba=list(FUR))  # fmt: skip
        add_visual_geom(body, f"{self.name}_tail", type=mujoco.mjtGeom.mjGEOM_CAPSULE,
                        size=[0.04 * h, 0.3 * h, 0],
                        pos=[-length / 2 - 0.2 * h, 0, h], quat=list(quat_yaw_pitch(0, 1.0)),
                        rgba=list(FUR))  # fmt: skip

    def poses(self, t_s: float) -> tuple[np.ndarray, np.ndarray]:
        """Position (1, 3) and quaternion (1, 4) of the pet at ``t_s``."""
        state = self.path.at(t_s)
        # a trot bobs the body by 1 cm twice a stride (a cue no wall gives)
        bob = 0.01 * abs(math.sin(math.pi * state.walked_m / (0.8 * self.shoulder_height_m)))
        return (
            np.array([(state.x_m, state.y_m, bob)]),
            np.array([quat_yaw_pitch(state.heading_rad, 0.0)]),
        )
