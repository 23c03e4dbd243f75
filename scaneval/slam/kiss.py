"""KISS-ICP (Vizzo et al., RA-L 2023) driven by 2D scans, as its maintainers suggest:
the scan's points as 3D points at z = 0.

KISS-ICP is an optional dependency (``pip install "twsb-pvfilter[slam]"``); importing this
module works without it, constructing :class:`KissIcp2D` does not. KISS-ICP estimates a
full 3D pose; the planar pose is its translation in x, y and its heading, and
:attr:`KissIcp2D.max_out_of_plane_m` reports how far it strayed from the plane.
"""

from __future__ import annotations

import math

import numpy as np

from pvfilter.scan import Scan
from scaneval.geometry import scan_points

INSTALL_HINT = 'KISS-ICP is an optional extra: pip install "twsb-pvfilter[slam]" (or kiss-icp)'


class KissIcp2D:
    """KISS-ICP odometry over a stream of 2D scans.

    Args:
        max_range_m: points farther than this are dropped, m (the LiDAR's range).
        min_range_m: points nearer than this are dropped, m.
        voxel_size_m: the local map's voxel size, m; None takes KISS-ICP's own rule,
            ``max_range / 100``.
        threads: registration threads (0 = all cores).

    The pose frame is the sensor frame of the first scan. KISS-ICP keeps no global map and
    closes no loops: it is odometry, scored here as the paper scores a SLAM trajectory.
    """

    def __init__(
        self,
        max_range_m: float = 12.0,
        min_range_m: float = 0.0,
        voxel_size_m: float | None = None,
        threads: int = 1,
    ) -> None:
        try:
            from kiss_icp.config import KISSConfig
        except ImportError as error:
            raise ImportError(INSTALL_HINT) from error
        config = KISSConfig()
        config.data.max_range = float(max_range_m)
        config.data.min_range = float(min_range_m)
        config.data.deskew = False  # a scan is one instant here; there are no point stamps
        config.mapping.voxel_size = (
            float(voxel_size_m) if voxel_size_m is not None else max_range_m / 100.0
        )
        config.registration.max_num_threads = int(threads)
        self.config = config
        self.reset()

    def reset(self) -> None:
        """Start over: an empty local map, the pose at the origin."""
        from kiss_icp.kiss_icp import KissICP

        self._odometry = KissICP(self.config)
        self.pose = np.zeros(3)
        self.max_out_of_plane_m = 0.0  # largest |z| of the estimated pose so far
        self.lost = False  # set when KISS-ICP returns a non-finite pose
        self.lost_at_scan: int | None = None
        self.scans = 0

    def process_scan(self, scan: Scan, removed: np.ndarray | None = None) -> np.ndarray:
        """:meth:`process` the valid beams of a scan, minus those a filter ``removed``."""
        return self.process(scan_points(scan, removed))

    def process(self, points_xy: np.ndarray) -> np.ndarray:
        """Register one scan.

        Args:
            points_xy: end points in the sensor frame, m, shape ``(n, 2)``; non-finite
                rows are dropped.

        Returns:
            The sensor's planar pose ``(x, y, theta)`` after this scan, m, m, rad.
        """
        points = np.asarray(points_xy, dtype=np.float64).reshape(-1, 2)
        points = points[np.isfinite(points).all(axis=1)]
        cloud = np.column_stack((points, np.zeros(len(points))))
        self._odometry.register_frame(cloud, np.zeros(len(cloud)))
        matrix = self._odometry.last_pose
        if np.all(np.isfinite(matrix)):
            heading = math.atan2(matrix[1, 0], matrix[0, 0])
            self.pose = np.array([matrix[0, 3], matrix[1, 3], heading])
            self.max_out_of_plane_m = max(self.max_out_of_plane_m, abs(float(matrix[2, 3])))
        elif not self.lost:
            self.lost, self.lost_at_scan = True, self.scans
        self.scans += 1
        return self.pose.copy()
