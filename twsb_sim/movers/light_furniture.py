"""Light furniture the robot bumps into and pushes: a stool, a box, a laundry basket.

Unlike people and doors these are real bodies (a free joint, mass, contacts with the floor,
the walls and the robot): a drive that reaches one brakes the robot at its wheels and
tips its body, as a bump into a real stool does. Their geoms sit on a body that moves, so
their beams are labeled DYNAMIC, standing or pushed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco

from twsb_sim.movers.people import MOVER_GROUP

LIGHT_FURNITURE_KINDS: tuple[str, ...] = ("box", "stool")
# sliding friction of the piece, with priority over the floor's and the tyres' (1): it
# slides on the floor under a push, and a wheel pressed against it slips instead of
# climbing it (the robot has no bumper)
FRICTION = 0.25
FRICTION_PRIORITY = 2
COLOURS = {"box": (0.70, 0.58, 0.40, 1.0), "stool": (0.45, 0.30, 0.18, 1.0)}


@dataclass(frozen=True)
class LightFurniture:
    """A light piece standing on the floor.

    Attributes:
        name: ``pushable_<k>``.
        kind: ``box`` (a cardboard box or basket) or ``stool`` (a round seat on a column).
        x_m, y_m: centre of its footprint (m, world).
        yaw_rad: its heading.
        mass_kg: its mass.
        size_m: (width, depth, height) of a box; (diameter, -, height) of a stool (m).
    """

    name: str
    kind: str
    x_m: float
    y_m: float
    yaw_rad: float = 0.0
    mass_kg: float = 3.0
    size_m: tuple[float, float, float] = (0.45, 0.35, 0.3)

    def __post_init__(self) -> None:
        if self.kind not in LIGHT_FURNITURE_KINDS:
            raise ValueError(
                f"kind: expected one of {list(LIGHT_FURNITURE_KINDS)}, got {self.kind!r}"
            )
        if not 0.2 <= self.mass_kg <= 30.0:
            raise ValueError(f"mass_kg: expected 0.2 to 30 kg, got {self.mass_kg}")
        if not all(0.05 <= v <= 1.5 for v in self.size_m):
            raise ValueError(f"size_m: expected sizes of 0.05 to 1.5 m, got {list(self.size_m)}")

    @property
    def body_names(self) -> tuple[str, ...]:
        return ()  # no mocap body: the physics moves it

    def add_to_spec(self, spec: mujoco.MjSpec) -> None:
        """A free body resting on the floor."""
        w, d, h = self.size_m
        half = self.yaw_rad / 2
        body = spec.worldbody.add_body(
            name=self.name, pos=[self.x_m, self.y_m, h / 2],
            quat=[math.cos(half), 0, 0, math.sin(half)],
        )  # fmt: skip
        body.add_freejoint(name=f"{self.name}_free")
        common = {
            "group": MOVER_GROUP,
            "rgba": list(COLOURS[self.kind]),
            "friction": [FRICTION, 0.005, 0.0001],
            "priority": FRICTION_PRIORITY,
        }
        if self.kind == "box":
            body.add_geom(name=f"{self.name}_shell", type=mujoco.mjtGeom.mjGEOM_BOX,
                          size=[w / 2, d / 2, h / 2], mass=self.mass_kg, **common)  # fmt: skip
            return
        seat_t = 0.03  # m, seat thickness
        body.add_geom(name=f"{self.name}_seat", type=mujoco.mjtGeom.mjGEOM_CYLINDER,
                      size=[w / 2, seat_t / 2, 0], pos=[0, 0, h / 2 - seat_t / 2],
                      mass=0.4 * self.mass_kg, **common)  # fmt: skip
        body.add_geom(name=f"{self.name}_column", type=mujoco.mjtGeom.mjGEOM_CYLINDER,
                      size=[0.04, h / 2 - seat_t, 0], pos=[0, 0, -seat_t / 2],
                      mass=0.2 * self.mass_kg, **common)  # fmt: skip
        body.add_geom(name=f"{self.name}_base", type=mujoco.mjtGeom.mjGEOM_CYLINDER,
                      size=[0.4 * w, 0.01, 0], pos=[0, 0, -h / 2 + 0.01],
                      mass=0.4 * self.mass_kg, **common)  # fmt: skip
