"""The headline metrics: Chamfer distance (eq. 6), per-beam PR and AUC, ATE (eq. 7), TUM files.

Computed as the project's design states, so numbers compare across tools. Chamfer distance
lives here; the others in :mod:`pvfilter.precision_recall` (the robot-side library scores
labelled scan files with it), :mod:`scaneval.trajectory` and :mod:`scaneval.tum`,
re-exported.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike
from scipy.spatial import cKDTree

from pvfilter.precision_recall import (
    PrCurve,
    auc_pr,
    confusion_counts,
    pr_curve,
    precision_recall,
    precision_recall_from_counts,
)
from scaneval.match_result import finite_points
from scaneval.trajectory import AteResult, associate, ate, umeyama
from scaneval.tum import read_tum, se2_from_xyz_quat, write_tum, xyz_quat_from_se2


def chamfer_distance(a_xy: ArrayLike, b_xy: ArrayLike) -> float:
    """Chamfer distance of eq. 6 between two point sets, m^2.

    The mean over ``a`` of the squared distance to the nearest point of ``b``, plus the
    same from ``b`` to ``a``. Rows with a non-finite coordinate are ignored. Align the sets
    first (e.g. ``transform_points(source, match.pose)`` against ``target``).

    Returns:
        The distance, m^2; NaN when either set has no finite point.
    """
    a, b = finite_points(a_xy), finite_points(b_xy)
    if len(a) == 0 or len(b) == 0:
        return float("nan")
    a_to_b, _ = cKDTree(b).query(a)
    b_to_a, _ = cKDTree(a).query(b)
    return float(np.mean(a_to_b**2) + np.mean(b_to_a**2))


__all__ = [
    "AteResult",
    "PrCurve",
    "associate",
    "ate",
    "auc_pr",
    "chamfer_distance",
    "confusion_counts",
    "pr_curve",
    "precision_recall",
    "precision_recall_from_counts",
    "read_tum",
    "se2_from_xyz_quat",
    "umeyama",
    "write_tum",
    "xyz_quat_from_se2",
]
