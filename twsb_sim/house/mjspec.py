"""Adding a house to a ``mujoco.MjSpec``."""

from __future__ import annotations

import math

import mujoco

from twsb_sim.house.model import House, Part

_GEOM_TYPES = {
    "plane": mujoco.mjtGeom.mjGEOM_PLANE,
    "box": mujoco.mjtGeom.mjGEOM_BOX,
    "cylinder": mujoco.mjtGeom.mjGEOM_CYLINDER,
    "capsule": mujoco.mjtGeom.mjGEOM_CAPSULE,
}
# a surface with a friction of its own outranks the tyres (geom priority 1), so its
# coefficients, rolling resistance included (condim 6), set the contact's
OWN_FRICTION_PRIORITY = 2
OWN_FRICTION_CONDIM = 6


def part_quat(part: Part) -> list[float]:
    """The part's orientation (w, x, y, z): its pitch about its own y axis, then its yaw."""
    cy, sy = math.cos(part.yaw_rad / 2), math.sin(part.yaw_rad / 2)
    cp, sp = math.cos(part.pitch_rad / 2), math.sin(part.pitch_rad / 2)
    return [cy * cp, -sy * sp, cy * sp, sy * cp]  # q_yaw * q_pitch


def _add_part(spec: mujoco.MjSpec, part: Part) -> None:
    geom = spec.worldbody.add_geom(
        name=part.name,
        type=_GEOM_TYPES[part.shape],
        size=list(part.size),
        pos=list(part.pos),
        quat=part_quat(part),
        rgba=list(part.rgba),
        group=part.group,
        contype=1,
        conaffinity=1,
    )
    if part.friction is not None:
        geom.friction = list(part.friction)
        geom.priority = OWN_FRICTION_PRIORITY
        geom.condim = OWN_FRICTION_CONDIM


def add_house_to_spec(spec: mujoco.MjSpec, house: House) -> None:
    """Add every geom of ``house`` to ``spec.worldbody``.

    The geoms are static, in geom groups 0 (floor, walls, door frames), 1 (furniture)
    and 2 (ceiling), collide with everything (contype = conaffinity = 1) and are named
    so that ``surface_classes`` can tell what each one is. Each room also gets a
    ceiling light ``light_<room>`` (no shadows).

    Args:
        spec: the spec to extend (typically one that already holds the robot).
        house: the house to add.
    """
    for part in house.parts():
        _add_part(spec, part)
    for room in house.rooms:
        # a ceiling light per room, without shadows (cheap to render)
        spec.worldbody.add_light(
            name=f"light_{room.name}",
            pos=[(room.x_min_m + room.x_max_m) / 2, (room.y_min_m + room.y_max_m) / 2,
                 house.ceiling_height_m - 0.05],
            dir=[0.0, 0.0, -1.0],
            type=mujoco.mjtLightType.mjLIGHT_POINT,
            castshadow=0,
            diffuse=[0.3, 0.3, 0.28],
        )  # fmt: skip


def house_spec(house: House) -> mujoco.MjSpec:
    """A fresh spec holding only ``house``, e.g. for tests and previews."""
    spec = mujoco.MjSpec()
    spec.modelname = house.name
    add_house_to_spec(spec, house)
    return spec
