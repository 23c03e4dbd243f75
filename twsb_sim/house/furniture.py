"""Furniture as boxes and cylinders: tables, sofas, shelves, chairs, cabinets, beds.

A piece is described in its own frame: origin at the centre of its footprint on the
floor, width along local x, depth along local y, the back (headboard, sofa back, shelf
back) on the local +y side. ``make_furniture`` rotates it by ``yaw`` about z and moves it
to ``(x, y)``; the parts are named ``<kind>_<k>_<part>`` (``table_2_leg_0``).
"""

from __future__ import annotations

import math

from twsb_sim.house.model import Furniture, Part, Rgba

FURNITURE_KINDS: tuple[str, ...] = ("table", "sofa", "shelf", "chair", "cabinet", "bed")
FURNITURE_GROUP = 1  # MuJoCo geom group of furniture

# Default outer dimensions (width, depth, height) in m.
DEFAULT_DIMENSIONS_M: dict[str, tuple[float, float, float]] = {
    "table": (1.2, 0.8, 0.75),
    "sofa": (2.0, 0.9, 0.85),
    "shelf": (0.9, 0.35, 1.8),
    "chair": (0.45, 0.45, 0.9),
    "cabinet": (1.2, 0.5, 0.9),
    "bed": (1.6, 2.0, 0.5),
}

WOOD: Rgba = (0.55, 0.38, 0.22, 1.0)
DARK_WOOD: Rgba = (0.36, 0.24, 0.15, 1.0)
METAL: Rgba = (0.25, 0.25, 0.27, 1.0)
FABRIC: Rgba = (0.30, 0.38, 0.52, 1.0)
CUSHION: Rgba = (0.42, 0.50, 0.64, 1.0)
WHITE_LACQUER: Rgba = (0.86, 0.86, 0.83, 1.0)
LINEN: Rgba = (0.93, 0.91, 0.86, 1.0)

# A local part: suffix, shape, size, local centre (x, y, z), colour.
_Local = tuple[str, str, tuple[float, float, float], tuple[float, float, float], Rgba]


def _table(w: float, d: float, h: float) -> list[_Local]:
    top = 0.02  # half thickness of the top (m)
    leg_r, inset = 0.025, 0.06  # m
    legs = [
        (
            f"leg_{j}",
            "cylinder",
            (leg_r, (h - 2 * top) / 2, 0.0),
            (sx, sy, (h - 2 * top) / 2),
            METAL,
        )
        for j, (sx, sy) in enumerate(
            (sx * (w / 2 - inset), sy * (d / 2 - inset))
            for sx, sy in ((-1, -1), (1, -1), (1, 1), (-1, 1))
        )
    ]
    return [("top", "box", (w / 2, d / 2, top), (0.0, 0.0, h - top), WOOD), *legs]


def _sofa(w: float, d: float, h: float) -> list[_Local]:
    seat_h, back_d, arm_w, arm_h = 0.42, 0.2, 0.15, 0.6  # m
    seat_d = d - back_d
    return [
        ("seat", "box", (w / 2, seat_d / 2, seat_h / 2), (0.0, -back_d / 2, seat_h / 2), CUSHION),
        ("back", "box", (w / 2, back_d / 2, h / 2), (0.0, d / 2 - back_d / 2, h / 2), FABRIC),
        *(
            (f"arm_{j}", "box", (arm_w / 2, seat_d / 2, arm_h / 2),
             (s * (w / 2 - arm_w / 2), -back_d / 2, arm_h / 2), FABRIC)
            for j, s in enumerate((-1, 1))
        ),
    ]  # fmt: skip


def _shelf(w: float, d: float, h: float) -> list[_Local]:
    t = 0.01  # half thickness of a panel (m)
    inner_w = w / 2 - 2 * t
    boards = [
        (f"board_{j}", "box", (inner_w, d / 2 - t, t), (0.0, -t, z), WOOD)
        for j, z in enumerate((0.08, (0.08 + h) / 2, h - t))
    ]
    return [
        *((f"side_{j}", "box", (t, d / 2, h / 2), (s * (w / 2 - t), 0.0, h / 2), DARK_WOOD)
          for j, s in enumerate((-1, 1))),
        ("back", "box", (inner_w, t, h / 2), (0.0, d / 2 - t, h / 2), DARK_WOOD),
        *boards,
    ]  # fmt: skip


def _chair(w: float, d: float, h: float) -> list[_Local]:
    seat_z, t, leg_r, inset = 0.45, 0.02, 0.018, 0.04  # m
    legs = [
        (
            f"leg_{j}",
            "cylinder",
            (leg_r, (seat_z - t) / 2, 0.0),
            (sx, sy, (seat_z - t) / 2),
            DARK_WOOD,
        )
        for j, (sx, sy) in enumerate(
            (sx * (w / 2 - inset), sy * (d / 2 - inset))
            for sx, sy in ((-1, -1), (1, -1), (1, 1), (-1, 1))
        )
    ]
    back_h = h - seat_z - t
    return [
        ("seat", "box", (w / 2, d / 2, t), (0.0, 0.0, seat_z), WOOD),
        ("back", "box", (w / 2, t, back_h / 2), (0.0, d / 2 - t, seat_z + t + back_h / 2), WOOD),
        *legs,
    ]


def _cabinet(w: float, d: float, h: float) -> list[_Local]:
    top = 0.015  # half thickness of the top slab (m)
    body_h = h - 2 * top
    return [
        (
            "body",
            "box",
            (w / 2 - 0.01, d / 2 - 0.01, body_h / 2),
            (0.0, 0.0, body_h / 2),
            WHITE_LACQUER,
        ),
        ("top", "box", (w / 2, d / 2, top), (0.0, 0.0, h - top), DARK_WOOD),
    ]


def _bed(w: float, d: float, h: float) -> list[_Local]:
    frame_h, head_t, head_h = 0.3, 0.04, 1.0  # m
    mattress_d = d - 2 * head_t
    return [
        ("frame", "box", (w / 2, d / 2, frame_h / 2), (0.0, 0.0, frame_h / 2), WOOD),
        ("mattress", "box", (w / 2 - 0.03, mattress_d / 2, (h - frame_h) / 2),
         (0.0, -head_t, frame_h + (h - frame_h) / 2), LINEN),
        ("headboard", "box", (w / 2, head_t, head_h / 2), (0.0, d / 2 - head_t, head_h / 2),
         DARK_WOOD),
    ]  # fmt: skip


_BUILDERS = {
    "table": _table,
    "sofa": _sofa,
    "shelf": _shelf,
    "chair": _chair,
    "cabinet": _cabinet,
    "bed": _bed,
}


def make_furniture(
    kind: str,
    index: int,
    x_m: float,
    y_m: float,
    yaw_rad: float,
    dimensions_m: tuple[float, float, float] | None = None,
) -> Furniture:
    """Build one piece of furniture in the world.

    Args:
        kind: one of ``FURNITURE_KINDS``.
        index: the ``k`` in the name ``<kind>_<k>``; unique per kind within a house.
        x_m, y_m: centre of the footprint (m).
        yaw_rad: rotation about z (rad); 0 puts the back on the +y side.
        dimensions_m: (width, depth, height) in m; the kind's default when None.

    Returns:
        The piece with its parts in world coordinates.
    """
    if kind not in _BUILDERS:
        raise ValueError(f"kind: expected one of {list(FURNITURE_KINDS)}, got {kind!r}")
    w, d, h = dimensions_m or DEFAULT_DIMENSIONS_M[kind]
    name = f"{kind}_{index}"
    c, s = math.cos(yaw_rad), math.sin(yaw_rad)
    parts = tuple(
        Part(
            name=f"{name}_{suffix}",
            shape=shape,  # type: ignore[arg-type]
            size=size,
            pos=(x_m + c * lx - s * ly, y_m + s * lx + c * ly, lz),
            yaw_rad=yaw_rad,
            rgba=rgba,
            group=FURNITURE_GROUP,
        )
        for suffix, shape, size, (lx, ly, lz), rgba in _BUILDERS[kind](w, d, h)
    )
    return Furniture(name, kind, x_m, y_m, yaw_rad, w, d, h, parts)
