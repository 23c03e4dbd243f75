"""Floors that tilt the robot: door thresholds, rugs and carpets, small ramps, cables.

A feature is described in its own frame: origin at its centre on the floor, local x the
direction a robot crosses it, its length across the path along local y. Its parts are
floor surfaces (named ``floor_<kind>_<k>...``, see :mod:`twsb_sim.house.surfaces`): a
tilted beam that ends on one is a FLOOR point, like one that ends on the floor itself,
unless a level scanner at the same place would have seen it too (see
:mod:`twsb_sim.level_view`). None of them blocks the robot: it drives over them.

| kind | shape | typical |
|---|---|---|
| ``threshold`` | a strip with bevelled edges | 1-3 cm high, 5-12 cm wide, 25-35 deg |
| ``ramp`` | up a slope, a flat top, down again | 3-8 cm high, slopes up to ~8 deg |
| ``rug`` | a thin slab, square edges, its own friction | 0.5-2 cm thick |
| ``cable`` | a capsule lying on the floor | 0.8-2.4 cm thick |
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from twsb_sim.house.model import Part, Rgba, Vec3

FLOOR_FEATURE_KINDS: tuple[str, ...] = ("threshold", "ramp", "rug", "cable")
SLOPE_THICKNESS_M = 0.01  # m, thickness of the slab under a slope (sunk below the floor)
FLOOR_FEATURE_GROUP = 0  # structure: shown and cast like the floor
CARPET_FRICTION: Vec3 = (1.2, 0.02, 0.002)  # sliding, torsional (m), rolling (m)

THRESHOLD_COLOUR: Rgba = (0.72, 0.62, 0.40, 1.0)
RAMP_COLOUR: Rgba = (0.45, 0.45, 0.47, 1.0)
RUG_COLOUR: Rgba = (0.55, 0.20, 0.18, 1.0)
CABLE_COLOUR: Rgba = (0.08, 0.08, 0.08, 1.0)


@dataclass(frozen=True)
class FloorFeature:
    """One feature on the floor.

    Attributes:
        kind: one of :data:`FLOOR_FEATURE_KINDS`.
        x_m, y_m: centre on the floor (m, world).
        yaw_rad: direction a robot crosses it (its local x), rad.
        height_m: top above the floor (m); a cable's diameter.
        length_m: extent across the path (m).
        width_m: extent along the path (m): a threshold's or ramp's flat top, a rug's depth;
            unused for a cable.
        slope_deg: a threshold's bevels or a ramp's slopes (deg above the floor).
        friction: a rug's (sliding, torsional m, rolling m) coefficients; None for the
            other kinds (the tyres' friction applies).
    """

    kind: str
    x_m: float
    y_m: float
    yaw_rad: float
    height_m: float
    length_m: float
    width_m: float = 0.08
    slope_deg: float = 30.0
    friction: Vec3 | None = None

    def __post_init__(self) -> None:
        if self.kind not in FLOOR_FEATURE_KINDS:
            kinds = list(FLOOR_FEATURE_KINDS)
            raise ValueError(f"kind: expected one of {kinds}, got {self.kind!r}")
        if not 0.002 <= self.height_m <= 0.2:
            raise ValueError(f"height_m: expected 0.002 to 0.2 m, got {self.height_m}")
        if not 0.05 <= self.length_m <= 20.0:
            raise ValueError(f"length_m: expected 0.05 to 20 m, got {self.length_m}")
        if not 0.0 <= self.width_m <= 20.0:
            raise ValueError(f"width_m: expected 0 to 20 m, got {self.width_m}")
        if not 1.0 <= self.slope_deg <= 60.0:
            raise ValueError(f"slope_deg: expected 1 to 60 deg, got {self.slope_deg}")

    @property
    def footprint_length_m(self) -> float:
        """Extent along the path, slopes included (m)."""
        if self.kind in ("threshold", "ramp"):
            return self.width_m + 2 * self.height_m / math.tan(math.radians(self.slope_deg))
        return self.height_m if self.kind == "cable" else self.width_m


def _to_world(feature: FloorFeature, along_m: float, z_m: float) -> Vec3:
    c, s = math.cos(feature.yaw_rad), math.sin(feature.yaw_rad)
    return (feature.x_m + c * along_m, feature.y_m + s * along_m, z_m)


def _slope(name: str, feature: FloorFeature, start_m: float, up: bool, rgba: Rgba) -> Part:
    """A thin slab whose top face rises (or falls) from the floor at ``start_m`` along the
    path to ``height_m``: a bevel or a ramp."""
    angle = math.radians(feature.slope_deg)
    run = feature.height_m / math.tan(angle)
    half_length = feature.height_m / math.sin(angle) / 2
    t = SLOPE_THICKNESS_M / 2
    # the top face's midpoint, then half a thickness down along the face's normal
    direction = 1.0 if up else -1.0
    mid_along = start_m + run / 2
    centre_along = mid_along + direction * t * math.sin(angle)
    centre_z = feature.height_m / 2 - t * math.cos(angle)
    return Part(
        name, "box", (half_length, feature.length_m / 2, t),
        _to_world(feature, centre_along, centre_z), feature.yaw_rad, rgba,
        FLOOR_FEATURE_GROUP, pitch_rad=-direction * angle, blocking=False,
    )  # fmt: skip


def _hump(prefix: str, feature: FloorFeature, rgba: Rgba) -> tuple[Part, ...]:
    """Up a slope, a flat top of ``width_m``, down a slope (thresholds and ramps)."""
    run = feature.height_m / math.tan(math.radians(feature.slope_deg))
    half_top = feature.width_m / 2
    top = Part(
        f"{prefix}_top", "box", (half_top, feature.length_m / 2, feature.height_m / 2),
        _to_world(feature, 0.0, feature.height_m / 2), feature.yaw_rad, rgba,
        FLOOR_FEATURE_GROUP, blocking=False,
    )  # fmt: skip
    up = _slope(f"{prefix}_up", feature, -half_top - run, True, rgba)
    down = _slope(f"{prefix}_down", feature, half_top, False, rgba)
    return (up, top, down) if half_top > 0 else (up, down)


def floor_feature_parts(feature: FloorFeature, index: int) -> tuple[Part, ...]:
    """The geoms of one feature, named ``floor_<kind>_<index>...``."""
    prefix = f"floor_{feature.kind}_{index}"
    if feature.kind == "threshold":
        return _hump(prefix, feature, THRESHOLD_COLOUR)
    if feature.kind == "ramp":
        return _hump(prefix, feature, RAMP_COLOUR)
    if feature.kind == "rug":
        return (
            Part(
                prefix, "box", (feature.width_m / 2, feature.length_m / 2, feature.height_m / 2),
                _to_world(feature, 0.0, feature.height_m / 2), feature.yaw_rad, RUG_COLOUR,
                FLOOR_FEATURE_GROUP, blocking=False,
                friction=feature.friction or CARPET_FRICTION,
            ),
        )  # fmt: skip
    radius = feature.height_m / 2
    return (
        Part(
            prefix, "capsule", (radius, max(feature.length_m / 2 - radius, 1e-3), 0.0),
            _to_world(feature, 0.0, radius), feature.yaw_rad + math.pi / 2, CABLE_COLOUR,
            FLOOR_FEATURE_GROUP, pitch_rad=math.pi / 2, blocking=False,
        ),
    )  # fmt: skip


def features_to_parts(features: tuple[FloorFeature, ...], first_index: int = 0) -> tuple[Part, ...]:
    """The parts of several features, numbered from ``first_index`` per house."""
    return tuple(
        part
        for k, feature in enumerate(features)
        for part in floor_feature_parts(feature, first_index + k)
    )
