"""What a house holds beyond rooms, walls and furniture: its floor features, lower or
sloped ceilings, stairs and wall shelves, added to a plain house.

``with_extras(house, extras)`` takes a plain house (no features yet) and returns it with a
new ceiling height (walls and door headers follow; doorways stay below the ceiling), the
extras' parts in ``House.features``; its spawn poses keep clear of the extras that block
the robot (stair treads, wall shelves). Named and random houses come with extras of their
own; a scenario can add more (:func:`merge_extras`).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from twsb_sim.house.ceilings import AtticSlope, Staircase, attic_slope_part, staircase_parts
from twsb_sim.house.floor_features import FloorFeature, features_to_parts
from twsb_sim.house.floorplan import assemble_house
from twsb_sim.house.furniture import FURNITURE_GROUP, WOOD
from twsb_sim.house.model import House, Part, Room

MIN_CEILING_M = 1.9  # m
MAX_CEILING_M = 4.0  # m
DOOR_HEADER_MIN_M = 0.1  # m, a doorway stays at least this far below the ceiling
SHELF_BOARD_THICKNESS_M = 0.025  # m


@dataclass(frozen=True)
class WallShelf:
    """A shelf board on a wall, with nothing under it (a tilted plane meets its underside).

    Attributes:
        room: the room's name.
        side: the wall: ``north`` (+y), ``south``, ``east`` (+x), ``west``.
        offset_m: its centre along the wall, from the wall's west or south end (m).
        width_m: along the wall (m); depth_m: out of it (m).
        height_m: its top above the floor (m).
    """

    room: str
    side: str
    offset_m: float
    width_m: float = 0.9
    depth_m: float = 0.25
    height_m: float = 0.8

    def __post_init__(self) -> None:
        if not 0.1 <= self.height_m <= 2.5:
            raise ValueError(f"height_m: expected 0.1 to 2.5 m, got {self.height_m}")


@dataclass(frozen=True)
class HouseExtras:
    """Changes to a house: a new ceiling height and parts added to it."""

    ceiling_height_m: float | None = None  # m; None keeps the house's
    floor_features: tuple[FloorFeature, ...] = ()
    attic_slopes: tuple[AtticSlope, ...] = ()
    staircases: tuple[Staircase, ...] = ()
    wall_shelves: tuple[WallShelf, ...] = ()

    def __post_init__(self) -> None:
        h = self.ceiling_height_m
        if h is not None and not MIN_CEILING_M <= h <= MAX_CEILING_M:
            raise ValueError(
                f"ceiling_height_m: expected {MIN_CEILING_M} to {MAX_CEILING_M} m, got {h}"
            )

    def __bool__(self) -> bool:
        return any(getattr(self, f.name) for f in dataclasses.fields(self))


def wall_shelf_part(shelf: WallShelf, room: Room, wall_thickness_m: float, index: int) -> Part:
    """The board of a wall shelf, its back against the wall."""
    t = wall_thickness_m / 2
    z = shelf.height_m - SHELF_BOARD_THICKNESS_M / 2
    off = t + shelf.depth_m / 2  # from the wall centreline to the board's centre
    half_width, half_depth = shelf.width_m / 2, shelf.depth_m / 2
    half_z = SHELF_BOARD_THICKNESS_M / 2
    if shelf.side in ("north", "south"):
        y = room.y_max_m - off if shelf.side == "north" else room.y_min_m + off
        pos, size = (room.x_min_m + t + shelf.offset_m, y, z), (half_width, half_depth, half_z)
    else:
        x = room.x_max_m - off if shelf.side == "east" else room.x_min_m + off
        pos, size = (x, room.y_min_m + t + shelf.offset_m, z), (half_depth, half_width, half_z)
    return Part(f"shelfboard_{index}", "box", size, pos, 0.0, WOOD, FURNITURE_GROUP)


def merge_extras(first: HouseExtras, then: HouseExtras) -> HouseExtras:
    """Both sets of extras; ``then``'s ceiling height wins when it gives one."""
    return HouseExtras(
        ceiling_height_m=then.ceiling_height_m or first.ceiling_height_m,
        **{
            f.name: (*getattr(first, f.name), *getattr(then, f.name))
            for f in dataclasses.fields(HouseExtras)
            if f.name != "ceiling_height_m"
        },
    )


def extra_parts(house: House, extras: HouseExtras, ceiling_height_m: float) -> tuple[Part, ...]:
    """The parts of the extras in ``house`` under a ceiling at ``ceiling_height_m``."""
    t = house.wall_thickness_m
    parts = list(features_to_parts(extras.floor_features))
    for k, slope in enumerate(extras.attic_slopes):
        parts.append(attic_slope_part(slope, house.room(slope.room), ceiling_height_m, t, k))
    for k, stairs in enumerate(extras.staircases):
        parts.extend(staircase_parts(stairs, house.room(stairs.room), ceiling_height_m, t, k))
    for k, shelf in enumerate(extras.wall_shelves):
        parts.append(wall_shelf_part(shelf, house.room(shelf.room), t, k))
    return tuple(parts)


def with_extras(house: House, extras: HouseExtras) -> House:
    """The plain ``house`` with ``extras`` applied (the same house when there are none).

    Raises:
        ValueError: ``house`` has features already (apply all extras at once).
        KeyError: an extra names a room the house does not have.
    """
    if not extras:
        return house
    if house.features:
        raise ValueError(f"{house.name}: extras go onto a plain house, this one has features")
    height = extras.ceiling_height_m or house.ceiling_height_m
    if height != house.ceiling_height_m:
        doors = tuple(
            dataclasses.replace(d, height_m=min(d.height_m, height - DOOR_HEADER_MIN_M))
            for d in house.doorways
        )
        house = assemble_house(
            house.name, house.seed, height, house.rooms, doors, house.furniture,
            house.wall_thickness_m,
        )  # fmt: skip
    features = extra_parts(house, extras, height)
    return dataclasses.replace(house, features=features)  # its spawn poses: searched anew
