"""From rooms, doorways and furniture to a complete house: walls, door frames, floor,
ceiling and spawn poses.

Rooms are rectangles whose bounds are wall centrelines; rooms that touch share a wall.
Every room edge becomes wall; collinear edges merge into one segment, extended by half
a wall thickness at both ends so corners and T-junctions close; doorways cut gaps of
their clear width into it, framed by two jambs and a header.
"""

from __future__ import annotations

import math
from collections import defaultdict
from collections.abc import Sequence

from twsb_sim.house.model import Doorway, Furniture, House, Part, Rgba, Room

WALL_THICKNESS_M = 0.1  # m
JAMB_WIDTH_M = 0.05  # door jamb along the wall (m)
JAMB_PROTRUSION_M = 0.02  # jambs stand out of the wall on each side (m)
FLOOR_MARGIN_M = 0.5  # the floor reaches this far beyond the outer walls (m)
CEILING_THICKNESS_M = 0.05  # m

WALL_COLOUR: Rgba = (0.92, 0.90, 0.85, 1.0)
DOOR_FRAME_COLOUR: Rgba = (0.97, 0.96, 0.93, 1.0)
FLOOR_COLOUR: Rgba = (0.62, 0.48, 0.34, 1.0)
CEILING_COLOUR: Rgba = (0.98, 0.98, 0.97, 1.0)
STRUCTURE_GROUP = 0  # floor, walls and door frames
CEILING_GROUP = 2  # so a viewer can hide the ceiling by toggling one group


def _merge(intervals: list[tuple[float, float]]) -> list[tuple[float, float]]:
    merged: list[tuple[float, float]] = []
    for a, b in sorted(intervals):
        if merged and a <= merged[-1][1] + 1e-9:
            merged[-1] = (merged[-1][0], max(merged[-1][1], b))
        else:
            merged.append((a, b))
    return merged


def _subtract(span: tuple[float, float], holes: list[tuple[float, float]]):
    start, end = span
    for a, b in sorted(holes):
        if b <= start or a >= end:
            continue
        if a > start:
            yield start, a
        start = max(start, b)
    if end > start:
        yield start, end


def _slab(name: str, along_x: bool, line: float, a: float, b: float, z0: float, z1: float,
          depth: float, rgba: Rgba) -> Part:  # fmt: skip
    """A box spanning [a, b] along a wall line, from height z0 to z1, ``depth`` thick."""
    mid, half = (a + b) / 2, (b - a) / 2
    size = (half, depth / 2, (z1 - z0) / 2) if along_x else (depth / 2, half, (z1 - z0) / 2)
    pos = (mid, line, (z0 + z1) / 2) if along_x else (line, mid, (z0 + z1) / 2)
    return Part(name, "box", size, pos, 0.0, rgba, STRUCTURE_GROUP)


def build_walls(
    rooms: Sequence[Room], doorways: Sequence[Doorway], height_m: float, thickness_m: float
) -> tuple[Part, ...]:
    """Wall segments (``wall_<k>``) and door frames (``door_frame_<k>_left|right|header``)."""
    lines: dict[tuple[bool, float], list[tuple[float, float]]] = defaultdict(list)
    for r in rooms:
        for y in (r.y_min_m, r.y_max_m):
            lines[(True, round(y, 6))].append((r.x_min_m, r.x_max_m))
        for x in (r.x_min_m, r.x_max_m):
            lines[(False, round(x, 6))].append((r.y_min_m, r.y_max_m))
    holes: dict[tuple[bool, float], list[tuple[float, float]]] = defaultdict(list)
    for door in doorways:
        line, mid = (door.y_m, door.x_m) if door.along_x else (door.x_m, door.y_m)
        holes[(door.along_x, round(line, 6))].append(
            (mid - door.width_m / 2, mid + door.width_m / 2)
        )
    walls: list[Part] = []
    for along_x, line in sorted(lines):
        for a, b in _merge(lines[(along_x, line)]):
            span = (a - thickness_m / 2, b + thickness_m / 2)
            for lo, hi in _subtract(span, holes[(along_x, line)]):
                name = f"wall_{len(walls)}"
                walls.append(
                    _slab(name, along_x, line, lo, hi, 0.0, height_m, thickness_m, WALL_COLOUR)
                )
    frames: list[Part] = []
    for k, door in enumerate(doorways):
        line, mid = (door.y_m, door.x_m) if door.along_x else (door.x_m, door.y_m)
        edge = door.width_m / 2 + JAMB_WIDTH_M
        jamb_depth = thickness_m + 2 * JAMB_PROTRUSION_M
        for side, (a, b) in (("left", (mid - edge, mid - door.width_m / 2)),
                             ("right", (mid + door.width_m / 2, mid + edge))):  # fmt: skip
            frames.append(
                _slab(f"door_frame_{k}_{side}", door.along_x, line, a, b, 0.0, door.height_m,
                      jamb_depth, DOOR_FRAME_COLOUR)
            )  # fmt: skip
        frames.append(
            _slab(f"door_frame_{k}_header", door.along_x, line, mid - edge, mid + edge,
                  door.height_m, height_m, thickness_m, DOOR_FRAME_COLOUR)
        )  # fmt: skip
    return (*walls, *frames)


def assemble_house(
    name: str,
    seed: int | None,
    ceiling_height_m: float,
    rooms: Sequence[Room],
    doorways: Sequence[Doorway],
    furniture: Sequence[Furniture],
    wall_thickness_m: float = WALL_THICKNESS_M,
) -> House:
    """Complete a floor plan into a ``House``: walls, floor, ceiling (spawn poses on demand)."""
    x0 = min(r.x_min_m for r in rooms)
    y0 = min(r.y_min_m for r in rooms)
    x1 = max(r.x_max_m for r in rooms)
    y1 = max(r.y_max_m for r in rooms)
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    hx, hy = (x1 - x0) / 2, (y1 - y0) / 2
    floor = Part(
        "floor", "plane", (hx + FLOOR_MARGIN_M, hy + FLOOR_MARGIN_M, 0.1), (cx, cy, 0.0), 0.0,
        FLOOR_COLOUR, STRUCTURE_GROUP,
    )  # fmt: skip
    ceiling = Part(
        "ceiling", "box", (hx + wall_thickness_m, hy + wall_thickness_m, CEILING_THICKNESS_M / 2),
        (cx, cy, ceiling_height_m + CEILING_THICKNESS_M / 2), 0.0, CEILING_COLOUR, CEILING_GROUP,
    )  # fmt: skip
    walls = build_walls(rooms, doorways, ceiling_height_m, wall_thickness_m)
    return House(
        name=name,
        seed=seed,
        ceiling_height_m=ceiling_height_m,
        wall_thickness_m=wall_thickness_m,
        extent_m=(x0, y0, x1, y1),
        rooms=tuple(rooms),
        doorways=tuple(doorways),
        floor=floor,
        ceiling=ceiling,
        walls=walls,
        furniture=tuple(furniture),
    )


def yaw_facing_away_from_wall(side: str) -> float:
    """Yaw that puts a piece's back (local +y) against the room's ``side`` wall
    (``"north"`` = +y, ``"south"``, ``"east"`` = +x, ``"west"``)."""
    return {"north": 0.0, "south": math.pi, "east": -math.pi / 2, "west": math.pi / 2}[side]
