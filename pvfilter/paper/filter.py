"""The paper's Pitch Variation Filter: cluster -> detect -> track -> remove, one scan at a time.

History between scans is the previous scan's KD-tree (the likelihood field) and the
tracking queue, both in sensor-frame coordinates. Robustness, by design:

- empty and all-invalid scans give an empty result of the same length and become the
  previous scan (with no points, so the next scan has no likelihood field);
- a scan whose beam count or angles differ from the previous one is processed normally:
  the history holds points and centroids, not beam indices, so it stays meaningful;
- a stamp earlier than the previous scan's resets the history (the scan starts a new
  sequence) and emits a :class:`pvfilter.StampWentBackWarning`; equal stamps are accepted.
"""

from __future__ import annotations

import dataclasses
import functools

import numpy as np
from numpy.typing import ArrayLike
from scipy.spatial import cKDTree

from pvfilter.clusters import ClusterView
from pvfilter.contract import check_scan, params_or_defaults
from pvfilter.paper.clustering import cluster_scan
from pvfilter.paper.detection import Detection, detect_clusters
from pvfilter.paper.params import FilterParams
from pvfilter.paper.tracking import Tracker
from pvfilter.result import FilterResult, without_removed
from pvfilter.scan import Scan
from pvfilter.stamps import stamp_went_back


@dataclasses.dataclass(frozen=True, eq=False)  # holds an array: no field-wise ==
class ClusterRecord:
    """One seed cluster of a scan and what the filter decided about it.

    Attributes:
        indices: its beams, ascending.
        centroid: (x_C, y_C) in the sensor frame, m.
        size: number of points N.
        v_c: perpendicular variance ratio (eq. 1).
        p_theta: angular confidence P(theta_C) (eq. 2).
        p_likelihood: likelihood P(L_C) (eq. 4); NaN when skipped by the ``v_th`` gate.
        p_pv: P(C_pv) (eq. 5); NaN when skipped by the ``v_th`` gate.
        detected: ``P(C_pv) > p_th`` in this scan (Algorithm 1).
        tracked: continues a cluster of the previous tracking queue (Algorithm 2).
    """

    indices: np.ndarray
    centroid: tuple[float, float]
    size: int
    v_c: float
    p_theta: float
    p_likelihood: float
    p_pv: float
    detected: bool
    tracked: bool

    @property
    def removed(self) -> bool:
        """The cluster is in the tracking queue Q^t, so its beams were removed."""
        return self.detected or self.tracked


@dataclasses.dataclass(frozen=True, eq=False)
class PaperResult(FilterResult):
    """The paper filter's output for one scan.

    Attributes:
        scan: the input scan with removed beams set to NaN (same length).
        removed: bool per beam: its cluster is in the tracking queue Q^t.
        scores: P(C_pv) of the beam's cluster per beam; 0 where the beam is in no
            cluster or its cluster was skipped by the ``v_th`` gate.
        detection: Algorithm 1's per-cluster arrays (and the seed clusters themselves).
        tracked: bool per cluster: continued a queued cluster (Algorithm 2).
    """

    detection: Detection
    tracked: np.ndarray

    @functools.cached_property
    def clusters(self) -> tuple[ClusterRecord, ...]:
        """One record per seed cluster, in order of first beam (built on first access)."""
        d, clusters = self.detection, self.detection.clusters
        columns = zip(
            clusters.beam_indices(),
            clusters.centroids.tolist(),
            clusters.sizes.tolist(),
            *(a.tolist() for a in (d.v_c, d.p_theta, d.p_likelihood, d.p_pv)),
            d.detected.tolist(),
            self.tracked.tolist(),
            strict=True,
        )
        return tuple(ClusterRecord(i, tuple(c), *rest) for i, c, *rest in columns)

    def cluster_view(self) -> ClusterView:
        """The seed clusters, P(C_pv), detected and tracked, for a viewer."""
        d = self.detection
        return ClusterView(d.clusters, d.p_pv, d.detected, np.asarray(self.tracked, dtype=bool))


def remove_queued(detection: Detection, tracked: np.ndarray) -> PaperResult:
    """Set the beams of every queued (detected or tracked) cluster to NaN.

    Args:
        detection: Algorithm 1's output for the scan.
        tracked: bool per cluster from Algorithm 2.
    """
    labels = detection.clusters.labels
    # label -1 (no cluster) indexes the appended last entry: not removed, score 0
    removed = np.append(detection.detected | tracked, False)[labels]
    scores = np.append(np.nan_to_num(detection.p_pv, nan=0.0), 0.0)[labels]
    filtered = without_removed(detection.clusters.scan, removed)
    return PaperResult(filtered, removed, scores, detection, tracked)


class PitchVariationFilter:
    """The Pitch Variation Filter (Kim, Lee and Choi), run sequentially, one scan per call.

    Args:
        params: the parameters; Table I defaults when omitted.
    """

    def __init__(self, params: FilterParams | None = None) -> None:
        self.params = params_or_defaults(params, FilterParams, "PitchVariationFilter")
        self._tracker = Tracker(self.params)
        self._previous_tree: cKDTree | None = None  # T_kd^{t-1}
        self._previous_stamp: float | None = None
        self._new_sequence = True

    def reset(self) -> None:
        """Forget the history: the next scan starts a new sequence."""
        self._new_sequence = True
        self._previous_stamp = None

    def process(
        self,
        scan: Scan,
        *,
        pitch_rad: float | None = None,
        roll_rad: float | None = None,
        pose_sensor_in_odom: ArrayLike | None = None,
    ) -> PaperResult:
        """Filter one scan; call once per scan, in time order.

        Args:
            scan: the scan at time t.
            pitch_rad: ignored: the paper's filter uses the scan alone.
            roll_rad: ignored.
            pose_sensor_in_odom: ignored.

        Returns:
            The filtered scan, the removed-beam mask, per-beam scores, per-cluster records.
        """
        check_scan(scan)
        # the paper runs these two halves in two threads (see pvfilter.threaded)
        return self.track_and_remove(self.cluster_and_detect(scan))

    def cluster_and_detect(self, scan: Scan) -> Detection:
        """First half (preprocessing and detection modules): the paper's first thread."""
        new_sequence = self._start(scan)
        # cluster: BFS over points within d_th, drop clusters under m_th, build T_kd^t
        clusters = cluster_scan(scan, self.params)
        # detect (Algorithm 1): v_C gate, then P(C_pv) = 1 - P(theta_C) P(L_C) > p_th
        detection = detect_clusters(clusters, self._previous_tree, self.params, new_sequence)
        # this scan is the likelihood field of the next one
        self._previous_tree = clusters.tree
        return detection

    def track_and_remove(self, detection: Detection) -> PaperResult:
        """Second half (tracking module and removal): the paper's second thread."""
        # track (Algorithm 2): follow queued clusters; detections join the queue
        if self.params.tracking:
            tracked = self._tracker.update(detection)
        else:  # detection only: nothing carries over between scans
            tracked = np.zeros(len(detection.clusters), dtype=bool)
        # remove: the beams of every queued cluster become NaN
        return remove_queued(detection, tracked)

    def _start(self, scan: Scan) -> bool:
        """Note the scan's stamp; True when it starts a new sequence (history dropped)."""
        if stamp_went_back(scan.stamp, self._previous_stamp, stacklevel=4):
            self._new_sequence = True
        new_sequence, self._new_sequence = self._new_sequence, False
        if new_sequence:
            self._previous_tree = None
        self._previous_stamp = scan.stamp
        return new_sequence
