"""The fixed named layouts: ``house1``, ``house2``, ``basement`` and ``attic``.

house1 (11 m x 8 m, ceiling 2.5 m): a long living room (10.9 m x 4.4 m inside) with a
sofa corner and a dining table, and three rooms off its north side (kitchen, bedroom,
study). A lane along the living room's middle is clear for ~10 m: room to reach 1 m/s
and stop hard.

house2 (14 m x 10 m, ceiling 2.6 m): a 14 m corridor with living room, dining room and
kitchen to the south and two bedrooms, a bathroom and an office to the north; more
furniture per room. The corridor and the rooms' middles are the long free lanes.

``basement`` and ``attic`` (low and sloped ceilings), and every layout's extras
(thresholds, rugs, stairs, ...), are in :mod:`twsb_sim.house.named_extras`.
"""

from __future__ import annotations

import functools
import math

from twsb_sim.house.extras import HouseExtras, with_extras
from twsb_sim.house.floorplan import assemble_house
from twsb_sim.house.furniture import make_furniture
from twsb_sim.house.model import Doorway, House, Room
from twsb_sim.house.named_extras import EXTRA_LAYOUTS, NAMED_EXTRAS
from twsb_sim.house.placement import against_wall

DOOR_HEIGHT_M = 2.05  # m
NORTH, SOUTH, EAST, WEST = "north", "south", "east", "west"
FACE_SOUTH, FACE_NORTH, FACE_WEST, FACE_EAST = 0.0, math.pi, -math.pi / 2, math.pi / 2


def _door(k: int, rooms: tuple[str, str], x: float, y: float, along_x: bool, w: float = 0.9):
    return Doorway(f"door_{k}", rooms, x, y, along_x, w, DOOR_HEIGHT_M)


def _house1() -> House:
    living = Room("living", 0.0, 0.0, 11.0, 4.5)
    kitchen = Room("kitchen", 0.0, 4.5, 4.0, 8.0)
    bedroom = Room("bedroom", 4.0, 4.5, 8.0, 8.0)
    study = Room("study", 8.0, 4.5, 11.0, 8.0)
    doors = (
        _door(0, ("living", "kitchen"), 2.0, 4.5, True),
        _door(1, ("living", "bedroom"), 5.2, 4.5, True),
        _door(2, ("living", "study"), 9.5, 4.5, True),
        _door(3, ("kitchen", "bedroom"), 4.0, 6.5, False, 0.8),
    )
    # a chair's back is on its local +y side: FACE_SOUTH puts the back north
    furniture = (
        # living room: sofa corner, shelves and TV cabinet on the north wall, dining table
        against_wall("sofa", 0, living, SOUTH, 3.0),
        make_furniture("table", 0, 3.05, 1.55, 0.0, (1.0, 0.5, 0.42)),
        make_furniture("chair", 0, 1.4, 1.5, FACE_EAST),
        against_wall("shelf", 0, living, NORTH, 3.55),
        against_wall("cabinet", 0, living, NORTH, 7.25, (1.6, 0.45, 0.5)),
        against_wall("shelf", 1, living, EAST, 0.8),
        make_furniture("table", 1, 8.6, 1.3, 0.0, (1.4, 0.8, 0.75)),
        make_furniture("chair", 1, 8.25, 0.6, FACE_NORTH),
        make_furniture("chair", 2, 8.95, 2.0, FACE_SOUTH),
        # kitchen: counter along the west wall, a wall cabinet, a small table
        against_wall("cabinet", 1, kitchen, WEST, 1.9, (2.4, 0.6, 0.9)),
        against_wall("cabinet", 2, kitchen, NORTH, 1.8, (1.2, 0.6, 0.9)),
        make_furniture("table", 2, 2.4, 6.0, 0.0, (1.0, 0.7, 0.75)),
        make_furniture("chair", 3, 3.2, 6.0, FACE_WEST),
        # bedroom
        against_wall("bed", 0, bedroom, NORTH, 2.4),
        against_wall("cabinet", 3, bedroom, EAST, 1.0, (1.0, 0.6, 2.0)),
        against_wall("shelf", 2, bedroom, WEST, 2.85),
        # study
        against_wall("table", 3, study, NORTH, 1.0, (1.2, 0.6, 0.75)),
        make_furniture("chair", 4, 9.05, 6.8, FACE_NORTH),
        against_wall("shelf", 3, study, EAST, 1.5),
        against_wall("cabinet", 4, study, WEST, 0.9, (0.8, 0.45, 0.75)),
    )
    return assemble_house("house1", None, 2.5, (living, kitchen, bedroom, study), doors, furniture)


def _house2() -> House:
    living = Room("living", 0.0, 0.0, 6.0, 4.2)
    dining = Room("dining", 6.0, 0.0, 10.0, 4.2)
    kitchen = Room("kitchen", 10.0, 0.0, 14.0, 4.2)
    corridor = Room("corridor", 0.0, 4.2, 14.0, 5.6)
    bedroom_1 = Room("bedroom_1", 0.0, 5.6, 4.5, 10.0)
    bath = Room("bath", 4.5, 5.6, 7.0, 10.0)
    bedroom_2 = Room("bedroom_2", 7.0, 5.6, 11.0, 10.0)
    office = Room("office", 11.0, 5.6, 14.0, 10.0)
    doors = (
        _door(0, ("corridor", "living"), 4.8, 4.2, True),
        _door(1, ("corridor", "dining"), 8.8, 4.2, True),
        _door(2, ("corridor", "kitchen"), 12.6, 4.2, True),
        _door(3, ("corridor", "bedroom_1"), 3.6, 5.6, True),
        _door(4, ("corridor", "bath"), 5.75, 5.6, True, 0.8),
        _door(5, ("corridor", "bedroom_2"), 8.0, 5.6, True),
        _door(6, ("corridor", "office"), 12.0, 5.6, True),
        _door(7, ("living", "dining"), 6.0, 2.0, False, 1.0),
        _door(8, ("dining", "kitchen"), 10.0, 1.5, False),
    )
    furniture = (
        # living room
        against_wall("sofa", 0, living, WEST, 2.0),
        make_furniture("table", 0, 1.7, 2.05, math.pi / 2, (1.0, 0.5, 0.42)),
        make_furniture("chair", 0, 1.5, 0.6, FACE_NORTH),
        make_furniture("chair", 1, 1.5, 3.5, FACE_SOUTH),
        against_wall("cabinet", 0, living, SOUTH, 4.0, (1.4, 0.45, 0.5)),
        against_wall("shelf", 0, living, NORTH, 1.0),
        against_wall("shelf", 1, living, EAST, 3.4),
        # dining room
        make_furniture("table", 1, 8.0, 2.0, 0.0, (1.6, 0.9, 0.75)),
        make_furniture("chair", 2, 7.6, 1.1, FACE_NORTH),
        make_furniture("chair", 3, 8.4, 1.1, FACE_NORTH),
        make_furniture("chair", 4, 7.6, 2.9, FACE_SOUTH),
        make_furniture("chair", 5, 8.4, 2.9, FACE_SOUTH),
        against_wall("cabinet", 1, dining, SOUTH, 1.0),
        against_wall("shelf", 2, dining, EAST, 3.2),
        # kitchen
        against_wall("cabinet", 2, kitchen, SOUTH, 2.4, (2.6, 0.6, 0.9)),
        against_wall("cabinet", 3, kitchen, EAST, 2.0, (1.8, 0.6, 0.9)),
        make_furniture("table", 2, 11.6, 2.6, 0.0, (0.9, 0.7, 0.75)),
        make_furniture("chair", 6, 11.6, 1.75, FACE_NORTH),
        # bedroom 1
        against_wall("bed", 0, bedroom_1, NORTH, 1.5),
        against_wall("cabinet", 4, bedroom_1, WEST, 1.0, (1.0, 0.6, 2.0)),
        against_wall("table", 3, bedroom_1, EAST, 3.3, (1.0, 0.55, 0.75)),
        make_furniture("chair", 7, 3.4, 8.95, FACE_EAST),
        # bathroom
        against_wall("cabinet", 5, bath, NORTH, 1.2, (1.0, 0.5, 0.85)),
        against_wall("shelf", 3, bath, EAST, 2.5, (0.6, 0.3, 1.6)),
        # bedroom 2
        against_wall("bed", 1, bedroom_2, NORTH, 2.6),
        against_wall("cabinet", 6, bedroom_2, WEST, 2.6, (1.2, 0.6, 2.0)),
        against_wall("shelf", 4, bedroom_2, EAST, 0.9),
        # office
        against_wall("table", 4, office, NORTH, 0.9, (1.2, 0.6, 0.75)),
        against_wall("table", 5, office, EAST, 2.2, (1.2, 0.6, 0.75)),
        make_furniture("chair", 8, 11.95, 8.8, FACE_NORTH),
        make_furniture("chair", 9, 12.9, 7.85, FACE_EAST),
        against_wall("shelf", 5, office, WEST, 2.0),
    )
    rooms = (living, dining, kitchen, corridor, bedroom_1, bath, bedroom_2, office)
    return assemble_house("house2", None, 2.6, rooms, doors, furniture)


NAMED_HOUSES = {"house1": _house1, "house2": _house2, **EXTRA_LAYOUTS}


@functools.cache
def make_house(name: str) -> House:
    """One of the fixed named layouts with its extras (built once, then shared: a House
    is immutable).

    Args:
        name: a key of :data:`NAMED_HOUSES` (``house1``, ``house2``, ``basement``,
            ``attic``).

    Raises:
        ValueError: for any other name.
    """
    return with_extras(plain_house(name), named_house_extras(name))


@functools.cache
def plain_house(name: str) -> House:
    """A named layout without its extras.

    Raises:
        ValueError: for an unknown name.
    """
    if name not in NAMED_HOUSES:
        raise ValueError(f"house: expected one of {sorted(NAMED_HOUSES)}, got {name!r}")
    return NAMED_HOUSES[name]()


def named_house_extras(name: str) -> HouseExtras:
    """The extras of a named layout (none for a layout without)."""
    return NAMED_EXTRAS.get(name, HouseExtras())
