"""Reading a scenario's environment tables, with errors that name the file and the key.

The keys (all optional; see ``docs/envelope.md``):

.. code-block:: toml

    [ceiling]
    height_m = 2.05
    [[floor_features]]       # threshold | ramp | rug | cable, on the robot's path
    kind = "threshold"
    ahead_m = 1.5
    height_m = 0.02
    [[people]]               # waypoints ahead of / left of the robot's start pose
    waypoints = [[3.0, -2.0], [3.0, 2.0]]
    speed_mps = 1.2
    [[pets]], [[doors]], [[light_furniture]], [[attic_slopes]], [[staircases]], [[wall_shelves]]
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

from twsb_sim.config_errors import ConfigError, apply_overrides
from twsb_sim.environment.specs import (
    AtticSlopeSpec,
    CeilingSpec,
    DoorSpec,
    FloorFeatureSpec,
    LightFurnitureSpec,
    PersonSpec,
    PetSpec,
    StaircaseSpec,
    WallShelfSpec,
)

_ROWS: dict[str, Any] = {
    "floor_features": FloorFeatureSpec,
    "attic_slopes": AtticSlopeSpec,
    "staircases": StaircaseSpec,
    "wall_shelves": WallShelfSpec,
    "people": PersonSpec,
    "pets": PetSpec,
    "doors": DoorSpec,
    "light_furniture": LightFurnitureSpec,
}
ENVIRONMENT_KEYS: tuple[str, ...] = ("ceiling", *_ROWS)
_PLACED = (FloorFeatureSpec, LightFurnitureSpec)
_WALKERS = (PersonSpec, PetSpec)
_NAMED = {AtticSlopeSpec: "room", StaircaseSpec: "room", WallShelfSpec: "room", DoorSpec: "doorway"}
_WAYPOINTS = ((0.0, 0.0), (1.0, 0.0))  # stands in until the row's own are applied


@dataclasses.dataclass(frozen=True)
class Environment:
    """Everything a scenario adds to its house (empty by default)."""

    ceiling: CeilingSpec = dataclasses.field(default_factory=CeilingSpec)
    floor_features: tuple[FloorFeatureSpec, ...] = ()
    attic_slopes: tuple[AtticSlopeSpec, ...] = ()
    staircases: tuple[StaircaseSpec, ...] = ()
    wall_shelves: tuple[WallShelfSpec, ...] = ()
    people: tuple[PersonSpec, ...] = ()
    pets: tuple[PetSpec, ...] = ()
    doors: tuple[DoorSpec, ...] = ()
    light_furniture: tuple[LightFurnitureSpec, ...] = ()

    def __bool__(self) -> bool:
        return self.ceiling.height_m is not None or any(getattr(self, key) for key in _ROWS)


def _row(spec_type: Any, row: dict[str, Any], source: str | Path, where: str) -> Any:
    """One row on top of a stand-in instance of its type."""
    if spec_type in _PLACED:
        if ("ahead_m" in row) == ("at_m" in row):
            raise ConfigError(source, f"{where}.ahead_m", "give exactly one of ahead_m or at_m")
        base = spec_type(ahead_m=0.0) if "ahead_m" in row else spec_type(at_m=(0.0, 0.0))
    elif spec_type in _WALKERS:
        if "waypoints" not in row:
            raise ConfigError(source, f"{where}.waypoints", "missing: at least two [x, y] points")
        base = spec_type(waypoints=_WAYPOINTS)
    else:
        base = spec_type()
    if spec_type in _NAMED and _NAMED[spec_type] not in row:
        key = _NAMED[spec_type]
        raise ConfigError(source, f"{where}.{key}", f"missing: the {key}'s name in the house")
    return apply_overrides(base, row, source, where)


def environment_from_table(table: dict[str, Any], source: str | Path = "<table>") -> Environment:
    """The environment keys of a parsed scenario table (others are ignored).

    Raises:
        ConfigError: a wrong key, type or value, naming the file and the key
            (``people[1].speed_mps``).
    """
    values: dict[str, Any] = {}
    if "ceiling" in table:
        values["ceiling"] = apply_overrides(CeilingSpec(), table["ceiling"], source, "ceiling")
    for key, spec_type in _ROWS.items():
        if key not in table:
            continue
        rows = table[key]
        if not isinstance(rows, list) or not all(isinstance(r, dict) for r in rows):
            raise ConfigError(source, key, f"expected an array of tables ([[{key}]]), got {rows!r}")
        values[key] = tuple(_row(spec_type, r, source, f"{key}[{i}]") for i, r in enumerate(rows))
    return Environment(**values)
