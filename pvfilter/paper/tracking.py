"""Tracking module (paper III-E, Algorithm 2): follow pitch-variation clusters over scans.

Pitch-variation clusters are not objects that move but artefacts that deform and shift
until the robot is level again, and after the first scan the likelihood field no longer
flags them. So each seed cluster of scan t is associated with the nearest cluster (by
centroid, in the sensor frame) of the previous tracking queue Q^{t-1}, and stays in the
queue when it passes every check:

1. the nearest queued centroid is at most ``d_track`` away;
2. ``v_C >= v_th`` (the same gate as detection);
3. its centroid's range is in ``[d_min, d_max]``;
4. its size over the associated cluster's size is in ``[size_ratio_min, size_ratio_max]``
   (Table I: Delta m_th = (m/2, 2m); the bounds are included here).

The clusters detected in scan t join the queue too (Algorithm 2, line 15). Every cluster in
Q^t is removed from scan t and is what scan t+1 is associated with.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from pvfilter.paper.detection import Detection
from pvfilter.paper.params import FilterParams


@dataclasses.dataclass(frozen=True, eq=False)
class TrackingQueue:
    """The tracking queue Q^t as the next scan sees it.

    Attributes:
        centroids: centroid of every queued cluster, sensor frame, m, shape ``(q, 2)``.
        sizes: points of every queued cluster, shape ``(q,)``.
    """

    centroids: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros((0, 2)))
    sizes: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros(0, dtype=np.intp))

    def __len__(self) -> int:
        return int(self.sizes.size)


def associate(
    centroids: np.ndarray,
    sizes: np.ndarray,
    v_c: np.ndarray,
    queue: TrackingQueue,
    params: FilterParams,
) -> np.ndarray:
    """Algorithm 2, lines 2-14: which clusters continue a queued cluster.

    Args:
        centroids: centroid per current cluster, m, shape ``(k, 2)``.
        sizes: points per current cluster, shape ``(k,)``.
        v_c: eq. 1 per current cluster.
        queue: the previous queue Q^{t-1}.
        params: ``d_track``, ``v_th``, ``d_min``, ``d_max`` and the size ratios are used.

    Returns:
        bool per current cluster: True where it passes all four checks.
    """
    k = len(sizes)
    if k == 0 or len(queue) == 0:
        return np.zeros(k, dtype=bool)
    gaps = np.linalg.norm(centroids[:, None, :] - queue.centroids[None, :, :], axis=2)
    nearest = np.argmin(gaps, axis=1)  # ties go to the first queued cluster
    close = gaps[np.arange(k), nearest] <= params.d_track
    line = v_c >= params.v_th
    radius = np.linalg.norm(centroids, axis=1)
    in_band = (radius >= params.d_min) & (radius <= params.d_max)
    ratio = sizes / queue.sizes[nearest]
    consistent = (ratio >= params.size_ratio_min) & (ratio <= params.size_ratio_max)
    return close & line & in_band & consistent


class Tracker:
    """Holds the tracking queue between scans and updates it per scan (Algorithm 2)."""

    def __init__(self, params: FilterParams) -> None:
        self.params = params
        self.queue = TrackingQueue()

    def reset(self) -> None:
        """Empty the queue (a new sequence starts)."""
        self.queue = TrackingQueue()

    def update(self, detection: Detection) -> np.ndarray:
        """Associate this scan's clusters with the queue, then replace the queue by Q^t.

        Args:
            detection: Algorithm 1's output for the scan; when its ``new_sequence`` is set,
                the queue is emptied first.

        Returns:
            bool per cluster: True where the cluster was tracked (it continues a queued
            cluster). Q^t holds the tracked and the detected clusters.
        """
        if detection.new_sequence:
            self.reset()
        clusters = detection.clusters
        tracked = associate(
            clusters.centroids, clusters.sizes, detection.v_c, self.queue, self.params
        )
        queued = tracked | detection.detected
        self.queue = TrackingQueue(clusters.centroids[queued], clusters.sizes[queued])
        return tracked
