"""A Hector-style 2D SLAM: multi-resolution occupancy maps and Gauss-Newton scan-to-map
matching, with no odometry (Kohlbrecher, von Stryk, Meyer and Klingauf, "A flexible and
scalable SLAM system with full 3D motion estimation", SSRR 2011).

Each scan is matched against the coarsest map first, and the result seeds the match on
the next finer map (§IV-C); the first guess is the previous pose, as in ``hector_mapping``
without odometry. The maps are updated from the matched pose when the sensor has moved or
turned enough since the last update. No loop closure: like Hector, this is a front end.

A health check that Hector itself lacks makes failure visible: when too few points land
on known obstacles after matching (or no match is possible) for several scans in a row,
the SLAM declares itself lost (``HectorSlam.lost``) and keeps going.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from pvfilter.scan import Scan
from scaneval.geometry import scan_points
from scaneval.slam.grid import OccupancyGrid
from scaneval.slam.scan_to_map import ScanToMapResult, match_scan_to_map


@dataclasses.dataclass(frozen=True)
class HectorParams:
    """Parameters of :class:`HectorSlam`; ``hector_mapping``'s names and defaults in brackets.

    Attributes:
        resolution_m: cell size of the finest map, m [map_resolution 0.05].
        levels: number of maps; level ``k`` has cells ``2**k`` times the finest
            [map_multi_res_levels 3].
        map_size_m: side of the square maps, m, centred on the first pose; points beyond
            are not mapped [map_size 1024 cells].
        p_free: occupancy probability of a cell a beam passes through [update_factor_free 0.4].
        p_occupied: occupancy probability of the cell a beam ends in
            [update_factor_occupied 0.9].
        update_distance_m: the maps are updated once the sensor has moved this far since
            the last update, m [map_update_distance_thresh 0.4].
        update_angle_rad: ... or turned this much, rad [map_update_angle_thresh 0.06].
        range_min_m, range_max_m: beams outside these ranges are not used, m
            [laser_min_dist 0.4, laser_max_dist 30].
        iterations_fine: Gauss-Newton steps on the finest map (hector: 5).
        iterations_coarse: Gauss-Newton steps on every coarser map (hector: 3).
        max_rotation_step_rad: largest rotation of one step, rad (hector: 0.2).
        min_points: fewer usable points than this and the scan is not matched.
        lost_inlier_fraction: a match is poor when fewer than this share of the points
            land on known obstacles.
        lost_after_scans: that many poor or impossible matches in a row and the SLAM is
            lost (1 s at 10 Hz).
    """

    resolution_m: float = 0.05
    levels: int = 3
    map_size_m: float = 60.0
    p_free: float = 0.4
    p_occupied: float = 0.9
    update_distance_m: float = 0.4
    update_angle_rad: float = 0.06
    range_min_m: float = 0.4
    range_max_m: float = 30.0
    iterations_fine: int = 5
    iterations_coarse: int = 3
    max_rotation_step_rad: float = 0.2
    min_points: int = 20
    lost_inlier_fraction: float = 0.2
    lost_after_scans: int = 10

    def __post_init__(self) -> None:
        if self.resolution_m <= 0.0:
            raise ValueError(
                f"resolution_m: expected a positive cell size, got {self.resolution_m}"
            )
        if self.levels < 1:
            raise ValueError(f"levels: expected at least 1, got {self.levels}")
        if self.map_size_m <= self.resolution_m * 2**self.levels:
            raise ValueError(f"map_size_m: too small for the coarsest map, got {self.map_size_m}")
        if not 0.0 < self.p_free < 0.5:
            raise ValueError(f"p_free: expected a value in (0, 0.5), got {self.p_free}")
        if not 0.5 < self.p_occupied < 1.0:
            raise ValueError(f"p_occupied: expected a value in (0.5, 1), got {self.p_occupied}")
        if not 0.0 <= self.range_min_m < self.range_max_m:
            raise ValueError(
                f"range_min_m, range_max_m: need 0 <= min < max, got "
                f"{self.range_min_m}, {self.range_max_m}"
            )
        if self.iterations_fine < 1 or self.iterations_coarse < 0:
            raise ValueError("iterations_fine, iterations_coarse: need >= 1 and >= 0")
        if self.min_points < 3:
            raise ValueError(f"min_points: expected at least 3, got {self.min_points}")
        if self.lost_after_scans < 1:
            raise ValueError(f"lost_after_scans: expected at least 1, got {self.lost_after_scans}")


@dataclasses.dataclass(frozen=True)
class SlamUpdate:
    """What one scan did to the SLAM.

    Attributes:
        pose: the sensor's pose in the map after this scan, ``(x, y, psi)``, m, m, rad.
        matched: the scan was matched (enough points, a non-degenerate match).
        map_updated: the maps integrated this scan.
        inlier_fraction: share of the scan's points on known obstacles after matching.
        points: usable points in the scan.
        lost: the SLAM is lost (at this scan or before).
    """

    pose: np.ndarray
    matched: bool
    map_updated: bool
    inlier_fraction: float
    points: int
    lost: bool


class HectorSlam:
    """Hector-style 2D SLAM over a stream of scans (see the module docstring).

    The map frame is the sensor frame of the first scan.

    Example::

        slam = HectorSlam()
        for scan in scans:
            update = slam.process_scan(scan)       # or slam.process(points_xy)
        slam.pose, slam.maps[0].probability()
    """

    def __init__(self, params: HectorParams | None = None) -> None:
        self.params = params or HectorParams()
        self.reset()

    def reset(self) -> None:
        """Start over: empty maps, the pose at the origin."""
        p = self.params
        self.maps = [
            OccupancyGrid(p.resolution_m * 2**k, p.map_size_m, (0.0, 0.0), p.p_free, p.p_occupied)
            for k in range(p.levels)
        ]
        self.pose = np.zeros(3)
        self.scans = 0
        self.lost = False
        self.lost_at_scan: int | None = None
        self._poor_in_a_row = 0
        self._last_update_pose: np.ndarray | None = None

    def process_scan(self, scan: Scan, removed: np.ndarray | None = None) -> SlamUpdate:
        """:meth:`process` the valid beams of a scan, minus those a filter ``removed``."""
        return self.process(scan_points(scan, removed))

    def process(self, points_xy: np.ndarray) -> SlamUpdate:
        """Match one scan to the maps, then update the maps if the sensor moved enough.

        Args:
            points_xy: beam end points in the sensor frame, m, shape ``(n, 2)``; rows with
                a non-finite value, or out of the range limits, are ignored.

        Returns:
            The :class:`SlamUpdate`; the new pose is also ``self.pose``.
        """
        p = self.params
        points = np.asarray(points_xy, dtype=np.float64).reshape(-1, 2)
        with np.errstate(invalid="ignore"):
            ranges = np.hypot(points[:, 0], points[:, 1])
            points = points[(ranges >= p.range_min_m) & (ranges <= p.range_max_m)]
        first = self._last_update_pose is None
        matched, inliers = False, 0.0
        if not first and len(points) >= p.min_points:
            result = self._match(points)
            matched, inliers = result.ok, result.inlier_fraction
            if result.ok:
                self.pose = result.pose
        poor = not first and (not matched or inliers < p.lost_inlier_fraction)
        self._poor_in_a_row = self._poor_in_a_row + 1 if poor else 0
        if self._poor_in_a_row >= p.lost_after_scans and not self.lost:
            self.lost, self.lost_at_scan = True, self.scans
        map_updated = len(points) >= p.min_points and (first or self._moved_enough())
        if map_updated:
            self._update_maps(points)
        self.scans += 1
        return SlamUpdate(
            pose=self.pose.copy(),
            matched=matched,
            map_updated=map_updated,
            inlier_fraction=inliers,
            points=len(points),
            lost=self.lost,
        )

    def _match(self, points: np.ndarray) -> ScanToMapResult:
        """Coarse to fine: each level starts from the pose the coarser one found."""
        p = self.params
        pose, result = self.pose, None
        for level in range(p.levels - 1, -1, -1):
            result = match_scan_to_map(
                self.maps[level],
                points,
                pose,
                iterations=p.iterations_fine if level == 0 else p.iterations_coarse,
                max_rotation_step_rad=p.max_rotation_step_rad,
            )
            if not result.ok:
                return result
            pose = result.pose
        assert result is not None
        return result

    def _moved_enough(self) -> bool:
        last = self._last_update_pose
        assert last is not None
        turned = abs((self.pose[2] - last[2] + math.pi) % (2.0 * math.pi) - math.pi)
        moved = math.hypot(self.pose[0] - last[0], self.pose[1] - last[1])
        return moved >= self.params.update_distance_m or turned >= self.params.update_angle_rad

    def _update_maps(self, points: np.ndarray) -> None:
        c, s = math.cos(self.pose[2]), math.sin(self.pose[2])
        world = points @ np.array([[c, s], [-s, c]]) + self.pose[:2]
        for grid in self.maps:
            grid.update(self.pose[:2], world)
        self._last_update_pose = self.pose.copy()
