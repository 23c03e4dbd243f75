"""What a scenario file adds to its house, as written: floor features, ceilings, movers.

Each dataclass is one row of a scenario table (``[[floor_features]]``, ``[[people]]``, ...),
with defaults in code and units in comments; placements may be relative to the robot's
start pose (``ahead_m``, ``frame = "start"``), so one scenario works in any house.
:mod:`twsb_sim.environment.world` turns them into house extras and movers once the house
and the start pose are known.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from twsb_sim.house.ceilings import AtticSlope, Staircase
from twsb_sim.house.extras import WallShelf
from twsb_sim.house.floor_features import FloorFeature
from twsb_sim.house.model import Doorway
from twsb_sim.movers import LightFurniture, SwingingDoor

# where the rows' own checks build a stand-in: a doorway for a door's swing
_STAND_IN_DOORWAY = Doorway("door_0", ("a", "b"), 0.0, 0.0, True, 0.9, 2.0)
Frame = Literal["start", "world"]


def _positive(name: str, value: float, low: float, high: float, unit: str) -> None:
    if not low <= value <= high:
        raise ValueError(f"{name}: expected {low:g} to {high:g} {unit}, got {value:g}")


@dataclass(frozen=True)
class Placement:
    """Where a thing is: on the robot's path (``ahead_m``), or at a world point (``at_m``).

    With ``ahead_m`` the centre is that far along the start heading from the start pose and
    ``lateral_m`` to its left, and ``yaw_deg`` turns the thing from the start heading; with
    ``at_m`` the centre is that world point and ``yaw_deg`` is its world heading.
    """

    ahead_m: float | None = None  # m, along the robot's start heading
    lateral_m: float = 0.0  # m, to the left of the path (with ahead_m)
    at_m: tuple[float, float] | None = None  # m, world x and y
    yaw_deg: float = 0.0  # deg

    def __post_init__(self) -> None:
        if (self.ahead_m is None) == (self.at_m is None):
            raise ValueError("ahead_m: give exactly one of ahead_m or at_m")
        if self.ahead_m is not None:
            _positive("ahead_m", self.ahead_m, -50.0, 50.0, "m")


@dataclass(frozen=True)
class FloorFeatureSpec(Placement):
    """A ``[[floor_features]]`` row; crossing direction = the placement's heading."""

    kind: Literal["threshold", "ramp", "rug", "cable"] = "threshold"
    height_m: float = 0.02  # m, top above the floor (a cable's diameter)
    length_m: float = 1.0  # m, across the path
    width_m: float = 0.08  # m, along the path: flat top of a threshold or ramp, a rug's depth
    slope_deg: float = 30.0  # deg, bevels of a threshold, slopes of a ramp
    friction: tuple[float, float, float] | None = None  # a rug's sliding, torsional, rolling

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.friction is not None and not all(0.0 <= f <= 5.0 for f in self.friction):
            raise ValueError(
                f"friction: expected coefficients of 0 to 5, got {list(self.friction)}"
            )
        FloorFeature(self.kind, 0.0, 0.0, 0.0, self.height_m, self.length_m, self.width_m,
                     self.slope_deg)  # fmt: skip


@dataclass(frozen=True)
class CeilingSpec:
    """The ``[ceiling]`` table."""

    height_m: float | None = None  # m, replaces the house's ceiling height

    def __post_init__(self) -> None:
        if self.height_m is not None:
            _positive("height_m", self.height_m, 1.9, 4.0, "m")


@dataclass(frozen=True)
class AtticSlopeSpec:
    """An ``[[attic_slopes]]`` row: a sloped ceiling along one wall of a room."""

    room: str = ""
    side: Literal["north", "south", "east", "west"] = "north"
    knee_height_m: float = 1.2  # m
    pitch_deg: float = 40.0  # deg

    def __post_init__(self) -> None:
        AtticSlope(self.room, self.side, self.knee_height_m, self.pitch_deg)


@dataclass(frozen=True)
class StaircaseSpec:
    """A ``[[staircases]]`` row: a flight along one wall of a room, open underneath."""

    room: str = ""
    side: Literal["north", "south", "east", "west"] = "north"
    start_m: float = 0.3  # m, its foot along the wall from the wall's west or south end
    width_m: float = 0.9  # m
    rising_east_or_north: bool = True

    def __post_init__(self) -> None:
        Staircase(self.room, self.side, self.start_m, self.width_m, self.rising_east_or_north)


@dataclass(frozen=True)
class WallShelfSpec:
    """A ``[[wall_shelves]]`` row: a board on a wall with nothing under it."""

    room: str = ""
    side: Literal["north", "south", "east", "west"] = "north"
    offset_m: float = 1.0  # m, its centre along the wall
    width_m: float = 0.9  # m
    depth_m: float = 0.25  # m
    height_m: float = 0.8  # m, its top above the floor

    def __post_init__(self) -> None:
        for name in ("width_m", "depth_m"):
            _positive(name, getattr(self, name), 0.05, 5.0, "m")
        WallShelf(self.room, self.side, self.offset_m, self.width_m, self.depth_m, self.height_m)


@dataclass(frozen=True)
class WalkerSpec:
    """The path of a ``[[people]]`` or ``[[pets]]`` row."""

    waypoints: tuple[tuple[float, float], ...] = ()  # m, at least two points
    frame: Frame = "start"  # start: x ahead of the robot's start pose, y to its left
    speed_mps: float = 1.2  # m/s
    start_s: float = 0.0  # s, stands at the first waypoint until then
    stand_s: float = 0.0  # s, stands (and turns) at every waypoint it reaches
    back_and_forth: bool = True  # walks the path back again, forever

    def __post_init__(self) -> None:
        if len(self.waypoints) < 2:
            raise ValueError(
                f"waypoints: expected at least two [x, y] points, got {len(self.waypoints)}"
            )
        _positive("speed_mps", self.speed_mps, 0.05, 5.0, "m/s")
        _positive("start_s", self.start_s, 0.0, 3600.0, "s")
        _positive("stand_s", self.stand_s, 0.0, 600.0, "s")


@dataclass(frozen=True)
class PersonSpec(WalkerSpec):
    """A ``[[people]]`` row."""

    height_m: float = 1.75  # m

    def __post_init__(self) -> None:
        super().__post_init__()
        _positive("height_m", self.height_m, 1.0, 2.2, "m")


@dataclass(frozen=True)
class PetSpec(WalkerSpec):
    """A ``[[pets]]`` row."""

    shoulder_height_m: float = 0.4  # m

    def __post_init__(self) -> None:
        super().__post_init__()
        _positive("shoulder_height_m", self.shoulder_height_m, 0.15, 0.8, "m")


@dataclass(frozen=True)
class DoorSpec:
    """A ``[[doors]]`` row: a leaf in one of the house's doorways."""

    doorway: str = ""  # the doorway's name, door_<k>
    hinge_at_low_end: bool = True  # hinge at the opening's end of lower x (or y)
    opens_positive: bool = True  # opens towards +y (walls along x) or +x
    open_deg: float = 90.0  # deg
    start_open: bool = False
    toggle_times_s: tuple[float, ...] = ()  # s, when it starts to swing to the other state
    swing_s: float = 1.5  # s

    def __post_init__(self) -> None:
        SwingingDoor("door_leaf_0", _STAND_IN_DOORWAY, self.hinge_at_low_end,
                     self.opens_positive, self.open_deg, self.start_open, self.toggle_times_s,
                     self.swing_s)  # fmt: skip


@dataclass(frozen=True)
class LightFurnitureSpec(Placement):
    """A ``[[light_furniture]]`` row: a piece the robot can bump into and push."""

    kind: Literal["box", "stool"] = "box"
    mass_kg: float = 3.0  # kg
    size_m: tuple[float, float, float] = (0.45, 0.35, 0.3)  # m: width, depth, height

    def __post_init__(self) -> None:
        super().__post_init__()
        LightFurniture("pushable_0", self.kind, 0.0, 0.0, 0.0, self.mass_kg, self.size_m)
