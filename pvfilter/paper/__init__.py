"""The paper's Pitch Variation Filter (Kim, Lee and Choi), Table I defaults.

One stage per module, as the paper's Fig. 2: :mod:`~pvfilter.paper.clustering`
(preprocessing), :mod:`~pvfilter.paper.detection` (Algorithm 1),
:mod:`~pvfilter.paper.tracking` (Algorithm 2), :mod:`~pvfilter.paper.filter` (the recipe,
sequential) and :mod:`~pvfilter.paper.threaded` (the paper's two-thread form).
"""

from pvfilter.paper.clustering import SeedClusters, cluster_scan
from pvfilter.paper.detection import Detection, detect_clusters
from pvfilter.paper.filter import ClusterRecord, PaperResult, PitchVariationFilter
from pvfilter.paper.params import CLUSTERING_MODES, FilterParams
from pvfilter.paper.threaded import ThreadedPitchVariationFilter
from pvfilter.paper.tracking import Tracker, TrackingQueue

__all__ = [
    "CLUSTERING_MODES",
    "ClusterRecord",
    "Detection",
    "FilterParams",
    "PaperResult",
    "PitchVariationFilter",
    "SeedClusters",
    "ThreadedPitchVariationFilter",
    "Tracker",
    "TrackingQueue",
    "cluster_scan",
    "detect_clusters",
]
