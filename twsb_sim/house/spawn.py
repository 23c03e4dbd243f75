"""Where a robot may start, and how far it can drive straight from there.

The robot is treated as a disc of radius ``ROBOT_RADIUS_M`` moving in the floor plane.
Obstacles are the footprints of every wall, door jamb and furniture part that reaches
below ``OBSTACLE_TOP_M`` (door headers do not); parts that do not block (floor features
the robot drives over, surfaces overhead) are left out. A box footprint is inflated by the radius
into a larger rectangle (not a rounded one), so the clearances are lower bounds: the
robot can always drive at least ``clear_ahead_m``, sometimes up to ~0.1 m more.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

import numpy as np

from twsb_sim.house.model import Part, Room, SpawnPose
from twsb_sim.kernel import kernel

ROBOT_RADIUS_M = 0.25  # footprint radius of the robot (m)
OBSTACLE_TOP_M = 1.5  # parts whose bottom is lower than this block the robot (m)
FREE_MARGIN_M = 0.05  # extra gap between a spawned robot and the nearest obstacle (m)
GRID_STEP_M = 0.25  # spacing of the candidate start positions (m)
MAX_CLEARANCE_M = 50.0  # clearances are capped here (m)
MIN_REVERSE_M = 0.3  # a "lane start" pose keeps at least this much room behind (m)
YAWS = np.array([0.0, math.pi / 2, math.pi, -math.pi / 2])  # rad, the start headings tried
PRUNE_MARGIN_M = 1e-6  # m, bounding circles grown by this: far above rounding, never prunes a hit


class Obstacles:
    """Footprints of the parts that block a robot, as arrays for vectorised queries."""

    def __init__(self, parts: Iterable[Part]) -> None:
        blocking = [
            p
            for p in parts
            if p.blocking and p.shape in ("box", "cylinder") and p.z_min_m < OBSTACLE_TOP_M
        ]
        boxes = [p for p in blocking if p.shape == "box"]
        discs = [p for p in blocking if p.shape == "cylinder"]
        # per box: centre x, y, half extents x, y, yaw
        self.boxes = np.array(
            [(p.pos[0], p.pos[1], p.size[0], p.size[1], p.yaw_rad) for p in boxes], float
        ).reshape(-1, 5)
        # per disc: centre x, y, radius
        self.discs = np.array([(p.pos[0], p.pos[1], p.size[0]) for p in discs], float).reshape(
            -1, 3
        )

    def is_free(self, xy: np.ndarray, radius_m: float) -> np.ndarray:
        """Whether a disc of ``radius_m`` centred at each point (N, 2) touches nothing."""
        yaw = self.boxes[:, 4]
        return _free(
            np.asarray(xy, dtype=np.float64).reshape(-1, 2), self.boxes, np.cos(yaw),
            np.sin(yaw), self.discs, radius_m,
        )  # fmt: skip

    def clearance_m(self, xy: np.ndarray, yaw_rad: np.ndarray, radius_m: float) -> np.ndarray:
        """How far a disc of ``radius_m`` at each point (N, 2) can move along its heading
        (N,) before touching an obstacle (m, a lower bound, 0 if it already touches)."""
        heading = np.stack((np.cos(yaw_rad), np.sin(yaw_rad)), -1)
        half = self.boxes[:, 2:4] + radius_m  # the boxes inflated by the radius
        reach = np.hypot(half[:, 0], half[:, 1]) + PRUNE_MARGIN_M  # their bounding circles
        yaw = self.boxes[:, 4]
        return _clearances(
            np.asarray(xy, dtype=np.float64), heading, self.boxes, half, np.cos(yaw),
            np.sin(yaw), reach, self.discs, radius_m,
        )  # fmt: skip


@kernel
def _clearances(
    xy: np.ndarray,
    heading: np.ndarray,
    boxes: np.ndarray,
    half: np.ndarray,
    cos_yaw: np.ndarray,
    sin_yaw: np.ndarray,
    reach: np.ndarray,
    discs: np.ndarray,
    radius_m: float,
) -> np.ndarray:
    """:meth:`Obstacles.clearance_m` of points (N, 2) along unit headings (N, 2).

    Per ray, the slab test against every box inflated to ``half`` (the first t >= 0 on
    the ray inside one), skipping the boxes whose bounding circle (``reach``) the ray
    passes by or has left behind, about nine in ten in a house; then the first t >= 0
    at which the disc touches each obstacle disc. Capped at ``MAX_CLEARANCE_M``.
    """
    out = np.empty(len(xy))
    for r in range(len(xy)):
        px, py, hx, hy = xy[r, 0], xy[r, 1], heading[r, 0], heading[r, 1]
        box_t = np.inf
        for m in range(len(boxes)):
            to_x, to_y = boxes[m, 0] - px, boxes[m, 1] - py
            if not (abs(to_y * hx - to_x * hy) <= reach[m] and to_x * hx + to_y * hy >= -reach[m]):
                continue
            c, s = cos_yaw[m], sin_yaw[m]
            rel_x, rel_y = px - boxes[m, 0], py - boxes[m, 1]
            local_x, local_y = c * rel_x + s * rel_y, -s * rel_x + c * rel_y
            d_x, d_y = c * hx + s * hy, -s * hx + c * hy
            d_x = 1e-12 if abs(d_x) < 1e-12 else d_x
            d_y = 1e-12 if abs(d_y) < 1e-12 else d_y
            t1_x, t2_x = (-half[m, 0] - local_x) / d_x, (half[m, 0] - local_x) / d_x
            t1_y, t2_y = (-half[m, 1] - local_y) / d_y, (half[m, 1] - local_y) / d_y
            t_near = np.maximum(np.minimum(t1_x, t2_x), np.minimum(t1_y, t2_y))
            t_far = np.minimum(np.maximum(t1_x, t2_x), np.maximum(t1_y, t2_y))
            if t_near <= t_far and t_far >= 0:
                box_t = np.minimum(box_t, np.maximum(t_near, 0.0))
        # disc-disc: solve |p + t d - c| = r_c + radius for the first t >= 0
        disc_t = np.inf
        for m in range(len(discs)):
            rel_x, rel_y = px - discs[m, 0], py - discs[m, 1]
            b = rel_x * hx + rel_y * hy
            grown = discs[m, 2] + radius_m
            cc = (rel_x * rel_x + rel_y * rel_y) - grown * grown
            disc = b * b - cc
            root = -b - np.sqrt(np.maximum(disc, 0.0))
            if cc <= 0:
                disc_t = np.minimum(disc_t, 0.0)
            elif disc >= 0 and root >= 0:
                disc_t = np.minimum(disc_t, root)
        out[r] = np.minimum(np.minimum(box_t, disc_t), MAX_CLEARANCE_M)
    return out


@kernel
def _free(
    xy: np.ndarray,
    boxes: np.ndarray,
    cos_yaw: np.ndarray,
    sin_yaw: np.ndarray,
    discs: np.ndarray,
    radius_m: float,
) -> np.ndarray:
    """:meth:`Obstacles.is_free` of points (N, 2): outside every box inflated by the
    radius (tested in the box's frame) and every disc grown by it."""
    free = np.ones(len(xy), np.bool_)
    for r in range(len(xy)):
        px, py = xy[r, 0], xy[r, 1]
        for m in range(len(boxes)):
            rel_x, rel_y = px - boxes[m, 0], py - boxes[m, 1]
            c, s = cos_yaw[m], sin_yaw[m]
            inside_x = abs(c * rel_x + s * rel_y) < boxes[m, 2] + radius_m
            if inside_x and abs(-s * rel_x + c * rel_y) < boxes[m, 3] + radius_m:
                free[r] = False
                break
        if not free[r]:
            continue
        for m in range(len(discs)):
            gap_x, gap_y = px - discs[m, 0], py - discs[m, 1]
            if np.sqrt(gap_x * gap_x + gap_y * gap_y) < discs[m, 2] + radius_m:
                free[r] = False
                break
    return free


def find_spawn_poses(
    rooms: Iterable[Room], parts: Iterable[Part], wall_thickness_m: float
) -> tuple[SpawnPose, ...]:
    """Pick start poses on a grid in every room, headings along the room's axes.

    Per room: the pose with the longest clear run ahead that can still back up
    ``MIN_REVERSE_M`` (a lane start), and the pose with the most room both ways (a
    centre). Returned sorted by ``clear_ahead_m``, longest first.
    """
    obstacles = Obstacles(parts)
    radius = ROBOT_RADIUS_M
    poses: dict[tuple[float, float, float], SpawnPose] = {}
    for room in rooms:
        inset = wall_thickness_m / 2 + radius + FREE_MARGIN_M
        xs = np.arange(room.x_min_m + inset, room.x_max_m - inset + 1e-9, GRID_STEP_M)
        ys = np.arange(room.y_min_m + inset, room.y_max_m - inset + 1e-9, GRID_STEP_M)
        if xs.size == 0 or ys.size == 0:
            continue
        grid = np.stack(np.meshgrid(xs, ys, indexing="ij"), -1).reshape(-1, 2)
        grid = grid[obstacles.is_free(grid, radius + FREE_MARGIN_M)]
        if grid.shape[0] == 0:
            continue
        # every heading once, ahead and behind: behind 0 is ahead pi and behind -pi/2 is
        # ahead pi/2 (-pi/2 + pi == pi/2 in floating point), so 6 headings, not 8
        headings, column = np.unique(np.concatenate((YAWS, YAWS + math.pi)), return_inverse=True)
        clear = obstacles.clearance_m(
            np.repeat(grid, headings.size, axis=0), np.tile(headings, grid.shape[0]), radius
        ).reshape(-1, headings.size)
        xy = np.repeat(grid, YAWS.size, axis=0)
        yaw = np.tile(YAWS, grid.shape[0])
        ahead = clear[:, column[: YAWS.size]].reshape(-1)
        behind = clear[:, column[YAWS.size :]].reshape(-1)
        lane_score = np.where(behind >= MIN_REVERSE_M, ahead, -1.0)
        for k in (int(np.argmax(lane_score)), int(np.argmax(np.minimum(ahead, behind)))):
            key = (round(float(xy[k, 0]), 6), round(float(xy[k, 1]), 6), float(yaw[k]))
            # floor to the millimetre so the stored clearances stay lower bounds
            poses[key] = SpawnPose(
                x_m=key[0],
                y_m=key[1],
                yaw_rad=key[2],
                clear_ahead_m=math.floor(float(ahead[k]) * 1000) / 1000,
                clear_behind_m=math.floor(float(behind[k]) * 1000) / 1000,
            )
    return tuple(sorted(poses.values(), key=lambda p: (-p.clear_ahead_m, p.x_m, p.y_m)))
