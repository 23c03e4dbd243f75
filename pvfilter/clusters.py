"""Clusters of a scan's points, as every clustering filter describes them.

Both filters group a scan's beams into clusters and decide per cluster: the paper's
filter its BFS seed clusters (:mod:`pvfilter.paper.clustering`), the improved filter its
line segments (:mod:`pvfilter.improved.segmentation`). :class:`ClusterSet` holds the
geometry both share; :class:`ClusterView` the decisions a viewer shows for either.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from pvfilter.scan import Scan


@dataclasses.dataclass(frozen=True, eq=False)  # holds arrays: no field-wise ==
class ClusterSet:
    """The clusters of one scan.

    Attributes:
        scan: the scan that was clustered.
        points: sensor-frame point of every beam, m, shape ``(n, 2)``; NaN where invalid.
        labels: cluster id of every beam, shape ``(n,)``; -1 where the beam is in none.
        sizes: points per cluster, shape ``(k,)``.
        centroids: mean point (x_C, y_C) per cluster, sensor frame, m, shape ``(k, 2)``.
        variances: population variances (v_x, v_y) of each cluster's points, m^2,
            shape ``(k, 2)``.
    """

    scan: Scan
    points: np.ndarray
    labels: np.ndarray
    sizes: np.ndarray
    centroids: np.ndarray
    variances: np.ndarray

    def __len__(self) -> int:
        return int(self.sizes.size)

    def beam_indices(self) -> list[np.ndarray]:
        """Ascending beam indices of every cluster, in cluster order."""
        order = np.argsort(self.labels, kind="stable")
        ends = np.cumsum(self.sizes)
        return np.split(order[order.size - ends[-1] :], ends[:-1]) if len(self) else []


@dataclasses.dataclass(frozen=True, eq=False)
class ClusterView:
    """What a viewer shows of a filter's clusters in one scan, whichever filter it was.

    Attributes:
        clusters: the clusters.
        scores: per cluster, the filter's score (its ``P(C_pv)`` or equivalent; NaN where
            the filter did not score the cluster).
        detected: per cluster, removed on this scan's own evidence.
        tracked: per cluster, removed because it continues a removed cluster of an earlier
            scan (all False for filters without tracking).
    """

    clusters: ClusterSet
    scores: np.ndarray
    detected: np.ndarray
    tracked: np.ndarray


def perpendicular_variance_ratio(variances: np.ndarray) -> np.ndarray:
    """Eq. 1 of the paper: ``v_C = v_y / (v_x + v_y)`` per cluster; 0 where both are 0.

    Args:
        variances: (v_x, v_y) per cluster, m^2, shape ``(k, 2)``.
    """
    total = variances.sum(axis=1)
    ratio = np.zeros(len(variances))
    np.divide(variances[:, 1], total, out=ratio, where=total > 0.0)
    return ratio
