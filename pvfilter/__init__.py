"""The Pitch Variation Filter: removes floor and ceiling clusters from 2D LiDAR scans.

numpy and scipy only; no simulator inside. See :class:`PitchVariationFilter`.
"""

from pvfilter.clustering import ClusterSet, cluster_scan
from pvfilter.detection import Detection, detect_clusters
from pvfilter.params import FilterParams
from pvfilter.pipeline import (
    ClusterRecord,
    FilterResult,
    PitchVariationFilter,
    StampWentBackWarning,
)
from pvfilter.scan import Scan
from pvfilter.threaded import ThreadedPitchVariationFilter
from pvfilter.tracking import Tracker, TrackingQueue

__all__ = [
    "ClusterRecord",
    "ClusterSet",
    "Detection",
    "FilterParams",
    "FilterResult",
    "PitchVariationFilter",
    "Scan",
    "StampWentBackWarning",
    "ThreadedPitchVariationFilter",
    "Tracker",
    "TrackingQueue",
    "cluster_scan",
    "detect_clusters",
]
