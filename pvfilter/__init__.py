"""The Pitch Variation Filter: removes floor and ceiling clusters from 2D LiDAR scans.

numpy and scipy only; no simulator inside.
"""

from pvfilter.scan import Scan

__all__ = ["Scan"]
