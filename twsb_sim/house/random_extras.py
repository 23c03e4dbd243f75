"""The extras of a random house, drawn from its seed: ceiling height, thresholds and ramps
in doorways, rugs, a cable, attic slopes, stairs, wall shelves.

The draws come from their own stream (``SeedSequence(seed, spawn_key=(1,))``), apart from
the floor plan's: a seed's rooms, doorways and furniture are what they were before houses
had extras. Probabilities and ranges are constants here (homes as they are, not a knob
of the data-set generator, which places features on the robot's own path instead).
"""

from __future__ import annotations

import math

import numpy as np

from twsb_sim.house.ceilings import MAX_RISE_M, TREAD_DEPTH_M, AtticSlope, Staircase
from twsb_sim.house.extras import HouseExtras, WallShelf
from twsb_sim.house.floor_features import FloorFeature
from twsb_sim.house.model import Doorway, Furniture, Room
from twsb_sim.house.placement import Rect, door_keep_outs, footprint, interior

EXTRAS_STREAM = 1  # spawn key of the extras' stream under the house seed
BASEMENT_PROBABILITY = 0.2  # a low ceiling, 2.0-2.3 m
CEILING_M = (2.3, 3.0)  # m, the other houses
BASEMENT_CEILING_M = (2.0, 2.3)  # m
THRESHOLD_PROBABILITY = 0.6  # per doorway
RAMP_PROBABILITY = 0.15  # per doorway, instead of a threshold
RUG_PROBABILITY = 0.6  # per living room and bedroom
CABLE_PROBABILITY = 0.3  # per house
ATTIC_PROBABILITY = 0.25  # per house: slopes over the rooms off the living room
MAX_ATTIC_SHARE = 0.45  # a slope covers at most this share of its room's depth
DOOR_HEADROOM_M = 0.1  # m, a slope passes at least this high over a doorway's edge
STAIRS_PROBABILITY = 0.3  # per house: a flight along the living room's outer wall
SHELVES = (0, 3)  # wall shelves per house, low and high (inclusive)
TRIES = 20  # placement attempts per item


def _u(rng: np.random.Generator, low: float, high: float, step: float = 0.005) -> float:
    return round(round(float(rng.uniform(low, high)) / step) * step, 6)


def _doorway_feature(rng: np.random.Generator, door: Doorway) -> FloorFeature | None:
    yaw = math.pi / 2 if door.along_x else 0.0  # crossed perpendicular to the wall
    draw = rng.random()
    if draw < RAMP_PROBABILITY:
        return FloorFeature(
            "ramp", door.x_m, door.y_m, yaw, _u(rng, 0.03, 0.08), door.width_m,
            width_m=_u(rng, 0.1, 0.3), slope_deg=_u(rng, 5.0, 8.0, 0.5),
        )  # fmt: skip
    if draw < RAMP_PROBABILITY + THRESHOLD_PROBABILITY:
        return FloorFeature(
            "threshold", door.x_m, door.y_m, yaw, _u(rng, 0.01, 0.03), door.width_m,
            width_m=_u(rng, 0.05, 0.12), slope_deg=_u(rng, 25.0, 35.0, 0.5),
        )  # fmt: skip
    return None


def _rug(rng: np.random.Generator, room: Room) -> FloorFeature:
    inside = interior(room)
    width = _u(rng, 1.0, min(3.0, inside.x1 - inside.x0 - 0.2))
    length = _u(rng, 1.0, min(2.5, inside.y1 - inside.y0 - 0.2))
    x = _u(rng, inside.x0 + width / 2 + 0.1, inside.x1 - width / 2 - 0.1)
    y = _u(rng, inside.y0 + length / 2 + 0.1, inside.y1 - length / 2 - 0.1)
    friction = (_u(rng, 0.8, 1.4, 0.01), 0.02, _u(rng, 0.0005, 0.003, 0.0001))
    return FloorFeature(
        "rug", x, y, 0.0, _u(rng, 0.005, 0.02, 0.001), length, width, 30.0, friction
    )


def _cable(rng: np.random.Generator, room: Room) -> FloorFeature:
    inside = interior(room)
    across_x = bool(rng.random() < 0.5)  # the cable runs along y, crossed along x
    span = (inside.y1 - inside.y0) if across_x else (inside.x1 - inside.x0)
    length = _u(rng, 1.0, min(3.0, span))
    x = _u(rng, inside.x0 + 0.3, inside.x1 - 0.3)
    y = _u(rng, inside.y0 + 0.3, inside.y1 - 0.3)
    yaw = 0.0 if across_x else math.pi / 2
    return FloorFeature("cable", x, y, yaw, _u(rng, 0.008, 0.024, 0.001), length)


def _outer_sides(room: Room, extent: tuple[float, float, float, float]) -> list[str]:
    x0, y0, x1, y1 = extent
    sides = {"south": room.y_min_m == y0, "north": room.y_max_m == y1}
    sides |= {"west": room.x_min_m == x0, "east": room.x_max_m == x1}
    return [side for side, outer in sides.items() if outer]


def _strip(room: Room, side: str, depth_m: float) -> Rect:
    """The floor within ``depth_m`` of one wall of a room."""
    r = interior(room)
    return {
        "north": Rect(r.x0, r.y1 - depth_m, r.x1, r.y1),
        "south": Rect(r.x0, r.y0, r.x1, r.y0 + depth_m),
        "east": Rect(r.x1 - depth_m, r.y0, r.x1, r.y1),
        "west": Rect(r.x0, r.y0, r.x0 + depth_m, r.y1),
    }[side]


def _door_gap_m(door: Doorway, room: Room, side: str) -> float:
    """How far a doorway of ``room`` stays from the wall ``side``: the distance from that
    wall's centreline to the opening's nearest edge (m)."""
    face = {"north": room.y_max_m, "south": room.y_min_m, "east": room.x_max_m,
            "west": room.x_min_m}[side]  # fmt: skip
    along_wall = side in ("north", "south")
    if door.along_x == along_wall:  # a doorway in a wall parallel to this one
        return abs((door.y_m if along_wall else door.x_m) - face)
    centre = door.y_m if along_wall else door.x_m
    return abs(centre - face) - door.width_m / 2


def _attic(rng, rooms, furniture, doorways, extent, ceiling_m) -> tuple[AtticSlope, ...]:
    slopes = []
    for room in rooms[1:]:  # the rooms off the living room sit under the roof
        knee, pitch = _u(rng, 1.0, 1.4, 0.05), _u(rng, 30.0, 45.0, 0.5)
        for side in _outer_sides(room, extent):
            # a slope covers at most MAX_ATTIC_SHARE of the room's depth: a steeper roof
            depth = room.size_m[1] if side in ("north", "south") else room.size_m[0]
            flattest = math.degrees(math.atan2(ceiling_m - knee, MAX_ATTIC_SHARE * depth))
            pitch = max(pitch, round(flattest + 0.5, 1))
            if pitch > 60.0:
                continue
            # every doorway of the room stays under the slope with room to spare
            slope = math.tan(math.radians(pitch))
            ours = [d for d in doorways if room.name in d.rooms]
            clear = [knee + _door_gap_m(d, room, side) * slope - d.height_m for d in ours]
            if any(c < DOOR_HEADROOM_M for c in clear):
                continue
            strip = _strip(room, side, 1.0)
            tall = [p for p in furniture if p.height_m > knee and footprint(p).overlaps(strip)]
            if not tall:
                slopes.append(AtticSlope(room.name, side, knee, pitch))
    return tuple(slopes)


def _stairs(rng, living: Room, ceiling_m, taken, extent) -> Staircase | None:
    run = math.ceil(ceiling_m / MAX_RISE_M) * TREAD_DEPTH_M
    width = _u(rng, 0.8, 1.0, 0.05)
    inside = interior(living)
    for side in _outer_sides(living, extent):
        if side not in ("north", "south") or inside.x1 - inside.x0 < run + 0.4:
            continue
        strip = _strip(living, side, width + 0.1)
        for _ in range(TRIES):
            start = _u(rng, 0.1, inside.x1 - inside.x0 - run - 0.1, 0.05)
            rect = Rect(inside.x0 + start, strip.y0, inside.x0 + start + run, strip.y1)
            if not any(rect.overlaps(t) for t in taken):
                taken.append(rect)
                return Staircase(living.name, side, start, width, bool(rng.random() < 0.5))
    return None


def _shelf(rng, rooms, taken) -> WallShelf | None:
    for _ in range(TRIES):
        room = rooms[int(rng.integers(len(rooms)))]
        side = ("north", "south", "east", "west")[int(rng.integers(4))]
        inside = interior(room)
        along = inside.x1 - inside.x0 if side in ("north", "south") else inside.y1 - inside.y0
        width, depth = _u(rng, 0.6, 1.2, 0.05), _u(rng, 0.2, 0.3, 0.01)
        if along < width + 0.2:
            continue
        offset = _u(rng, width / 2 + 0.05, along - width / 2 - 0.05, 0.01)
        strip = _strip(room, side, depth)
        if side in ("north", "south"):
            rect = Rect(inside.x0 + offset - width / 2, strip.y0, inside.x0 + offset + width / 2,
                        strip.y1)  # fmt: skip
        else:
            rect = Rect(strip.x0, inside.y0 + offset - width / 2, strip.x1,
                        inside.y0 + offset + width / 2)  # fmt: skip
        if not any(rect.overlaps(t, 0.05) for t in taken):
            taken.append(rect)
            return WallShelf(room.name, side, offset, width, depth, _u(rng, 0.35, 1.2, 0.01))
    return None


def draw_extras(
    seed: int,
    rooms: tuple[Room, ...],
    doorways: tuple[Doorway, ...],
    furniture: tuple[Furniture, ...],
    extent: tuple[float, float, float, float],
) -> HouseExtras:
    """The extras of random house ``seed`` (``rooms[0]`` is its living room)."""
    rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(EXTRAS_STREAM,)))
    low = rng.random() < BASEMENT_PROBABILITY
    ceiling = _u(rng, *(BASEMENT_CEILING_M if low else CEILING_M), 0.01)
    features = [f for door in doorways if (f := _doorway_feature(rng, door)) is not None]
    for room in rooms:
        if room.name.startswith(("living", "bedroom")) and rng.random() < RUG_PROBABILITY:
            features.append(_rug(rng, room))
    if rng.random() < CABLE_PROBABILITY:
        features.append(_cable(rng, rooms[int(rng.integers(len(rooms)))]))
    attic = ()
    if rng.random() < ATTIC_PROBABILITY:
        attic = _attic(rng, rooms, furniture, doorways, extent, ceiling)
    taken = [footprint(p) for p in furniture] + door_keep_outs(doorways)
    stairs = None
    if rng.random() < STAIRS_PROBABILITY:
        stairs = _stairs(rng, rooms[0], ceiling, taken, extent)
    count = int(rng.integers(SHELVES[0], SHELVES[1] + 1))
    shelves = [_shelf(rng, rooms, taken) for _ in range(count)]
    return HouseExtras(
        ceiling_height_m=ceiling,
        floor_features=tuple(features),
        attic_slopes=attic,
        staircases=(stairs,) if stairs is not None else (),
        wall_shelves=tuple(s for s in shelves if s is not None),
    )
