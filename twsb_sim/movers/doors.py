"""Doors that open and close: a leaf hinged at one jamb of a doorway, swung kinematically.

The leaf is a mocap body (``door_leaf_<k>``) whose frame sits on the hinge axis; it turns
about the vertical through the hinge from closed (in the wall's plane, across the opening)
to ``open_deg`` into one of the two rooms. At every time in ``toggle_times_s`` it starts to
swing to the other state, over ``swing_s``, with a cosine ease (a hand pushes, the door
slows near its stop). Like people, the leaf has no contacts and is labeled DYNAMIC.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from twsb_sim.house.model import Doorway
from twsb_sim.movers.people import add_visual_geom, quat_yaw_pitch

LEAF_THICKNESS_M = 0.04  # m
LEAF_GAP_M = 0.01  # m, clearance to the jambs and the floor
LEAF_COLOUR: tuple[float, float, float, float] = (0.70, 0.55, 0.38, 1.0)


@dataclass(frozen=True)
class SwingingDoor:
    """A door leaf in a doorway.

    Attributes:
        name: ``door_leaf_<k>``.
        doorway: the opening it closes.
        hinge_at_low_end: the hinge is at the opening's end of lower x (walls along x) or
            lower y; else at the other end.
        opens_positive: it opens towards +y (walls along x) or +x; else towards -y / -x.
        open_deg: how far it opens (deg).
        start_open: its state at time 0.
        toggle_times_s: when it starts to swing to the other state (s, increasing).
        swing_s: how long a swing takes (s).
    """

    name: str
    doorway: Doorway
    hinge_at_low_end: bool = True
    opens_positive: bool = True
    open_deg: float = 90.0
    start_open: bool = False
    toggle_times_s: tuple[float, ...] = ()
    swing_s: float = 1.5

    def __post_init__(self) -> None:
        if not 10.0 <= self.open_deg <= 180.0:
            raise ValueError(f"open_deg: expected 10 to 180 deg, got {self.open_deg}")
        if not 0.1 <= self.swing_s <= 10.0:
            raise ValueError(f"swing_s: expected 0.1 to 10 s, got {self.swing_s}")
        if any(b < a for a, b in zip(self.toggle_times_s, self.toggle_times_s[1:], strict=False)):
            raise ValueError(
                f"toggle_times_s: expected increasing times, got {self.toggle_times_s}"
            )

    @property
    def body_names(self) -> tuple[str, ...]:
        return (self.name,)

    def _hinge_and_closed_yaw(self) -> tuple[float, float, float]:
        """Hinge (x, y) and the yaw of the leaf's long axis when closed."""
        d = self.doorway
        half = d.width_m / 2
        sign = -1.0 if self.hinge_at_low_end else 1.0
        if d.along_x:
            return d.x_m + sign * half, d.y_m, 0.0 if self.hinge_at_low_end else math.pi
        return d.x_m, d.y_m + sign * half, math.pi / 2 if self.hinge_at_low_end else -math.pi / 2

    def add_to_spec(self, spec: mujoco.MjSpec) -> None:
        """The leaf: a mocap body on the hinge axis, the board along its local +x."""
        d = self.doorway
        width = d.width_m - 2 * LEAF_GAP_M
        height = d.height_m - 2 * LEAF_GAP_M
        body = spec.worldbody.add_body(name=self.name, mocap=True)
        add_visual_geom(body, f"{self.name}_board", type=mujoco.mjtGeom.mjGEOM_BOX,
                        size=[width / 2, LEAF_THICKNESS_M / 2, height / 2],
                        pos=[LEAF_GAP_M + width / 2, 0, LEAF_GAP_M + height / 2],
                        rgba=list(LEAF_COLOUR))  # fmt: skip

    def opening(self, t_s: float) -> float:
        """How open the door is at ``t_s``: 0 closed, 1 open."""
        state = 1.0 if self.start_open else 0.0
        for toggle in self.toggle_times_s:
            if t_s <= toggle:
                break
            target = 1.0 - state
            progress = min(1.0, (t_s - toggle) / self.swing_s)
            eased = 0.5 - 0.5 * math.cos(math.pi * progress)
            state = state + (target - state) * eased
        return state

    def poses(self, t_s: float) -> tuple[np.ndarray, np.ndarray]:
        """Position (1, 3) and quaternion (1, 4) of the leaf at ``t_s``."""
        x, y, closed_yaw = self._hinge_and_closed_yaw()
        # opening turns the free end towards the room it opens into
        towards = 1.0 if self.opens_positive else -1.0
        turn = math.radians(self.open_deg) * self.opening(t_s)
        leaf_dir = (math.cos(closed_yaw), math.sin(closed_yaw))
        normal = (-leaf_dir[1], leaf_dir[0])  # the leaf's left
        room_side = (0.0, 1.0) if self.doorway.along_x else (1.0, 0.0)
        left_is_room = normal[0] * room_side[0] + normal[1] * room_side[1] > 0
        sense = towards if left_is_room else -towards
        yaw = closed_yaw + sense * turn
        return np.array([(x, y, 0.0)]), np.array([quat_yaw_pitch(yaw, 0.0)])
