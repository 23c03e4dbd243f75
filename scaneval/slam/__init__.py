"""SLAM in the loop: a Hector-style 2D SLAM, and KISS-ICP driven by 2D scans.

numpy and scipy only (KISS-ICP is an optional extra), so both run on a real robot's scans
as well as the simulator's. :class:`HectorSlam` keeps multi-resolution occupancy maps
(:class:`OccupancyGrid`) and matches each scan to them by Gauss-Newton
(:func:`match_scan_to_map`); :class:`KissIcp2D` feeds the same scans to KISS-ICP as 3D
points at z = 0; :func:`score_trajectory` gives the ATE and says whether tracking failed.
"""

from scaneval.slam.grid import OccupancyGrid
from scaneval.slam.hector import HectorParams, HectorSlam, SlamUpdate
from scaneval.slam.kiss import KissIcp2D
from scaneval.slam.scan_to_map import ScanToMapResult, match_scan_to_map
from scaneval.slam.scoring import FAILURE_DISTANCE_M, TrajectoryScore, score_trajectory

__all__ = [
    "FAILURE_DISTANCE_M",
    "HectorParams",
    "HectorSlam",
    "KissIcp2D",
    "OccupancyGrid",
    "ScanToMapResult",
    "SlamUpdate",
    "TrajectoryScore",
    "match_scan_to_map",
    "score_trajectory",
]
