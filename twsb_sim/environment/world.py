"""From a scenario's environment to what the simulation builds: house extras and movers.

Placements relative to the robot's start pose (``ahead_m``, ``frame = "start"``) are
turned into world coordinates here, once the house and the start pose are known.
"""

from __future__ import annotations

import math
from pathlib import Path

from twsb_sim.config_errors import ConfigError
from twsb_sim.environment.loader import Environment
from twsb_sim.environment.specs import Placement, WalkerSpec
from twsb_sim.house.ceilings import AtticSlope, Staircase
from twsb_sim.house.extras import HouseExtras, WallShelf
from twsb_sim.house.floor_features import FloorFeature
from twsb_sim.house.model import House
from twsb_sim.movers import LightFurniture, MoverSet, Person, Pet, SwingingDoor, WalkPath

Pose = tuple[float, float, float]  # x m, y m, yaw rad


def _place(placement: Placement, start: Pose) -> tuple[float, float, float]:
    """World (x, y, yaw) of a placement."""
    if placement.at_m is not None:
        return placement.at_m[0], placement.at_m[1], math.radians(placement.yaw_deg)
    x0, y0, yaw0 = start
    c, s = math.cos(yaw0), math.sin(yaw0)
    ahead, left = placement.ahead_m, placement.lateral_m
    return (
        x0 + c * ahead - s * left,
        y0 + s * ahead + c * left,
        yaw0 + math.radians(placement.yaw_deg),
    )


def _path(spec: WalkerSpec, start: Pose) -> WalkPath:
    points = spec.waypoints
    if spec.frame == "start":
        x0, y0, yaw0 = start
        c, s = math.cos(yaw0), math.sin(yaw0)
        points = tuple((x0 + c * a - s * b, y0 + s * a + c * b) for a, b in points)
    return WalkPath(points, spec.speed_mps, spec.start_s, spec.stand_s, spec.back_and_forth)


def house_extras(environment: Environment, start: Pose) -> HouseExtras:
    """The scenario's additions to its house, in world coordinates."""
    features = []
    for spec in environment.floor_features:
        x, y, yaw = _place(spec, start)
        features.append(
            FloorFeature(
                spec.kind,
                x,
                y,
                yaw,
                spec.height_m,
                spec.length_m,
                spec.width_m,
                spec.slope_deg,
                spec.friction,
            )
        )
    return HouseExtras(
        ceiling_height_m=environment.ceiling.height_m,
        floor_features=tuple(features),
        attic_slopes=tuple(
            AtticSlope(s.room, s.side, s.knee_height_m, s.pitch_deg)
            for s in environment.attic_slopes
        ),
        staircases=tuple(
            Staircase(s.room, s.side, s.start_m, s.width_m, s.rising_east_or_north)
            for s in environment.staircases
        ),
        wall_shelves=tuple(
            WallShelf(s.room, s.side, s.offset_m, s.width_m, s.depth_m, s.height_m)
            for s in environment.wall_shelves
        ),
    )


def check_rooms(environment: Environment, house: House, source: str | Path) -> None:
    """Every room and doorway the environment names exists in ``house``."""
    rooms = {r.name for r in house.rooms}
    for key in ("attic_slopes", "staircases", "wall_shelves"):
        for i, spec in enumerate(getattr(environment, key)):
            if spec.room not in rooms:
                known = ", ".join(sorted(rooms))
                message = f"{house.name} has no room {spec.room!r} (rooms: {known})"
                raise ConfigError(source, f"{key}[{i}].room", message)
    doorways = {d.name for d in house.doorways}
    for i, spec in enumerate(environment.doors):
        if spec.doorway not in doorways:
            known = ", ".join(sorted(doorways))
            message = f"{house.name} has no doorway {spec.doorway!r} (doorways: {known})"
            raise ConfigError(source, f"doors[{i}].doorway", message)


def movers(environment: Environment, house: House, start: Pose) -> MoverSet:
    """The scenario's people, pets, doors and light furniture."""
    found: list = [
        Person(f"person_{k}", _path(spec, start), spec.height_m)
        for k, spec in enumerate(environment.people)
    ]
    found += [
        Pet(f"pet_{k}", _path(spec, start), spec.shoulder_height_m)
        for k, spec in enumerate(environment.pets)
    ]
    doorways = {d.name: d for d in house.doorways}
    found += [
        SwingingDoor(
            f"door_leaf_{k}",
            doorways[spec.doorway],
            spec.hinge_at_low_end,
            spec.opens_positive,
            spec.open_deg,
            spec.start_open,
            spec.toggle_times_s,
            spec.swing_s,
        )
        for k, spec in enumerate(environment.doors)
    ]
    for k, spec in enumerate(environment.light_furniture):
        x, y, yaw = _place(spec, start)
        found.append(
            LightFurniture(f"pushable_{k}", spec.kind, x, y, yaw, spec.mass_kg, spec.size_m)
        )
    return MoverSet(found)
