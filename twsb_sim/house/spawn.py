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

ROBOT_RADIUS_M = 0.25  # footprint radius of the robot (m)
OBSTACLE_TOP_M = 1.5  # parts whose bottom is lower than this block the robot (m)
FREE_MARGIN_M = 0.05  # extra gap between a spawned robot and the nearest obstacle (m)
GRID_STEP_M = 0.25  # spacing of the candidate start positions (m)
MAX_CLEARANCE_M = 50.0  # clearances are capped here (m)
MIN_REVERSE_M = 0.3  # a "lane start" pose keeps at least this much room behind (m)
YAWS = np.array([0.0, math.pi / 2, math.pi, -math.pi / 2])  # rad, the start headings tried
PRUNE_MARGIN_M = 1e-6  # m, bounding circles grown by this: far above rounding, never prunes a hit
RAY_BLOCK = 512  # rays tested at a time: the (ray, obstacle) arrays stay in the CPU's cache


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

    def _box_frames(self, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Points in every box's frame (N, M, 2), and the boxes' cos/sin of yaw (M,)."""
        c, s = np.cos(self.boxes[:, 4]), np.sin(self.boxes[:, 4])
        rel = xy[:, None, :] - self.boxes[None, :, :2]
        local = np.stack(
            (c * rel[..., 0] + s * rel[..., 1], -s * rel[..., 0] + c * rel[..., 1]), -1
        )
        return local, c, s

    def is_free(self, xy: np.ndarray, radius_m: float) -> np.ndarray:
        """Whether a disc of ``radius_m`` centred at each point (N, 2) touches nothing."""
        local, _, _ = self._box_frames(xy)
        within = np.abs(local) < self.boxes[None, :, 2:4] + radius_m
        inside_box = within[..., 0] & within[..., 1]  # cheaper than np.all along an axis of 2
        gap = np.linalg.norm(xy[:, None, :] - self.discs[None, :, :2], axis=-1)
        inside_disc = gap < self.discs[None, :, 2] + radius_m
        return ~(inside_box.any(axis=1) | inside_disc.any(axis=1))

    def clearance_m(self, xy: np.ndarray, yaw_rad: np.ndarray, radius_m: float) -> np.ndarray:
        """How far a disc of ``radius_m`` at each point (N, 2) can move along its heading
        (N,) before touching an obstacle (m, a lower bound, 0 if it already touches)."""
        heading = np.stack((np.cos(yaw_rad), np.sin(yaw_rad)), -1)
        # in blocks of rays: each ray's result is its own, and a few thousand rays at once
        # make (ray, obstacle) arrays of megabytes that are slower to fill than to compute
        blocks = [
            self._clearance_m(xy[i : i + RAY_BLOCK], heading[i : i + RAY_BLOCK], radius_m)
            for i in range(0, len(xy), RAY_BLOCK)
        ]
        return np.concatenate(blocks) if blocks else np.zeros(0)

    def _clearance_m(self, xy: np.ndarray, heading: np.ndarray, radius_m: float) -> np.ndarray:
        """:meth:`clearance_m` of points (N, 2) along unit headings (N, 2)."""
        box_t = self._box_clearance(xy, heading, radius_m)
        # disc-disc: solve |p + t d - c| = r_c + radius for the first t >= 0
        rel = xy[:, None, :] - self.discs[None, :, :2]
        b = np.einsum("nmk,nk->nm", rel, heading)
        cc = np.einsum("nmk,nmk->nm", rel, rel) - (self.discs[None, :, 2] + radius_m) ** 2
        disc = b**2 - cc
        root = -b - np.sqrt(np.maximum(disc, 0))
        disc_t = np.where(cc <= 0, 0.0, np.where((disc >= 0) & (root >= 0), root, np.inf))
        nearest = np.minimum(box_t, disc_t.min(axis=1, initial=np.inf))
        return np.minimum(nearest, MAX_CLEARANCE_M)

    def _box_clearance(self, xy: np.ndarray, heading: np.ndarray, radius_m: float) -> np.ndarray:
        """The slab test of each point (N, 2) and unit heading (N, 2) against every box
        inflated by ``radius_m``: the first t >= 0 on the ray inside one (m, inf if none).

        Only the (point, box) pairs whose ray passes within the box's bounding circle
        are tested, about a tenth of them in a house: a third of the time of testing all
        (each pair's arithmetic is the same, so are the results).
        """
        n = len(xy)
        half = self.boxes[:, 2:4] + radius_m  # (M, 2)
        # x and y as (N, M) arrays of their own: the same numbers, without the slow
        # strided passes over an (N, M, 2) array
        to_x = self.boxes[None, :, 0] - xy[:, None, 0]
        to_y = self.boxes[None, :, 1] - xy[:, None, 1]
        hx, hy = heading[:, None, 0], heading[:, None, 1]
        along = to_x * hx + to_y * hy
        across = to_y * hx - to_x * hy
        reach = np.hypot(half[:, 0], half[:, 1]) + PRUNE_MARGIN_M  # bounding circles (M,)
        ni, mi = np.nonzero((np.abs(across) <= reach) & (along >= -reach))
        c, s = np.cos(self.boxes[:, 4]), np.sin(self.boxes[:, 4])
        c, s = c[mi], s[mi]
        rel = xy[ni] - self.boxes[mi, :2]
        local = np.stack((c * rel[:, 0] + s * rel[:, 1], -s * rel[:, 0] + c * rel[:, 1]), -1)
        h = heading[ni]
        d_local = np.stack((c * h[:, 0] + s * h[:, 1], -s * h[:, 0] + c * h[:, 1]), -1)
        d_local = np.where(np.abs(d_local) < 1e-12, 1e-12, d_local)
        t1, t2 = (-half[mi] - local) / d_local, (half[mi] - local) / d_local
        near, far = np.minimum(t1, t2), np.maximum(t1, t2)
        # the larger (smaller) of two columns: a reduction along an axis of 2 costs more
        t_near = np.maximum(near[:, 0], near[:, 1])
        t_far = np.minimum(far[:, 0], far[:, 1])
        hit = np.where((t_near <= t_far) & (t_far >= 0), np.maximum(t_near, 0), np.inf)
        nearest = np.full(n, np.inf)
        np.minimum.at(nearest, ni, hit)
        return nearest


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
