"""Whether a robot can stand at a point of a house: inside it, clear of walls and furniture.

A start pose given by hand (a scenario's ``house.start``) can put the robot outside the
house or inside a wall or a sofa. MuJoCo then pushes the overlapping bodies apart with
huge contact forces, and the run reports nonsense. :func:`why_cannot_stand` tells why a
point is no place for the robot, naming the part in the way.
"""

from __future__ import annotations

import numpy as np

from twsb_sim.house.model import Doorway, House
from twsb_sim.house.spawn import Obstacles

# half the robot's width over the tyres (track 0.30 m, tyres 0.035 m wide): a smaller disc
# than the planning footprint, so a start the robot physically fits in is never refused
STANDING_RADIUS_M = 0.17  # m
ROBOT_HEIGHT_M = 0.6  # m, the torso's top (0.58 m): it stands under a table top, not a shelf


def _in_doorway(door: Doorway, wall_thickness_m: float, x_m: float, y_m: float) -> bool:
    along, across = (
        (x_m - door.x_m, y_m - door.y_m) if door.along_x else (y_m - door.y_m, x_m - door.x_m)
    )
    return abs(along) <= door.width_m / 2 and abs(across) <= wall_thickness_m / 2


def why_cannot_stand(
    house: House, x_m: float, y_m: float, height_m: float = ROBOT_HEIGHT_M
) -> str | None:
    """Why the robot cannot stand upright at ``(x_m, y_m)`` (None when it can).

    Args:
        house: the house.
        x_m, y_m: the robot's base position in the world (m).
        height_m: the robot's height (m): parts higher up (table tops) leave room under them.

    Returns:
        A short reason, e.g. ``"outside house1 (its rooms span x 0 to 11 m, y 0 to 8 m)"``
        or ``"inside sofa_0_seat (a disc of 0.17 m radius overlaps it)"``.
    """
    inside = any(room.contains(x_m, y_m) for room in house.rooms) or any(
        _in_doorway(door, house.wall_thickness_m, x_m, y_m) for door in house.doorways
    )
    if not inside:
        x0, y0, x1, y1 = house.extent_m
        return f"outside {house.name} (its rooms span x {x0:g} to {x1:g} m, y {y0:g} to {y1:g} m)"
    point = np.array([[x_m, y_m]])
    low = [p for p in house.parts() if p.shape != "plane" and p.z_min_m < height_m]
    # one test against all parts (each part's arithmetic is the same as alone): the usual
    # answer, "free", without building a hundred one-part obstacle sets (about 8 ms)
    if Obstacles(low).is_free(point, STANDING_RADIUS_M)[0]:
        return None
    for part in low:  # something is in the way: name the first part that is
        if not Obstacles([part]).is_free(point, STANDING_RADIUS_M)[0]:
            return (
                f"inside or against {part.name} (the robot, {STANDING_RADIUS_M:g} m from its "
                "centre to its tyres' edges, would overlap it)"
            )
    return None
