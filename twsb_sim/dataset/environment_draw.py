"""An episode's surroundings and robot class, drawn as scenario-file tables.

Everything is placed relative to the episode's start pose and lane (``ahead_m`` along the
lane, waypoints in the start frame: x along the lane, y to its left), in free floor space
of the house: floor features across the lane, people crossing the robot's view or walking
beside the lane, a pet roaming the start room, door leaves in that room's doorways, a
light piece of furniture on the lane ahead. The draws come from the episode's own
environment stream, so they leave its house, robot and motion as they were.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from twsb_sim.dataset.environment_ranges import CeilingRanges, FloorRanges, MoverRanges
from twsb_sim.dataset.motion import Lane
from twsb_sim.dataset.ranges_checks import Range
from twsb_sim.house import House
from twsb_sim.house.spawn import Obstacles
from twsb_sim.robot_classes import draw_class_tables

PERSON_RADIUS_M = 0.3  # m, kept free around a walker's path
MARCH_STEP_M = 0.1  # m, resolution of the free-space search
MAX_REACH_M = 6.0  # m, how far a path reaches from the lane
MIN_PATH_M = 1.2  # m, shorter free paths are not walked
TRIES = 10
Pose = tuple[float, float, float]  # x m, y m, yaw rad


def _u(rng: np.random.Generator, bounds: Range, digits: int = 3) -> float:
    low, high = bounds
    return round(float(rng.uniform(low, high)) if high > low else float(low), digits)


def _count(rng: np.random.Generator, bounds: Range) -> int:
    return int(rng.integers(math.floor(bounds[0]), math.floor(bounds[1]) + 1))


class _Space:
    """Free floor around the start pose, in the start frame (x along the lane)."""

    def __init__(self, house: House, start: Pose) -> None:
        self.obstacles = Obstacles(house.parts())
        self.start = start

    def world(self, a: float, b: float) -> np.ndarray:
        x0, y0, yaw = self.start
        c, s = math.cos(yaw), math.sin(yaw)
        return np.array([x0 + c * a - s * b, y0 + s * a + c * b])

    def free(self, a: float, b: float, radius_m: float = PERSON_RADIUS_M) -> bool:
        return bool(self.obstacles.is_free(self.world(a, b)[None, :], radius_m)[0])

    def reach(self, a: float, b: float, da: float, db: float) -> float:
        """How far one can walk from (a, b) along (da, db) in free space (m)."""
        walked = 0.0
        while walked < MAX_REACH_M and self.free(a + da * (walked + MARCH_STEP_M),
                                                 b + db * (walked + MARCH_STEP_M)):  # fmt: skip
            walked += MARCH_STEP_M
        return walked


def floor_features(rng: np.random.Generator, lane: Lane, r: FloorRanges) -> list[dict]:
    """Features across the lane, at least 0.4 m from the start (under the robot)."""
    if rng.random() >= r.probability or lane.ahead_m + lane.behind_m < 0.8:
        return []
    kinds = list(r.weights())
    weights = np.array(list(r.weights().values()))
    rows = []
    for _ in range(_count(rng, r.count)):
        kind = kinds[int(rng.choice(len(kinds), p=weights / weights.sum()))]
        ahead = _u(rng, (-lane.behind_m, lane.ahead_m))
        if abs(ahead) < 0.4:
            ahead = math.copysign(0.4, ahead if ahead else 1.0)
        row: dict[str, Any] = {"kind": kind, "ahead_m": ahead, "length_m": _u(rng, (0.8, 1.4))}
        if kind == "threshold":
            row |= {"height_m": _u(rng, r.threshold_height_m, 4), "width_m": _u(rng, (0.05, 0.12)),
                    "slope_deg": _u(rng, (25.0, 35.0), 1)}  # fmt: skip
        elif kind == "ramp":
            row |= {"height_m": _u(rng, r.ramp_height_m, 4), "width_m": _u(rng, (0.2, 0.6)),
                    "slope_deg": _u(rng, r.ramp_slope_deg, 1)}  # fmt: skip
        elif kind == "rug":
            row |= {"height_m": _u(rng, r.rug_height_m, 4), "width_m": _u(rng, (0.8, 2.0)),
                    "friction": [_u(rng, r.rug_friction, 2), 0.02, 0.002]}  # fmt: skip
        else:
            row |= {"height_m": _u(rng, r.cable_height_m, 4)}
        rows.append(row)
    return rows


def _walk_path(rng: np.random.Generator, space: _Space, lane: Lane) -> list[list[float]] | None:
    """Across the lane at some distance ahead, or along it beside the robot."""
    for _ in range(TRIES):
        if rng.random() < 0.6:  # across the view
            a = _u(rng, (1.0, max(1.5, lane.ahead_m + 1.5)))
            if not space.free(a, 0.0):
                continue
            left, right = space.reach(a, 0.0, 0.0, 1.0), space.reach(a, 0.0, 0.0, -1.0)
            if left + right >= MIN_PATH_M:
                ends = [[a, round(left, 2)], [a, round(-right, 2)]]
                return ends if rng.random() < 0.5 else ends[::-1]
        else:  # beside the lane, towards the robot or away
            b = _u(rng, (0.8, 1.6)) * (1 if rng.random() < 0.5 else -1)
            a = _u(rng, (0.5, max(1.0, lane.ahead_m)))
            if not space.free(a, b):
                continue
            back, on = space.reach(a, b, -1.0, 0.0), space.reach(a, b, 1.0, 0.0)
            if back + on >= MIN_PATH_M:
                ends = [[round(a - back, 2), b], [round(a + on, 2), b]]
                return ends if rng.random() < 0.5 else ends[::-1]
    return None


def movers(
    rng: np.random.Generator, house: House, start: Pose, lane: Lane, r: MoverRanges,
    duration_s: float,
) -> dict[str, list[dict]]:  # fmt: skip
    """People, a pet, doors and light furniture, as scenario rows (empty lists: none)."""
    space = _Space(house, start)
    tables: dict[str, list[dict]] = {"people": [], "pets": [], "doors": [], "light_furniture": []}
    if rng.random() < r.people_probability:
        for _ in range(_count(rng, r.people)):
            path = _walk_path(rng, space, lane)
            if path is not None:
                tables["people"].append({
                    "waypoints": path, "speed_mps": _u(rng, r.person_speed_mps, 2),
                    "start_s": _u(rng, (0.0, 0.5 * duration_s), 1),
                    "stand_s": _u(rng, r.stand_s, 1), "height_m": _u(rng, r.person_height_m, 2),
                })  # fmt: skip
    if rng.random() < r.pet_probability:
        path = _walk_path(rng, space, lane)
        if path is not None:
            tables["pets"].append({
                "waypoints": path, "speed_mps": _u(rng, r.pet_speed_mps, 2),
                "start_s": _u(rng, (0.0, 0.5 * duration_s), 1), "stand_s": _u(rng, (0.0, 3.0), 1),
                "shoulder_height_m": _u(rng, r.pet_shoulder_height_m, 2),
            })  # fmt: skip
    if rng.random() < r.door_probability:
        tables["doors"] = _doors(rng, house, start, r, duration_s)
    if rng.random() < r.light_furniture_probability and lane.ahead_m >= 0.9:
        stool = rng.random() < 0.5
        size = [_u(rng, (0.3, 0.4), 2), 0.3, _u(rng, (0.4, 0.5), 2)] if stool else [
            _u(rng, (0.3, 0.5), 2), _u(rng, (0.25, 0.4), 2), _u(rng, (0.25, 0.4), 2)]  # fmt: skip
        tables["light_furniture"].append({
            "kind": "stool" if stool else "box", "ahead_m": _u(rng, (0.9, lane.ahead_m + 0.3), 2),
            "yaw_deg": _u(rng, (-30.0, 30.0), 1), "mass_kg": _u(rng, r.light_furniture_mass_kg, 2),
            "size_m": size,
        })  # fmt: skip
    return tables


def _doors(
    rng: np.random.Generator, house: House, start: Pose, r: MoverRanges, duration_s: float
) -> list[dict]:
    """Leaves in the doorways of the room the robot starts in, each swinging a few times."""
    rooms = [room.name for room in house.rooms if room.contains(start[0], start[1])]
    rows = []
    for door in house.doorways:
        if not set(door.rooms) & set(rooms):
            continue
        swings = sorted(_u(rng, (0.0, duration_s), 2) for _ in range(_count(rng, r.door_swings)))
        rows.append({
            "doorway": door.name, "hinge_at_low_end": bool(rng.random() < 0.5),
            "opens_positive": bool(rng.random() < 0.5), "open_deg": _u(rng, (70.0, 110.0), 1),
            "start_open": bool(rng.random() < 0.5), "toggle_times_s": swings,
            "swing_s": _u(rng, (1.0, 2.5), 2),
        })  # fmt: skip
    return rows


def ceiling(rng: np.random.Generator, r: CeilingRanges) -> dict[str, float] | None:
    """A low ceiling's table, or None to keep the house's."""
    return {"height_m": _u(rng, r.height_m, 2)} if rng.random() < r.low_probability else None


def robot_class(rng: np.random.Generator, weights: dict[str, float]) -> tuple[str, dict]:
    """A robot class by weight, and its tables for this episode."""
    names = list(weights)
    p = np.array(list(weights.values()), dtype=float)
    name = names[int(rng.choice(len(names), p=p / p.sum()))]
    return name, draw_class_tables(rng, name)
