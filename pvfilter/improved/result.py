"""The improved filter's result: the contract's three arrays, and the line detection."""

from __future__ import annotations

import dataclasses
import functools

import numpy as np

from pvfilter.clusters import ClusterView
from pvfilter.improved.detection import LineDetection
from pvfilter.result import FilterResult, without_removed


@dataclasses.dataclass(frozen=True, eq=False)  # holds an array: no field-wise ==
class LineRecord:
    """One cluster of the improved filter (a segment, or the IMU's floor points).

    Attributes:
        indices: its beams, ascending.
        centroid: (x, y) in the sensor frame, m.
        size: number of points.
        passes_gates: its segment passes the geometry gates of a floor line.
        share_new: share of its points in space the level view saw as free.
        score: its segment's score (see :class:`LineDetection`).
        detected: ``score > p_th``: its beams were removed.
    """

    indices: np.ndarray
    centroid: tuple[float, float]
    size: int
    passes_gates: bool
    share_new: float
    score: float
    detected: bool


@dataclasses.dataclass(frozen=True, eq=False)
class ImprovedResult(FilterResult):
    """The improved filter's output for one scan.

    Attributes:
        scan: the input scan with removed beams set to NaN (same length).
        removed: bool per beam: ``scores > p_th``.
        scores: per beam, the claim score: the best score of the lines that take the beam
            in (``SILENT_VIEW_WEIGHT``, 0.8, of it where the level view is free by silence
            alone), at least ``new_return_score`` (0.01) on a new return
            (:mod:`pvfilter.improved.clusters`); the beam is removed exactly when it
            exceeds ``p_th``, whatever ``p_th``.
        lines: the per-cluster and per-beam detail.
    """

    lines: LineDetection

    @property
    def level_view_m(self) -> np.ndarray:
        """Per beam, where the level view the scan was compared with lies along it, m
        (NaN unknown, ``+inf`` free up to ``range_max``): see
        :attr:`LineDetection.level_view_m <pvfilter.improved.clusters.LineDetection>`."""
        return self.lines.level_view_m

    @functools.cached_property
    def clusters(self) -> tuple[LineRecord, ...]:
        """One record per cluster, in cluster order (built on first access)."""
        d, clusters = self.lines, self.lines.clusters
        columns = zip(
            clusters.beam_indices(),
            clusters.centroids.tolist(),
            clusters.sizes.tolist(),
            d.passes_gates.tolist(),
            d.share_new.tolist(),
            d.scores.tolist(),
            d.detected.tolist(),
            strict=True,
        )
        return tuple(LineRecord(i, tuple(c), *rest) for i, c, *rest in columns)

    def cluster_view(self) -> ClusterView:
        """The clusters, their scores and decisions, for a viewer (no tracking)."""
        d = self.lines
        return ClusterView(d.clusters, d.scores, d.detected, np.zeros(len(d.clusters), bool))


def removal(detection: LineDetection) -> ImprovedResult:
    """The filter's result: the beams whose claim score exceeds ``p_th`` become NaN.

    The per-beam scores are the claim scores: a beam's score exceeds ``p_th`` exactly when
    it is removed, whatever ``p_th``. Above ``new_return_score`` those are the beams of the
    detected clusters; a ``p_th`` below it removes every new return too, in a cluster or
    not.
    """
    removed = detection.claim_scores > detection.p_th
    filtered = without_removed(detection.scan, removed)
    return ImprovedResult(filtered, removed, detection.claim_scores, detection)
