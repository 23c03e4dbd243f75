"""The Pitch Variation Filter: removes floor and ceiling clusters from 2D LiDAR scans.

numpy and scipy only; no simulator inside. See :class:`PitchVariationFilter` (the paper's
filter, Table I defaults) and :class:`ImprovedPitchVariationFilter` (the improved filter,
same API; :func:`load_params` reads the parameter files ``twsb tune`` writes).
"""

from pvfilter.clustering import ClusterSet, cluster_scan
from pvfilter.detection import Detection, detect_clusters
from pvfilter.improved import ImprovedParams, ImprovedPitchVariationFilter
from pvfilter.params import FilterParams
from pvfilter.params_file import load_params, save_params
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
    "ImprovedParams",
    "ImprovedPitchVariationFilter",
    "PitchVariationFilter",
    "Scan",
    "StampWentBackWarning",
    "ThreadedPitchVariationFilter",
    "Tracker",
    "TrackingQueue",
    "cluster_scan",
    "detect_clusters",
    "load_params",
    "save_params",
]
