"""Preprocessing module (paper III-C): distance-based BFS clustering and the scan's KD-tree.

The paper groups points "within a predefined d_th" by breadth-first search, "starting from
the first index of z^t", selecting "a new cluster starting point" when the condition
fails. It does not say which points are a point's neighbours, so both readings are here:

- ``"scan_order"`` (default): a point's neighbours are the previous and next valid points
  in beam order, so a cluster is a run of consecutive valid beams whose successive points
  are at most ``d_th`` apart. This is the default because it is what the paper's wording
  describes (a sweep from the first index that starts a new cluster when the distance
  condition fails), it is the classic jump-distance segmentation of a 2D scan, and it is
  linear in the number of beams.
- ``"radius"``: a point's neighbours are all points within ``d_th`` (Euclidean
  clustering): the connected components of the KD-tree's radius graph. It
  also joins points that are close in space but far apart in beam order, e.g. across a
  gap in the field of view.

Choices the paper leaves open, made the same way in both modes:

- Invalid beams (NaN, +/-inf, outside ``[range_min, range_max]``) are not points: they
  never join a cluster, and a cluster may span them when the points on either side are
  within ``d_th``.
- A scan whose beams cover a full turn is a ring: in ``"scan_order"`` the last valid
  point is a neighbour of the first, so a cluster straight behind the sensor (where a
  scan from -pi to pi has its seam) is not cut in two.
- Clusters with fewer than ``m_th`` points are dropped (size ``>= m_th`` is kept).

Cluster ids are numbered in the order of each cluster's first beam.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy.spatial import cKDTree

from pvfilter.clusters import ClusterSet
from pvfilter.paper.params import FilterParams
from pvfilter.scan import Scan


@dataclasses.dataclass(frozen=True, eq=False)
class SeedClusters(ClusterSet):
    """The seed clusters S_C^t of one scan (see :class:`pvfilter.ClusterSet`) and its KD-tree.

    Attributes:
        tree: KD-tree T_kd^t over the scan's valid points, in beam order: the likelihood
            field of the next scan (it may hold no points).
    """

    tree: cKDTree


def cluster_scan(scan: Scan, params: FilterParams) -> SeedClusters:
    """Cluster a scan's valid points (``d_th``, ``m_th``, ``clustering``) and build its KD-tree.

    Args:
        scan: the scan to cluster.
        params: the filter parameters.

    Returns:
        The clusters, with per-cluster size, centroid and variances, and the KD-tree.
    """
    points = scan.points()
    valid = np.flatnonzero(scan.valid_mask())
    valid_points = points[valid]
    # building without median balancing is faster, and queries on a 2D scan stay cheap
    tree = cKDTree(valid_points, balanced_tree=False, compact_nodes=False)
    if params.clustering == "radius":
        raw = radius_labels(tree, params.d_th)
    else:
        raw = scan_order_labels(valid_points, params.d_th, ring=covers_full_turn(scan))
    kept = drop_small_clusters(raw, params.m_th)
    labels = np.full(len(scan), -1, dtype=np.intp)
    labels[valid] = kept
    sizes, centroids, variances = _moments(valid_points, kept)
    return SeedClusters(scan, points, labels, sizes, centroids, variances, tree)


def covers_full_turn(scan: Scan) -> bool:
    """True when the gap from the last beam back to the first is at most two increments."""
    return (len(scan) + 1) * scan.angle_increment >= 2.0 * math.pi


def scan_order_labels(points: np.ndarray, d_th: float, ring: bool = False) -> np.ndarray:
    """Label runs of consecutive points whose successive distances are at most ``d_th``.

    Args:
        points: valid points in beam order, m, shape ``(m, 2)``.
        d_th: clustering distance, m.
        ring: the last point is also a neighbour of the first (a full-turn scan).

    Returns:
        Cluster id per point, shape ``(m,)``, numbered from 0 in beam order.
    """
    if len(points) == 0:
        return np.zeros(0, dtype=np.intp)
    steps = np.linalg.norm(np.diff(points, axis=0), axis=1)
    labels = np.concatenate(([0], np.cumsum(steps > d_th)))
    if ring and labels[-1] > 0 and np.linalg.norm(points[-1] - points[0]) <= d_th:
        labels[labels == labels[-1]] = 0  # the last run continues the first across the seam
    return labels


def radius_labels(tree: cKDTree, d_th: float) -> np.ndarray:
    """Label the connected components of the graph joining points at most ``d_th`` apart.

    Runs that are joined in scan order are joined here too, so the components are found
    over the few runs (min-label propagation with pointer jumping) rather than the points.

    Args:
        tree: KD-tree over the valid points, in beam order.
        d_th: clustering distance, m.

    Returns:
        Cluster id per point in the tree's order, numbered from 0 in order of first point.
    """
    runs = scan_order_labels(tree.data, d_th)
    pairs = runs[tree.query_pairs(d_th, output_type="ndarray")]
    pairs = pairs[pairs[:, 0] != pairs[:, 1]]  # links between different runs
    roots = np.arange(runs[-1] + 1 if len(runs) else 0)
    while True:
        lowest = roots[pairs].min(axis=1)
        joined = roots.copy()
        np.minimum.at(joined, pairs[:, 0], lowest)
        np.minimum.at(joined, pairs[:, 1], lowest)
        joined = joined[joined]  # pointer jumping: follow each root to its own root
        if np.array_equal(joined, roots):
            break
        roots = joined
    # every run now names the lowest run of its component; renumber those 0..k-1
    return np.unique(roots, return_inverse=True)[1][runs]


def drop_small_clusters(labels: np.ndarray, m_th: int) -> np.ndarray:
    """Set clusters with fewer than ``m_th`` points to -1 and renumber the rest 0..k-1.

    Args:
        labels: cluster id per point, numbered 0.. in order of first point.
        m_th: minimum cluster size, points.

    Returns:
        Cluster id per point, -1 for dropped points; the order of clusters is kept.
    """
    keep = np.bincount(labels) >= m_th
    renumbered = np.cumsum(keep) - 1
    return np.where(keep[labels], renumbered[labels], -1) if len(labels) else labels


def _moments(points: np.ndarray, labels: np.ndarray) -> tuple[np.ndarray, ...]:
    """Size, centroid and (v_x, v_y) per cluster; points labelled -1 are ignored."""
    member = labels >= 0
    points, labels = points[member], labels[member]
    k = int(labels.max()) + 1 if len(labels) else 0
    sizes = np.bincount(labels, minlength=k)
    centroids = np.empty((k, 2))
    variances = np.empty((k, 2))
    for axis in range(2):  # x then y; two passes keep the variance accurate far from 0
        centroids[:, axis] = np.bincount(labels, points[:, axis], k) / sizes
        offsets = points[:, axis] - centroids[labels, axis]
        variances[:, axis] = np.bincount(labels, offsets * offsets, k) / sizes
    return sizes, centroids, variances
