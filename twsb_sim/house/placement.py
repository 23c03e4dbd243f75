"""Putting furniture into rooms: against a wall, or free-standing, without overlaps."""

from __future__ import annotations

import math
from dataclasses import dataclass

from twsb_sim.house.floorplan import WALL_THICKNESS_M, yaw_facing_away_from_wall
from twsb_sim.house.furniture import DEFAULT_DIMENSIONS_M, make_furniture
from twsb_sim.house.model import Doorway, Furniture, Room

WALL_GAP_M = 0.02  # gap between a piece's back and the wall (m)
DOOR_KEEP_OUT_M = 1.0  # no furniture within this distance in front of a doorway (m)
DOOR_KEEP_OUT_SIDE_M = 0.2  # ... nor this far to either side of the opening (m)


def against_wall(
    kind: str,
    index: int,
    room: Room,
    side: str,
    offset_m: float,
    dimensions_m: tuple[float, float, float] | None = None,
) -> Furniture:
    """A piece with its back against one wall of ``room``.

    Args:
        kind: furniture kind.
        index: the ``k`` of its name.
        room: the room.
        side: ``"north"`` (+y), ``"south"``, ``"east"`` (+x) or ``"west"``.
        offset_m: where its centre lies along the wall, from the wall's west or south
            end inside the room (m).
        dimensions_m: (width, depth, height) in m, or the kind's default.
    """
    w, d, h = dimensions_m or DEFAULT_DIMENSIONS_M[kind]
    inner = WALL_THICKNESS_M / 2
    back_off = inner + WALL_GAP_M + d / 2
    if side in ("north", "south"):
        x = room.x_min_m + inner + offset_m
        y = room.y_max_m - back_off if side == "north" else room.y_min_m + back_off
    else:
        y = room.y_min_m + inner + offset_m
        x = room.x_max_m - back_off if side == "east" else room.x_min_m + back_off
    return make_furniture(kind, index, x, y, yaw_facing_away_from_wall(side), (w, d, h))


@dataclass(frozen=True)
class Rect:
    """An axis-aligned rectangle in the floor plane (m)."""

    x0: float
    y0: float
    x1: float
    y1: float

    def overlaps(self, other: Rect, margin_m: float = 0.0) -> bool:
        """Whether the two rectangles come closer than ``margin_m``."""
        return not (
            self.x1 + margin_m <= other.x0
            or other.x1 + margin_m <= self.x0
            or self.y1 + margin_m <= other.y0
            or other.y1 + margin_m <= self.y0
        )

    def inside(self, other: Rect) -> bool:
        """Whether this rectangle lies within ``other``."""
        return (
            self.x0 >= other.x0
            and self.y0 >= other.y0
            and self.x1 <= other.x1
            and self.y1 <= other.y1
        )


def footprint(piece: Furniture) -> Rect:
    """The world-axis-aligned footprint of a piece placed at a multiple of 90 degrees."""
    quarter_turn = round(piece.yaw_rad / (math.pi / 2)) % 2 == 1
    hx, hy = piece.width_m / 2, piece.depth_m / 2
    if quarter_turn:
        hx, hy = hy, hx
    return Rect(piece.x_m - hx, piece.y_m - hy, piece.x_m + hx, piece.y_m + hy)


def interior(room: Room) -> Rect:
    """The floor inside a room's walls."""
    t = WALL_THICKNESS_M / 2
    return Rect(room.x_min_m + t, room.y_min_m + t, room.x_max_m - t, room.y_max_m - t)


def door_keep_outs(doorways: list[Doorway] | tuple[Doorway, ...]) -> list[Rect]:
    """The floor in front of and behind every doorway, kept free for passing."""
    rects = []
    for door in doorways:
        half = door.width_m / 2 + DOOR_KEEP_OUT_SIDE_M
        if door.along_x:
            rects.append(Rect(door.x_m - half, door.y_m - DOOR_KEEP_OUT_M,
                              door.x_m + half, door.y_m + DOOR_KEEP_OUT_M))  # fmt: skip
        else:
            rects.append(Rect(door.x_m - DOOR_KEEP_OUT_M, door.y_m - half,
                              door.x_m + DOOR_KEEP_OUT_M, door.y_m + half))  # fmt: skip
    return rects
