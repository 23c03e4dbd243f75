"""The extras of the named layouts, and two layouts under low ceilings.

house1 and house2 get thresholds in their doorways, rugs and a cable (house2 a small
ramp between living and dining room), all off the lanes of the shipped sequences
(house1's living-room lane at y = 2.6 m, house2's corridor at y = 4.8 m), so those runs see
the same pitch variations as before; drives through doorways cross them.

``basement`` (15 m x 8 m, ceiling 2.05 m): a long open basement with a staircase along its
south wall, its soffit open underneath, storage shelves, a laundry and a workshop; the
lane along y = 2.8 m is ~11 m long. ``attic`` (14 m x 5 m, flat ceiling 2.6 m): a long
room and a bedroom under a roof pitched at 45 deg, knee walls 1.0 m high on both long
sides, wall shelves; the lane along y = 2.5 m runs under the flat part.
"""

from __future__ import annotations

import math

from twsb_sim.house.ceilings import AtticSlope, Staircase
from twsb_sim.house.extras import HouseExtras, WallShelf
from twsb_sim.house.floor_features import FloorFeature
from twsb_sim.house.floorplan import assemble_house
from twsb_sim.house.furniture import make_furniture
from twsb_sim.house.model import Doorway, House, Room
from twsb_sim.house.placement import against_wall

ACROSS_Y = math.pi / 2  # a feature crossed along y (in a wall that runs along x)
BASEMENT_DOOR_HEIGHT_M = 1.9  # m
ATTIC_DOOR_HEIGHT_M = 2.0  # m


def _threshold(door: tuple[float, float, bool, float], height_m: float) -> FloorFeature:
    x, y, along_x, width = door
    yaw = ACROSS_Y if along_x else 0.0
    return FloorFeature("threshold", x, y, yaw, height_m, width, width_m=0.08, slope_deg=30.0)


HOUSE1_EXTRAS = HouseExtras(
    floor_features=(
        _threshold((2.0, 4.5, True, 0.9), 0.015),
        _threshold((5.2, 4.5, True, 0.9), 0.02),
        _threshold((9.5, 4.5, True, 0.9), 0.01),
        _threshold((4.0, 6.5, False, 0.8), 0.025),
        FloorFeature("rug", 3.05, 1.55, 0.0, 0.012, 1.3, 2.2),  # under the coffee table
        FloorFeature("rug", 6.0, 5.55, 0.0, 0.015, 1.0, 2.0),  # at the foot of the bed
        FloorFeature("cable", 9.25, 5.3, ACROSS_Y, 0.012, 1.5),  # across the study
    )
)
HOUSE2_DOORS = (  # x, y, clear width, threshold height (m): the corridor's doorways
    (4.8, 4.2, 0.9, 0.015),
    (8.8, 4.2, 0.9, 0.02),
    (12.6, 4.2, 0.9, 0.01),
    (3.6, 5.6, 0.9, 0.02),
    (5.75, 5.6, 0.8, 0.03),
    (8.0, 5.6, 0.9, 0.015),
    (12.0, 5.6, 0.9, 0.02),
)
HOUSE2_EXTRAS = HouseExtras(
    floor_features=(
        *(_threshold((x, y, True, w), h) for x, y, w, h in HOUSE2_DOORS),
        FloorFeature("ramp", 6.0, 2.0, 0.0, 0.04, 1.0, width_m=0.2, slope_deg=7.0),
        FloorFeature("rug", 1.9, 2.05, 0.0, 0.01, 2.0, 1.6),
        FloorFeature("rug", 9.0, 7.0, 0.0, 0.015, 1.2, 1.8),
    )
)


def basement() -> House:
    """The plain basement layout (its stairs and shelves are extras)."""
    main = Room("basement", 0.0, 0.0, 15.0, 5.0)
    laundry = Room("laundry", 0.0, 5.0, 5.0, 8.0)
    workshop = Room("workshop", 5.0, 5.0, 15.0, 8.0)
    doors = (
        Doorway("door_0", ("basement", "laundry"), 2.5, 5.0, True, 0.9, BASEMENT_DOOR_HEIGHT_M),
        Doorway("door_1", ("basement", "workshop"), 10.0, 5.0, True, 0.9, BASEMENT_DOOR_HEIGHT_M),
    )
    furniture = (
        against_wall("shelf", 0, main, "west", 2.5, (1.2, 0.4, 1.9)),
        against_wall("shelf", 1, main, "north", 6.0, (1.2, 0.4, 1.9)),
        against_wall("sofa", 0, main, "north", 12.5, (2.0, 0.9, 0.85)),
        make_furniture("table", 0, 12.5, 2.6, 0.0, (1.0, 0.5, 0.42)),
        against_wall("cabinet", 0, laundry, "north", 2.5, (2.4, 0.6, 0.9)),
        against_wall("shelf", 2, laundry, "west", 1.5, (0.9, 0.35, 1.8)),
        against_wall("table", 1, workshop, "north", 3.0, (2.0, 0.7, 0.9)),
        make_furniture("chair", 0, 7.9, 6.4, math.pi),
        against_wall("cabinet", 1, workshop, "east", 1.5, (1.2, 0.5, 0.9)),
        against_wall("shelf", 3, workshop, "north", 7.0, (1.2, 0.4, 1.9)),
    )
    return assemble_house("basement", None, 2.05, (main, laundry, workshop), doors, furniture)


BASEMENT_EXTRAS = HouseExtras(
    staircases=(Staircase("basement", "south", 7.5, 0.9, True),),
    wall_shelves=(
        WallShelf("basement", "north", 9.0, 1.2, 0.3, 0.9),
        WallShelf("basement", "north", 9.0, 1.2, 0.3, 1.35),
        WallShelf("workshop", "south", 6.0, 1.0, 0.25, 1.1),
    ),
    floor_features=(
        FloorFeature("cable", 4.0, 2.8, 0.0, 0.015, 2.0),  # across the lane
        FloorFeature("rug", 12.5, 2.6, 0.0, 0.015, 2.0, 2.2),
        _threshold((2.5, 5.0, True, 0.9), 0.02),
        _threshold((10.0, 5.0, True, 0.9), 0.02),
    ),
)


def attic() -> House:
    """The plain attic layout (its sloped ceilings are extras)."""
    main = Room("attic", 0.0, 0.0, 10.0, 5.0)
    bedroom = Room("bedroom", 10.0, 0.0, 14.0, 5.0)
    doors = (Doorway("door_0", ("attic", "bedroom"), 10.0, 2.5, False, 0.9, ATTIC_DOOR_HEIGHT_M),)
    furniture = (
        against_wall("cabinet", 0, main, "north", 2.0, (1.6, 0.45, 0.6)),
        against_wall("cabinet", 1, main, "south", 7.0, (1.6, 0.45, 0.6)),
        against_wall("sofa", 0, main, "south", 2.5, (2.0, 0.9, 0.8)),
        make_furniture("table", 0, 2.5, 1.3, 0.0, (1.0, 0.5, 0.42)),
        against_wall("shelf", 0, main, "west", 1.0, (0.8, 0.35, 0.9)),
        make_furniture("table", 1, 7.0, 3.9, 0.0, (1.2, 0.7, 0.74)),
        make_furniture("chair", 0, 6.6, 3.35, 0.0),
        make_furniture("chair", 1, 7.4, 3.35, 0.0),
        against_wall("bed", 0, bedroom, "east", 2.5, (1.4, 2.0, 0.5)),
        against_wall("cabinet", 2, bedroom, "north", 1.6, (1.2, 0.5, 0.7)),
    )
    return assemble_house("attic", None, 2.6, (main, bedroom), doors, furniture)


ATTIC_EXTRAS = HouseExtras(
    attic_slopes=tuple(
        AtticSlope(room, side, 1.0, 45.0)
        for room in ("attic", "bedroom")
        for side in ("north", "south")
    ),
    wall_shelves=(WallShelf("attic", "east", 1.2, 1.0, 0.25, 0.75),),
    floor_features=(
        FloorFeature("rug", 4.5, 2.5, 0.0, 0.015, 1.6, 2.4),  # across the lane
        _threshold((10.0, 2.5, False, 0.9), 0.02),
    ),
)

EXTRA_LAYOUTS = {"basement": basement, "attic": attic}
NAMED_EXTRAS = {
    "house1": HOUSE1_EXTRAS,
    "house2": HOUSE2_EXTRAS,
    "basement": BASEMENT_EXTRAS,
    "attic": ATTIC_EXTRAS,
}
