"""Seeded random houses.

Recipe (every draw from ``numpy.random.default_rng(seed)``):

1. a rectangular house, 10-14 m by 7.5-10 m, ceiling 2.4-2.7 m;
2. a living room spanning the whole length on the south or north side (a long lane);
3. the rest: optionally a hall (1.2-1.4 m wide) across it, and the remaining blocks cut
   recursively into rooms at least ``MIN_ROOM_M`` wide (kitchen, bedrooms, study, bath);
4. doorways: a random spanning tree over the rooms that share enough wall, a door from
   the hall into every room it touches, and a few extra doors;
5. furniture per room type, against walls or free-standing, never in front of a doorway
   nor in the living room's middle lane, never overlapping;
6. the house's extras, from a stream of their own (:mod:`twsb_sim.house.random_extras`):
   ceiling height, thresholds and ramps in doorways, rugs, a cable, attic slopes, stairs,
   wall shelves.

A draw that leaves a room unreachable is thrown away and drawn again from the same
generator, so a seed always gives the same house.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from twsb_sim.house.extras import HouseExtras, with_extras
from twsb_sim.house.floorplan import WALL_THICKNESS_M, assemble_house
from twsb_sim.house.furniture import make_furniture
from twsb_sim.house.model import Doorway, Furniture, House, Room
from twsb_sim.house.placement import Rect, against_wall, door_keep_outs, footprint, interior
from twsb_sim.house.random_extras import draw_extras

MIN_ROOM_M = 2.6  # smallest room side between wall centrelines (m)
DOOR_CORNER_GAP_M = 0.35  # from a door's edge to the nearest wall corner (m)
DOOR_WIDTH_M = (0.8, 1.0)  # m
DOOR_HEIGHT_M = (2.0, 2.1)  # m
LANE_HALF_WIDTH_M = 0.6  # the living room keeps this much free either side of its axis (m)
FURNITURE_GAP_M = 0.1  # between two pieces (m)
PLACEMENT_TRIES = 30
MAX_PLAN_DRAWS = 100
SIDES = ("north", "south", "east", "west")
ROOM_TYPES = ("kitchen", "bedroom", "study", "bedroom", "bath", "study", "bedroom")


def _r(value: float, step: float = 0.05) -> float:
    """Round to a grid so plans read cleanly (and print stably)."""
    return round(round(value / step) * step, 6)


def _split(rng: np.random.Generator, rect: tuple[float, ...], depth: int, out: list) -> None:
    """Cut a block into rooms, recursively (a slicing floor plan)."""
    x0, y0, x1, y1 = rect
    w, h = x1 - x0, y1 - y0
    can_x, can_y = w >= 2 * MIN_ROOM_M, h >= 2 * MIN_ROOM_M
    small = w * h < 16.0 and rng.random() < 0.6
    if not (can_x or can_y) or depth >= 3 or (depth >= 1 and small):
        out.append(rect)
        return
    cut_x = can_x and (not can_y or w >= h)
    lo, hi = (x0, x1) if cut_x else (y0, y1)
    cut = _r(rng.uniform(lo + MIN_ROOM_M, hi - MIN_ROOM_M))
    first, second = (
        ((x0, y0, cut, y1), (cut, y0, x1, y1)) if cut_x else ((x0, y0, x1, cut), (x0, cut, x1, y1))
    )
    _split(rng, first, depth + 1, out)
    _split(rng, second, depth + 1, out)


def _rooms(rng: np.random.Generator) -> list[Room]:
    width = _r(rng.uniform(10.0, 14.0), 0.1)
    depth = _r(rng.uniform(7.5, 10.0), 0.1)
    living_depth = _r(rng.uniform(3.8, min(4.8, depth - 2.8)))
    living_south = bool(rng.random() < 0.5)
    ly0, ly1 = (0.0, living_depth) if living_south else (depth - living_depth, depth)
    ry0, ry1 = (living_depth, depth) if living_south else (0.0, depth - living_depth)
    rooms = [Room("living", 0.0, ly0, width, ly1)]
    blocks: list[tuple[float, ...]] = [(0.0, ry0, width, ry1)]
    if rng.random() < 0.6:
        hall_w = _r(rng.uniform(1.2, 1.4))
        hall_x = _r(rng.uniform(MIN_ROOM_M, width - MIN_ROOM_M - hall_w))
        rooms.append(Room("hall", hall_x, ry0, hall_x + hall_w, ry1))
        blocks = [(0.0, ry0, hall_x, ry1), (hall_x + hall_w, ry0, width, ry1)]
    cells: list[tuple[float, ...]] = []
    for block in blocks:
        _split(rng, block, 0, cells)
    cells.sort(key=lambda c: -(c[2] - c[0]) * (c[3] - c[1]))
    for k, (x0, y0, x1, y1) in enumerate(cells):
        rooms.append(Room(f"{ROOM_TYPES[k % len(ROOM_TYPES)]}_{k + 1}", x0, y0, x1, y1))
    return rooms


def _shared_walls(rooms: list[Room], min_length_m: float):
    """(i, j, along_x, line, lo, hi) for every pair of rooms sharing enough wall."""
    eps = 1e-6
    for i, a in enumerate(rooms):
        for j in range(i + 1, len(rooms)):
            b = rooms[j]
            for along_x, line_a, line_b, lo, hi in (
                (True, (a.y_min_m, a.y_max_m), (b.y_max_m, b.y_min_m),
                 max(a.x_min_m, b.x_min_m), min(a.x_max_m, b.x_max_m)),
                (False, (a.x_min_m, a.x_max_m), (b.x_max_m, b.x_min_m),
                 max(a.y_min_m, b.y_min_m), min(a.y_max_m, b.y_max_m)),
            ):  # fmt: skip
                for line, other in zip(line_a, line_b, strict=True):
                    if abs(line - other) < eps and hi - lo >= min_length_m:
                        yield i, j, along_x, line, lo, hi


def _doorways(rng: np.random.Generator, rooms: list[Room]) -> list[Doorway] | None:
    """Doors making every room reachable, or None if the plan cannot be connected."""
    min_len = DOOR_WIDTH_M[1] + 2 * DOOR_CORNER_GAP_M
    candidates = list(_shared_walls(rooms, min_len))
    order = rng.permutation(len(candidates))
    parent = list(range(len(rooms)))

    def root(k: int) -> int:
        while parent[k] != k:
            k = parent[k]
        return k

    chosen = []
    for c in order:
        i, j = candidates[c][:2]
        via_hall = "hall" in (rooms[i].name, rooms[j].name)
        joins = root(i) != root(j)
        if joins or via_hall or rng.random() < 0.2:
            parent[root(i)] = root(j)
            chosen.append(candidates[c])
    if len({root(k) for k in range(len(rooms))}) != 1:
        return None
    doors = []
    for k, (i, j, along_x, line, lo, hi) in enumerate(sorted(chosen)):
        width = _r(rng.uniform(*DOOR_WIDTH_M))
        margin = DOOR_CORNER_GAP_M + DOOR_WIDTH_M[1] / 2
        mid = _r(rng.uniform(lo + margin, hi - margin))
        x, y = (mid, line) if along_x else (line, mid)
        height = _r(rng.uniform(*DOOR_HEIGHT_M))
        doors.append(
            Doorway(f"door_{k}", (rooms[i].name, rooms[j].name), x, y, along_x, width, height)
        )
    return doors


# per room type: (kind, placement, dimension ranges (min, max) per width/depth/height)
_RECIPES: dict[str, tuple[tuple[str, str, tuple[tuple[float, float], ...]], ...]] = {
    "living": (
        ("sofa", "wall", ((1.6, 2.2), (0.85, 0.95), (0.8, 0.9))),
        ("table", "free", ((0.9, 1.2), (0.5, 0.6), (0.4, 0.45))),
        ("shelf", "wall", ((0.6, 1.2), (0.3, 0.4), (1.2, 2.0))),
        ("cabinet", "wall", ((1.2, 1.8), (0.4, 0.5), (0.45, 0.6))),
        ("chair", "free", ((0.45, 0.5), (0.45, 0.5), (0.85, 0.95))),
        ("table", "dining", ((1.2, 1.6), (0.8, 0.9), (0.72, 0.76))),
    ),
    "kitchen": (
        ("cabinet", "wall", ((1.6, 2.6), (0.6, 0.6), (0.88, 0.92))),
        ("cabinet", "wall", ((1.0, 1.8), (0.6, 0.6), (0.88, 0.92))),
        ("table", "dining", ((0.8, 1.2), (0.7, 0.8), (0.72, 0.76))),
    ),
    "bedroom": (
        ("bed", "wall", ((0.9, 1.8), (2.0, 2.1), (0.45, 0.55))),
        ("cabinet", "wall", ((0.8, 1.4), (0.55, 0.6), (1.9, 2.1))),
        ("shelf", "wall", ((0.6, 1.0), (0.3, 0.35), (1.0, 1.8))),
    ),
    "study": (
        ("table", "wall", ((1.0, 1.4), (0.55, 0.7), (0.72, 0.76))),
        ("chair", "free", ((0.45, 0.5), (0.45, 0.5), (0.85, 0.95))),
        ("shelf", "wall", ((0.8, 1.2), (0.3, 0.4), (1.6, 2.0))),
        ("cabinet", "wall", ((0.6, 1.0), (0.4, 0.5), (0.7, 0.8))),
    ),
    "bath": (
        ("cabinet", "wall", ((0.6, 1.0), (0.45, 0.5), (0.8, 0.9))),
        ("shelf", "wall", ((0.4, 0.6), (0.25, 0.3), (1.2, 1.6))),
    ),
    "hall": (),
}


class _Furnisher:
    """Places pieces into rooms without overlaps, counting names per kind."""

    def __init__(self, rng: np.random.Generator, keep_out: list[Rect]) -> None:
        self.rng = rng
        self.taken = list(keep_out)
        self.pieces: list[Furniture] = []
        self.count: dict[str, int] = {}

    def _accept(self, piece: Furniture, room_rect: Rect) -> bool:
        rect = footprint(piece)
        if not rect.inside(room_rect) or any(rect.overlaps(t, FURNITURE_GAP_M) for t in self.taken):
            return False
        self.taken.append(rect)
        self.pieces.append(piece)
        self.count[piece.kind] = self.count.get(piece.kind, 0) + 1
        return True

    def place(self, room: Room, kind: str, how: str, dims: tuple[float, float, float]) -> None:
        rng, inside = self.rng, interior(room)
        for _ in range(PLACEMENT_TRIES):
            index = self.count.get(kind, 0)
            if how == "wall":
                side = SIDES[int(rng.integers(4))]
                length = (
                    inside.x1 - inside.x0 if side in ("north", "south") else inside.y1 - inside.y0
                )
                if length < dims[0] + 0.1:
                    continue
                offset = _r(rng.uniform(dims[0] / 2 + 0.05, length - dims[0] / 2 - 0.05), 0.01)
                piece = against_wall(kind, index, room, side, offset, dims)
            else:
                yaw = math.pi / 2 * int(rng.integers(4))
                x = _r(rng.uniform(inside.x0 + 0.5, inside.x1 - 0.5), 0.01)
                y = _r(rng.uniform(inside.y0 + 0.5, inside.y1 - 0.5), 0.01)
                piece = make_furniture(kind, index, x, y, yaw, dims)
            if self._accept(piece, inside):
                if how == "dining":
                    self._chairs_around(piece, inside)
                return

    def _chairs_around(self, table: Furniture, inside: Rect) -> None:
        """Up to two chairs facing the table's long sides."""
        c, s = math.cos(table.yaw_rad), math.sin(table.yaw_rad)
        reach = table.depth_m / 2 + 0.3
        for side in (-1.0, 1.0):
            # a chair's back is its local +y: turn it so the back points away from the table
            x, y = table.x_m - s * side * reach, table.y_m + c * side * reach
            yaw = table.yaw_rad + (0.0 if side > 0 else math.pi)
            chair = make_furniture(
                "chair", self.count.get("chair", 0), _r(x, 0.01), _r(y, 0.01), yaw
            )
            self._accept(chair, inside)


def _furnish(rng: np.random.Generator, rooms: list[Room], doors: list[Doorway]) -> list[Furniture]:
    keep_out = door_keep_outs(doors)
    living = rooms[0]
    mid = (living.y_min_m + living.y_max_m) / 2
    keep_out.append(
        Rect(living.x_min_m, mid - LANE_HALF_WIDTH_M, living.x_max_m, mid + LANE_HALF_WIDTH_M)
    )
    furnisher = _Furnisher(rng, keep_out)
    for room in rooms:
        room_type = room.name.rsplit("_", 1)[0] if room.name[-1].isdigit() else room.name
        for kind, how, ranges in _RECIPES[room_type]:
            dims = tuple(_r(rng.uniform(lo, hi), 0.01) for lo, hi in ranges)
            furnisher.place(room, kind, how, dims)  # type: ignore[arg-type]
    return furnisher.pieces


@functools.lru_cache(maxsize=16)
def random_house(seed: int) -> House:
    """A random house drawn from ``seed``; the same seed always gives the same house.

    The last few houses are kept (a House is immutable): asking again for the same seed,
    e.g. to plan a run and then to run it, costs nothing.

    Args:
        seed: any non-negative integer.

    Returns:
        A house named ``random_<seed>``, with its extras.
    """
    return with_extras(random_plain_house(seed), random_house_extras(seed))


def random_house_extras(seed: int) -> HouseExtras:
    """The extras of random house ``seed`` (ceiling, floor features, stairs, ...)."""
    plain = random_plain_house(seed)
    return draw_extras(seed, plain.rooms, plain.doorways, plain.furniture, plain.extent_m)


@functools.lru_cache(maxsize=16)
def random_plain_house(seed: int) -> House:
    """Random house ``seed`` without its extras: rooms, doorways, furniture, a flat
    ceiling at 2.4-2.7 m."""
    rng = np.random.default_rng(np.random.SeedSequence(seed))
    ceiling = _r(rng.uniform(2.4, 2.7), 0.01)
    for _ in range(MAX_PLAN_DRAWS):
        rooms = _rooms(rng)
        doors = _doorways(rng, rooms)
        if doors is not None:
            break
    else:  # pragma: no cover - a plan always connects within a few draws
        raise RuntimeError(f"seed {seed}: no connected floor plan in {MAX_PLAN_DRAWS} draws")
    furniture = _furnish(rng, rooms, doors)
    return assemble_house(
        f"random_{seed}", seed, ceiling, rooms, doors, furniture, WALL_THICKNESS_M
    )
