"""Pitch-variation filters: remove floor and ceiling hits from 2D LiDAR scans.

numpy and scipy only; no simulator inside. Two sibling filters keep one contract
(:class:`ScanFilter`: ``process(scan, *, robot inputs) -> FilterResult`` and ``reset()``):

- :class:`PitchVariationFilter`, the paper's filter with Table I defaults
  (:mod:`pvfilter.paper`, registered as ``paper``);
- :class:`ImprovedPitchVariationFilter`, the improved filter (:mod:`pvfilter.improved`,
  registered as ``improved``).

Every filter is found by name in one registry (:func:`make_filter`, :func:`filter_names`,
:func:`register_filter`); :func:`load_params` reads the parameter files that name them.
"""

__version__ = "0.1.0"  # the robot distribution (packages/pvfilter) reads it from here

from pvfilter.clusters import ClusterSet, ClusterView
from pvfilter.contract import ROBOT_INPUTS, ScanFilter
from pvfilter.improved import ImprovedParams, ImprovedPitchVariationFilter, ImprovedResult
from pvfilter.improved.imu import ImuSignWarning
from pvfilter.paper import (
    ClusterRecord,
    Detection,
    FilterParams,
    PaperResult,
    PitchVariationFilter,
    ThreadedPitchVariationFilter,
    Tracker,
    TrackingQueue,
    cluster_scan,
    detect_clusters,
)
from pvfilter.params_file import load_params, save_params
from pvfilter.registry import (
    FilterEntry,
    filter_entry,
    filter_for,
    filter_names,
    make_filter,
    register_filter,
)
from pvfilter.result import FilterResult
from pvfilter.scan import Scan
from pvfilter.stamps import ScansApartWarning, StampWentBackWarning

__all__ = [
    "ROBOT_INPUTS",
    "ClusterRecord",
    "ClusterSet",
    "ClusterView",
    "Detection",
    "FilterEntry",
    "FilterParams",
    "FilterResult",
    "ImprovedParams",
    "ImprovedPitchVariationFilter",
    "ImprovedResult",
    "ImuSignWarning",
    "PaperResult",
    "PitchVariationFilter",
    "Scan",
    "ScanFilter",
    "ScansApartWarning",
    "StampWentBackWarning",
    "ThreadedPitchVariationFilter",
    "Tracker",
    "TrackingQueue",
    "cluster_scan",
    "detect_clusters",
    "filter_entry",
    "filter_for",
    "filter_names",
    "load_params",
    "make_filter",
    "register_filter",
    "save_params",
]
