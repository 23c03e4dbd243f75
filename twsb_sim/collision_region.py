"""A run confined to a region: the house's geoms the robot cannot reach leave collision.

MuJoCo collides each of the robot's bodies with the house by walking the bounding-volume
tree of every static geom, every physics step; in a generated house that walk is about a
third of the step (``docs/speed.md``). A run whose LiDAR origin stays inside a known
region (a data-set episode drives one lane) can only touch the geoms that come within the
robot's reach of that region; the others are compiled without contacts, which leaves a
smaller tree to walk. The contacts, and so the trajectory, are the same to the bit, as
long as the robot really stays inside: the simulation checks the LiDAR origin at every
physics step against the region and raises :class:`LeftCollisionRegion` the first time it
is outside, after which the run's frames are no longer to be trusted (run it again without
a region).

The ray cast does not look at contact flags: every geom stays visible to the LiDAR.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from twsb_sim.kernel import kernel
from twsb_sim.robot import LIDAR_SITE

REACH_MARGIN_M = 0.01  # m, kept in collision beyond the robot's reach (rounding, margins)
_CORNERS = np.array([(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)


class LeftCollisionRegion(RuntimeError):
    """The robot left the region its run was compiled for: contacts may have been missed."""


@dataclass(frozen=True)
class CollisionRegion:
    """A box the LiDAR origin must stay in, in a frame turned by ``yaw_rad`` about world z.

    Attributes:
        origin_m: ``(x, y, z)`` of the box frame's origin in the world, m.
        yaw_rad: heading of the box frame's x axis, counter-clockwise from world x.
        lower_m: ``(x, y, z)`` lower corner of the box in its frame, m.
        upper_m: ``(x, y, z)`` upper corner, m, each above the lower one.
    """

    origin_m: tuple[float, float, float]
    yaw_rad: float
    lower_m: tuple[float, float, float]
    upper_m: tuple[float, float, float]

    def __post_init__(self) -> None:
        values = (*self.origin_m, self.yaw_rad, *self.lower_m, *self.upper_m)
        if len(values) != 10 or not all(math.isfinite(v) for v in values):
            raise ValueError(f"collision region: expected finite 3-vectors and yaw, got {self}")
        if not all(lo < hi for lo, hi in zip(self.lower_m, self.upper_m, strict=True)):
            raise ValueError(f"collision region: lower_m must lie below upper_m, got {self}")

    def rotation(self) -> np.ndarray:
        """``(3, 3)``: world vectors times this give box-frame vectors (``v @ R``)."""
        c, s = math.cos(self.yaw_rad), math.sin(self.yaw_rad)
        return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])

    def to_box(self, points_world: np.ndarray) -> np.ndarray:
        """``(n, 3)`` world points in the box frame."""
        return (np.asarray(points_world) - self.origin_m) @ self.rotation()

    def grown(self, distance_m: float) -> tuple[np.ndarray, np.ndarray]:
        """The box's lower and upper corners, each moved out by ``distance_m``."""
        return np.array(self.lower_m) - distance_m, np.array(self.upper_m) + distance_m


class RegionGuard:
    """Checks positions against a region, with the box frame's numbers prepared once.

    Args:
        region: the box.
    """

    def __init__(self, region: CollisionRegion) -> None:
        self.region = region
        self._rotation = region.rotation()
        # p @ R - o @ R within [lower, upper]  <=>  p @ R within [lower + o @ R, upper + o @ R]
        shift = np.asarray(region.origin_m) @ self._rotation
        self._lower = np.array(region.lower_m) + shift
        self._upper = np.array(region.upper_m) + shift

    def check(self, positions_world: np.ndarray) -> None:
        """Raise :class:`LeftCollisionRegion` if any of the ``(n, 3)`` positions is outside."""
        outside = _first_outside(positions_world, self._rotation, self._lower, self._upper)
        if outside >= 0:
            raise LeftCollisionRegion(
                f"the LiDAR origin reached {np.round(positions_world[outside], 3).tolist()} "
                f"(m, world), outside the collision region {self.region}"
            )


@kernel
def _first_outside(
    positions: np.ndarray, rotation: np.ndarray, lower: np.ndarray, upper: np.ndarray
) -> int:
    """The first of the ``(n, 3)`` positions whose ``position @ rotation`` is not within
    ``[lower, upper]``, or -1 (every physics step checks one: a compiled loop)."""
    for i in range(len(positions)):
        for axis in range(3):
            local = 0.0
            for k in range(3):
                local += positions[i, k] * rotation[k, axis]
            if local < lower[axis] or local > upper[axis]:
                return i
    return -1


def robot_reach_m(model: mujoco.MjModel, data: mujoco.MjData) -> float:
    """How far from the LiDAR origin any colliding geom of the robot can be (m).

    The robot's bodies are those of the LiDAR site's tree; each colliding geom counts with
    its centre's distance from the site in ``data``'s pose plus its bounding radius. The
    base is rigid and the wheels turn about their own centres, so this holds in any pose.
    """
    site = model.site(LIDAR_SITE)
    root = model.body_rootid[site.bodyid[0]]
    robot = model.body_rootid[model.geom_bodyid] == root
    colliding = robot & ((model.geom_contype | model.geom_conaffinity) > 0)
    offsets = data.geom_xpos[colliding] - data.site_xpos[site.id]
    return float((np.linalg.norm(offsets, axis=1) + model.geom_rbound[colliding]).max())


def others_move(model: mujoco.MjModel) -> bool:
    """Whether a body outside the robot's tree can move and collide (free furniture):
    its positions are not tracked, so a region cannot vouch for its contacts."""
    root = model.body_rootid[model.site(LIDAR_SITE).bodyid[0]]
    for body in range(1, model.nbody):
        colliding = model.body_contype[body] or model.body_conaffinity[body]
        if colliding and model.body_weldid[body] != 0 and model.body_rootid[body] != root:
            return True
    return False


def confine_collisions(spec: mujoco.MjSpec, region: CollisionRegion) -> list[str]:
    """Take out of collision the static geoms that the robot cannot touch from ``region``.

    A static geom (welded to the world, named, not a plane) keeps its contacts when its
    bounding box, in the region's frame, comes within the robot's reach (plus
    ``REACH_MARGIN_M``) of the region; the others get ``contype = conaffinity = 0``.
    Nothing changes when another body than the robot can move and collide.

    Args:
        spec: the full model (robot, house, movers), not yet compiled; changed in place.
        region: where the LiDAR origin will stay.

    Returns:
        The names of the geoms taken out of collision.
    """
    model = spec.compile()
    if others_move(model):
        return []
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    lower, upper = region.grown(robot_reach_m(model, data) + REACH_MARGIN_M)
    static = model.body_weldid[model.geom_bodyid] == 0
    static &= model.geom_type != mujoco.mjtGeom.mjGEOM_PLANE
    static &= (model.geom_contype | model.geom_conaffinity) > 0
    ids = np.array([g for g in np.flatnonzero(static) if model.geom(int(g)).name], dtype=int)
    # every corner of each geom's bounding box, in the region's frame
    corners = model.geom_aabb[ids, None, :3] + _CORNERS * model.geom_aabb[ids, None, 3:]
    rotations = data.geom_xmat[ids].reshape(-1, 3, 3)
    world = np.einsum("gij,gkj->gki", rotations, corners) + data.geom_xpos[ids, None, :]
    local = region.to_box(world.reshape(-1, 3)).reshape(len(ids), 8, 3)
    reachable = ((local.max(axis=1) >= lower) & (local.min(axis=1) <= upper)).all(axis=1)
    names = [model.geom(int(g)).name for g in ids[~reachable]]
    for name in names:
        geom = spec.geom(name)
        geom.contype = geom.conaffinity = 0
    return names
