"""All the movers of a run: added to the model once, posed whenever the LiDAR casts."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol

import mujoco
import numpy as np


class Mover(Protocol):
    """What the simulation needs from a mover."""

    name: str

    @property
    def body_names(self) -> tuple[str, ...]:
        """Its mocap bodies, in the order :meth:`poses` gives them (none for free bodies)."""
        ...

    def add_to_spec(self, spec: mujoco.MjSpec) -> None:
        """Add its bodies and geoms to the spec."""
        ...


class MoverSet:
    """The movers of one run.

    Args:
        movers: people, pets, doors, light furniture (names unique).
    """

    def __init__(self, movers: Sequence[Mover] = ()) -> None:
        names = [m.name for m in movers]
        if len(set(names)) != len(names):
            raise ValueError(f"movers: names must be unique, got {names}")
        self.movers = tuple(movers)
        self._kinematic = tuple(m for m in self.movers if m.body_names)
        self._mocap_ids: np.ndarray | None = None

    def __bool__(self) -> bool:
        return bool(self.movers)

    def add_to_spec(self, spec: mujoco.MjSpec) -> None:
        """Add every mover's bodies (after the house and the robot)."""
        for mover in self.movers:
            mover.add_to_spec(spec)

    def bind(self, model: mujoco.MjModel) -> None:
        """Find the mocap bodies in a compiled model (by name)."""
        ids = [
            int(model.body_mocapid[model.body(name).id])
            for mover in self._kinematic
            for name in mover.body_names
        ]
        self._mocap_ids = np.array(ids, dtype=np.int64)

    def pose(self, data: mujoco.MjData, t_s: float) -> None:
        """Put every kinematic mover where it is at ``t_s`` (call before ``mj_forward``)."""
        if not self._kinematic:
            return
        if self._mocap_ids is None:
            raise RuntimeError("MoverSet.bind(model) must run before pose()")
        positions, quats = zip(*(m.poses(t_s) for m in self._kinematic), strict=True)
        data.mocap_pos[self._mocap_ids] = np.concatenate(positions)
        data.mocap_quat[self._mocap_ids] = np.concatenate(quats)
