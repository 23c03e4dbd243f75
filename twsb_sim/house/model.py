"""The plain data a house is made of: parts, furniture, rooms, doorways, spawn poses.

Everything is in the world frame (REP-103: x east/forward, y left, z up), in metres and
radians. A house is a frozen value: two houses built from the same seed compare equal.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Literal

Shape = Literal["plane", "box", "cylinder", "capsule"]
Rgba = tuple[float, float, float, float]
Vec3 = tuple[float, float, float]


@dataclass(frozen=True)
class Part:
    """One static MuJoCo geom of a house.

    Attributes:
        name: geom name; its prefix gives the surface class (see ``surfaces.py``).
        shape: ``"plane"``, ``"box"``, ``"cylinder"`` or ``"capsule"`` (axis along local z:
            vertical unless pitched).
        size: MuJoCo geom size: box half-extents (m); cylinder and capsule (radius,
            half-length, 0) (m); plane (half-x, half-y, grid spacing) (m).
        pos: centre in the world (m).
        yaw_rad: rotation about the world z axis (rad).
        rgba: colour, each channel in [0, 1].
        group: MuJoCo geom group (0 structure, 1 furniture, 2 ceiling; 3 is the robot's).
        pitch_rad: rotation about the part's own y axis, applied before the yaw (rad): a
            ramp, a sloped ceiling, a cable lying on the floor (a capsule pitched by pi/2).
        blocking: whether the part stops a robot driving on the floor (spawn poses, free
            lanes). Floor features it drives over and surfaces overhead do not.
        friction: (sliding, torsional, rolling) coefficients of a surface with a friction
            of its own (a carpet); None keeps MuJoCo's default, where the tyres' friction
            sets the contact's.
    """

    name: str
    shape: Shape
    size: Vec3
    pos: Vec3
    yaw_rad: float
    rgba: Rgba
    group: int = 0
    pitch_rad: float = 0.0
    blocking: bool = True
    friction: Vec3 | None = None

    @property
    def z_min_m(self) -> float:
        """Height of the part's lowest point above the floor (m)."""
        if self.shape == "plane":
            return self.pos[2]
        c, s = abs(math.cos(self.pitch_rad)), abs(math.sin(self.pitch_rad))
        if self.shape == "box":
            return self.pos[2] - (c * self.size[2] + s * self.size[0])
        radius, half = self.size[0], self.size[1]
        if self.shape == "capsule":
            return self.pos[2] - (c * half + radius)
        return self.pos[2] - (c * half + s * radius)

    @property
    def z_max_m(self) -> float:
        """Height of the part's highest point above the floor (m)."""
        if self.shape == "plane":
            return self.pos[2]
        return 2 * self.pos[2] - self.z_min_m


@dataclass(frozen=True)
class Furniture:
    """One piece of furniture: a named group of parts.

    Attributes:
        name: ``<kind>_<k>``, e.g. ``table_2``; its parts are ``table_2_top``, ...
        kind: ``table``, ``sofa``, ``shelf``, ``chair``, ``cabinet`` or ``bed``.
        x_m, y_m: centre of the footprint in the world (m).
        yaw_rad: heading; the piece's back faces local +y rotated by this yaw (rad).
        width_m, depth_m, height_m: outer dimensions (m), width along local x.
        parts: the geoms.
    """

    name: str
    kind: str
    x_m: float
    y_m: float
    yaw_rad: float
    width_m: float
    depth_m: float
    height_m: float
    parts: tuple[Part, ...]


@dataclass(frozen=True)
class Room:
    """A rectangular room; the bounds are the centrelines of its walls (m)."""

    name: str
    x_min_m: float
    y_min_m: float
    x_max_m: float
    y_max_m: float

    @property
    def size_m(self) -> tuple[float, float]:
        """Length along x and y between wall centrelines (m)."""
        return self.x_max_m - self.x_min_m, self.y_max_m - self.y_min_m

    def contains(self, x_m: float, y_m: float) -> bool:
        """Whether the point lies inside the wall centrelines."""
        return self.x_min_m < x_m < self.x_max_m and self.y_min_m < y_m < self.y_max_m


@dataclass(frozen=True)
class Doorway:
    """An opening in the wall between two rooms.

    Attributes:
        name: ``door_<k>``; its frame geoms are ``door_frame_<k>_left``, ``_right``, ``_header``.
        rooms: the names of the two rooms it joins.
        x_m, y_m: centre of the opening on the wall centreline (m).
        along_x: True when the wall runs along x (the doorway is crossed along y).
        width_m: clear width of the opening (m).
        height_m: clear height of the opening (m).
    """

    name: str
    rooms: tuple[str, str]
    x_m: float
    y_m: float
    along_x: bool
    width_m: float
    height_m: float


@dataclass(frozen=True)
class SpawnPose:
    """An upright start pose in free floor space.

    Attributes:
        x_m, y_m: position of the robot's base on the floor (m).
        yaw_rad: heading, 0 = along world +x (rad).
        clear_ahead_m: how far a robot of radius ``ROBOT_RADIUS_M`` can drive straight
            forward from here before touching anything (m, a lower bound).
        clear_behind_m: the same, driving backward (m).
    """

    x_m: float
    y_m: float
    yaw_rad: float
    clear_ahead_m: float
    clear_behind_m: float


@dataclass(frozen=True)
class House:
    """A house: rooms, walls, furniture, floor, ceiling and where a robot may start.

    Attributes:
        name: ``house1``, ``house2`` or ``random_<seed>``.
        seed: the seed of a random house; None for a fixed named layout.
        ceiling_height_m: floor to ceiling (m).
        wall_thickness_m: thickness of every wall (m).
        extent_m: (x_min, y_min, x_max, y_max) of the outer wall centrelines (m).
        rooms: the rooms.
        doorways: the openings joining them.
        floor: the floor geom (a plane facing up at z = 0).
        ceiling: the ceiling geom (a thin box whose underside is at ``ceiling_height_m``).
        walls: wall segments and door frames.
        furniture: the furniture.
        features: what makes the floor and the ceiling uneven (door thresholds, rugs,
            ramps, cables, sloped ceilings, stairs, wall shelves): parts named
            ``floor_<kind>_<k>...`` and ``ceiling_<kind>_<k>...`` are floor and ceiling
            surfaces; see :mod:`twsb_sim.house.floor_features` and
            :mod:`twsb_sim.house.ceilings`.
    """

    name: str
    seed: int | None
    ceiling_height_m: float
    wall_thickness_m: float
    extent_m: tuple[float, float, float, float]
    rooms: tuple[Room, ...]
    doorways: tuple[Doorway, ...]
    floor: Part
    ceiling: Part
    walls: tuple[Part, ...]
    furniture: tuple[Furniture, ...]
    features: tuple[Part, ...] = ()

    @functools.cached_property
    def spawn_poses(self) -> tuple[SpawnPose, ...]:
        """Start poses, the longest clear lane ahead first (see :mod:`.spawn`).

        Searched on first use, not when the house is built: the search is the costliest
        part of building a house, and most houses a run builds (the same plan with a
        scenario's extras, a start given by position) never need it.
        """
        from twsb_sim.house.spawn import find_spawn_poses  # spawn imports this module

        solid = [*self.walls, *(p for piece in self.furniture for p in piece.parts)]
        return find_spawn_poses(self.rooms, [*solid, *self.features], self.wall_thickness_m)

    def parts(self) -> Iterator[Part]:
        """Every geom of the house, floor and ceiling first, the features last."""
        yield self.floor
        yield self.ceiling
        yield from self.walls
        for piece in self.furniture:
            yield from piece.parts
        yield from self.features

    def room(self, name: str) -> Room:
        """The room called ``name``."""
        for room in self.rooms:
            if room.name == name:
                return room
        raise KeyError(f"{self.name} has no room {name!r}")
