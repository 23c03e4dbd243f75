"""Ceilings that a tilted scan plane meets: sloped attic ceilings and the undersides of stairs.

The flat ceiling of a house is one box (``ceiling``) at its ``ceiling_height_m``; this
module adds the overhead surfaces that come lower:

- an **attic slope** runs along one wall of a room, from the top of a knee wall
  (``knee_height_m``) up to the flat ceiling, at the roof's pitch;
- a **staircase** runs along one wall from the floor up to the ceiling: treads every
  ``rise_m``, and under them a sloped soffit (the underside a robot passes by, or under
  where it is high enough).

Slopes and soffits are ceiling surfaces (named ``ceiling_<kind>_<k>...``), so a beam that
ends on one is a CEILING point unless a level scanner at the same place would have seen it
too (the soffit's low end, which stands in the scan plane like a wall: see
:mod:`twsb_sim.level_view`). Treads are structure (``stairs_<k>_tread_<j>``): their tops
are horizontal surfaces, and those below 1.5 m block the robot.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from twsb_sim.house.floorplan import CEILING_COLOUR, CEILING_GROUP, STRUCTURE_GROUP
from twsb_sim.house.model import Part, Rgba, Room

SIDES = ("north", "south", "east", "west")
SLAB_THICKNESS_M = 0.05  # m, attic slopes and stair soffits
TREAD_THICKNESS_M = 0.04  # m
TREAD_DEPTH_M = 0.27  # m, horizontal run per step
MAX_RISE_M = 0.19  # m, a step's height at most
STAIR_COLOUR: Rgba = (0.50, 0.36, 0.22, 1.0)


@dataclass(frozen=True)
class AtticSlope:
    """A sloped ceiling along one wall of a room.

    Attributes:
        room: the room's name.
        side: the wall it slopes down to: ``north`` (+y), ``south``, ``east`` (+x), ``west``.
        knee_height_m: where the slope meets that wall (m above the floor).
        pitch_deg: the roof's slope (deg above horizontal).
    """

    room: str
    side: str
    knee_height_m: float = 1.2
    pitch_deg: float = 40.0

    def __post_init__(self) -> None:
        if self.side not in SIDES:
            raise ValueError(f"side: expected one of {list(SIDES)}, got {self.side!r}")
        if not 0.6 <= self.knee_height_m <= 2.5:
            raise ValueError(f"knee_height_m: expected 0.6 to 2.5 m, got {self.knee_height_m}")
        if not 15.0 <= self.pitch_deg <= 60.0:
            raise ValueError(f"pitch_deg: expected 15 to 60 deg, got {self.pitch_deg}")


@dataclass(frozen=True)
class Staircase:
    """Stairs along one wall of a room, rising from ``start_m`` along that wall.

    Attributes:
        room: the room's name.
        side: the wall it runs along.
        start_m: where its foot is along the wall, from the wall's west or south end (m).
        width_m: width of the flight (m).
        rising_east_or_north: the flight rises towards +x (walls along x) or +y.
    """

    room: str
    side: str
    start_m: float = 0.3
    width_m: float = 0.9
    rising_east_or_north: bool = True

    def __post_init__(self) -> None:
        if self.side not in SIDES:
            raise ValueError(f"side: expected one of {list(SIDES)}, got {self.side!r}")
        if not 0.6 <= self.width_m <= 1.5:
            raise ValueError(f"width_m: expected 0.6 to 1.5 m, got {self.width_m}")


def _inner_face(room: Room, side: str, wall_thickness_m: float) -> float:
    t = wall_thickness_m / 2
    return {
        "north": room.y_max_m - t,
        "south": room.y_min_m + t,
        "east": room.x_max_m - t,
        "west": room.x_min_m + t,
    }[side]


def attic_slope_part(
    slope: AtticSlope, room: Room, ceiling_height_m: float, wall_thickness_m: float, index: int
) -> Part:
    """The sloped slab of an attic ceiling, its underside from the knee to the ceiling."""
    along_x = slope.side in ("north", "south")
    t = wall_thickness_m / 2
    span = (room.x_max_m - room.x_min_m if along_x else room.y_max_m - room.y_min_m) - 2 * t
    rise = max(ceiling_height_m - slope.knee_height_m, 0.01)
    angle = math.radians(slope.pitch_deg)
    run = rise / math.tan(angle)
    wall = _inner_face(room, slope.side, wall_thickness_m)
    inward = -1.0 if slope.side in ("north", "east") else 1.0  # from the wall into the room
    # the underside's midpoint, then half a thickness up along the slab's normal
    mid_in = wall + inward * run / 2
    half = SLAB_THICKNESS_M / 2
    centre_in = mid_in - inward * half * math.sin(angle)
    centre_z = slope.knee_height_m + rise / 2 + half * math.cos(angle)
    # local x runs from the wall into the room, rising: pitch -angle after facing inward
    yaw = {"north": -math.pi / 2, "south": math.pi / 2, "east": math.pi, "west": 0.0}[slope.side]
    mid_along = (room.x_min_m + room.x_max_m) / 2 if along_x else (room.y_min_m + room.y_max_m) / 2
    pos = (mid_along, centre_in, centre_z) if along_x else (centre_in, mid_along, centre_z)
    return Part(
        f"ceiling_attic_{index}", "box", (rise / math.sin(angle) / 2, span / 2, half), pos, yaw,
        CEILING_COLOUR, CEILING_GROUP, pitch_rad=-angle, blocking=False,
    )  # fmt: skip


def staircase_parts(
    stairs: Staircase, room: Room, ceiling_height_m: float, wall_thickness_m: float, index: int
) -> tuple[Part, ...]:
    """Treads and the soffit under them, from the floor up to the ceiling."""
    steps = math.ceil(ceiling_height_m / MAX_RISE_M)
    rise = ceiling_height_m / steps
    run = steps * TREAD_DEPTH_M
    along_x = stairs.side in ("north", "south")
    wall = _inner_face(room, stairs.side, wall_thickness_m)
    inward = -1.0 if stairs.side in ("north", "east") else 1.0
    across = wall + inward * stairs.width_m / 2  # the flight's centreline
    low_end = (room.x_min_m if along_x else room.y_min_m) + wall_thickness_m / 2 + stairs.start_m
    sign = 1.0 if stairs.rising_east_or_north else -1.0
    if sign < 0:
        low_end += run  # the foot is at the far end; the flight rises back towards start_m

    def point(along: float, z: float) -> tuple[float, float, float]:
        a = low_end + sign * along
        return (a, across, z) if along_x else (across, a, z)

    yaw = (0.0 if sign > 0 else math.pi) if along_x else (math.pi / 2 if sign > 0 else -math.pi / 2)
    tread_size = (TREAD_DEPTH_M / 2, stairs.width_m / 2, TREAD_THICKNESS_M / 2)
    treads = [
        Part(
            f"stairs_{index}_tread_{j}",
            "box",
            tread_size,
            point((j + 0.5) * TREAD_DEPTH_M, (j + 1) * rise - TREAD_THICKNESS_M / 2),
            yaw,
            STAIR_COLOUR,
            STRUCTURE_GROUP,
        )
        for j in range(steps)
    ]
    angle = math.atan2(ceiling_height_m, run)
    half = SLAB_THICKNESS_M / 2
    # the soffit's underside runs from the foot (floor) to the top (ceiling)
    centre_along = run / 2 - half * math.sin(angle)
    centre_z = ceiling_height_m / 2 + half * math.cos(angle)
    soffit = Part(
        f"ceiling_stairs_{index}_soffit", "box",
        (math.hypot(run, ceiling_height_m) / 2, stairs.width_m / 2, half),
        point(centre_along, centre_z), yaw, CEILING_COLOUR, CEILING_GROUP,
        pitch_rad=-angle, blocking=False,
    )  # fmt: skip
    return (*treads, soffit)
