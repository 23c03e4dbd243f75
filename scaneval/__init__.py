"""Scan-matching, metrics and baseline filters for evaluating pitch-variation filtering.

numpy and scipy only (and :mod:`pvfilter` for the scan type), so it runs on real robot
data as well as on the simulator's: :mod:`scaneval.geometry` (SE(2) poses, scan points),
:mod:`scaneval.matching` (ICP, NDT, HSM), :mod:`scaneval.metrics` (Chamfer distance,
per-beam PR and AUC, ATE, TUM files) and :mod:`scaneval.baselines` (filters to compare
with: no filter, a DATMO-like tracker, an IMU height gate).
"""

from scaneval.baselines import (
    DatmoLikeFilter,
    DatmoParams,
    ImuGateParams,
    ImuHeightGate,
    NoFilter,
)
from scaneval.geometry import compose, invert, scan_points, se2_matrix, transform_points
from scaneval.matching import MATCHERS, MatchResult, hsm, icp, ndt
from scaneval.metrics import (
    AteResult,
    PrCurve,
    ate,
    auc_pr,
    chamfer_distance,
    pr_curve,
    precision_recall,
    read_tum,
    write_tum,
)

__all__ = [
    "MATCHERS",
    "AteResult",
    "DatmoLikeFilter",
    "DatmoParams",
    "ImuGateParams",
    "ImuHeightGate",
    "MatchResult",
    "NoFilter",
    "PrCurve",
    "ate",
    "auc_pr",
    "chamfer_distance",
    "compose",
    "hsm",
    "icp",
    "invert",
    "ndt",
    "pr_curve",
    "precision_recall",
    "read_tum",
    "scan_points",
    "se2_matrix",
    "transform_points",
    "write_tum",
]
