"""Surface classes of geoms, derived from their names (and the robot's geom group).

Naming convention of house geoms (``add_house_to_spec`` writes exactly these):

| name | class |
|---|---|
| ``floor``, ``floor_<kind>_<k>...`` (thresholds, rugs, ramps, cables) | FLOOR |
| ``ceiling``, ``ceiling_<kind>_<k>...`` (sloped ceilings, stair undersides) | CEILING |
| ``wall_<k>``, ``door_frame_<k>_left|right|header`` | STRUCTURE |
| ``<kind>_<k>_<part>``, kind in table, sofa, shelf, chair, cabinet, bed | FURNITURE |
| any geom in geom group 3 | ROBOT |
| any other geom on a body that can move | DYNAMIC |
| any other geom (unnamed or unknown) | STRUCTURE |
"""

from __future__ import annotations

from enum import IntEnum

import mujoco
import numpy as np

from twsb_sim.house.furniture import FURNITURE_KINDS
from twsb_sim.robot import ROBOT_GEOM_GROUP  # the LiDAR never sees this group


class SurfaceClass(IntEnum):
    """What kind of surface a geom is, for labelling LiDAR beams."""

    STRUCTURE = 0  # walls, door frames, anything static and unnamed
    FLOOR = 1
    CEILING = 2
    FURNITURE = 3
    ROBOT = 4  # geom group 3
    DYNAMIC = 5  # geoms on a moving body other than the robot (people, moving furniture)


_FURNITURE_PREFIXES = tuple(f"{kind}_" for kind in FURNITURE_KINDS)


def surface_class_of_name(name: str) -> SurfaceClass:
    """The class a static house geom's name implies."""
    if name == "floor" or name.startswith("floor_"):
        return SurfaceClass.FLOOR
    if name == "ceiling" or name.startswith("ceiling_"):
        return SurfaceClass.CEILING
    if name.startswith(_FURNITURE_PREFIXES):
        return SurfaceClass.FURNITURE
    return SurfaceClass.STRUCTURE


def surface_classes(model: mujoco.MjModel) -> np.ndarray:
    """Each geom's surface class, computed once per model.

    Args:
        model: a compiled model holding a house (and possibly a robot).

    Returns:
        uint8 array of ``SurfaceClass`` codes, indexed by geom id.
    """
    classes = np.empty(model.ngeom, dtype=np.uint8)
    for geom_id in range(model.ngeom):
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, geom_id) or ""
        body_id = model.geom_bodyid[geom_id]
        if model.geom_group[geom_id] == ROBOT_GEOM_GROUP:
            classes[geom_id] = SurfaceClass.ROBOT
        elif model.body_weldid[body_id] != 0 or model.body_mocapid[body_id] >= 0:
            classes[geom_id] = SurfaceClass.DYNAMIC
        else:
            classes[geom_id] = surface_class_of_name(name)
    return classes
