"""Building the clusters of a scan from its scored segments and their claims.

The clusters are the detected segments (score above ``p_th``) with every point they
claimed, and the other segments of at least ``min_points`` points (with the points no
better line claimed). Each beam keeps its claim score: it is removed exactly when that
exceeds ``p_th``, whatever ``p_th``.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from pvfilter.clusters import ClusterSet
from pvfilter.improved.motion import Motion
from pvfilter.improved.params import ImprovedParams
from pvfilter.improved.scoring import SegmentScores
from pvfilter.improved.segmentation import Segments
from pvfilter.scan import Scan

CANDIDATE_SHARE = 0.25  # 1: segments that pass the gates and score above this are
# candidate lines whatever p_th: the next ego-motion fit leaves them out, the level view
# holds behind them, and with enough new points they mark the scan as tilted


@dataclasses.dataclass(frozen=True, eq=False)
class LineDetection:
    """What the improved filter decided for one scan, per cluster and per beam.

    Attributes:
        clusters: the clusters.
        passes_gates: per cluster, its segment passes the geometry gates of a floor line.
        share_new: per cluster, the share of its points that are new.
        scores: per cluster, its segment's score (see :mod:`pvfilter.improved.scoring`).
        detected: per cluster, ``score > p_th``.
        new_sequence: this scan starts a sequence (no level view yet).
        new_points: bool per beam: in space the level view saw as free.
        candidates: bool per beam: in a candidate line (see ``CANDIDATE_SHARE``).
        tilted: the scan has a candidate line with at least ``down_side_min_new`` new
            points: its plane was tilted (the level view does not learn from it).
        line_distances: per cluster, distance of its fitted line from the sensor, m (NaN
            where not fitted).
        implied_tilt_rad: per cluster, the scan plane's tilt that puts the floor there.
        down_side: +1 floor ahead, -1 behind, 0 unknown.
        plane_tilt_rad: the tilt of the scan plane that puts the floor on the strongest line
            (or the IMU's), rad; NaN when the scan has no such line.
        motion: the ego-motion from the previous scan.
        claim_scores: per beam, the best score of the lines that take it in: the beam is
            removed exactly when this exceeds ``p_th``.
    """

    clusters: ClusterSet
    passes_gates: np.ndarray
    share_new: np.ndarray
    scores: np.ndarray
    detected: np.ndarray
    new_sequence: bool
    new_points: np.ndarray
    candidates: np.ndarray
    tilted: bool
    line_distances: np.ndarray
    implied_tilt_rad: np.ndarray
    down_side: int
    plane_tilt_rad: float
    motion: Motion
    claim_scores: np.ndarray


def build_detection(
    scan: Scan,
    points: np.ndarray,
    segments: Segments,
    scores: SegmentScores,
    owner: np.ndarray,
    best: np.ndarray,
    new: np.ndarray,
    params: ImprovedParams,
    motion: Motion,
    new_sequence: bool,
) -> LineDetection:
    """The clusters and the per-beam results (see the module docstring).

    Args:
        scan: the scan.
        points: its points per beam, m, ``(n, 2)``.
        segments: its segments.
        scores: their scores.
        owner: per valid point, the segment whose line claims it best.
        best: per valid point, that line's score.
        new: bool per beam: new.
        params: ``p_th`` and ``min_points``.
        motion: the ego-motion (kept in the result).
        new_sequence: this scan starts a sequence.
    """
    k, labels, n = len(segments), segments.labels, len(scan)
    score = scores.scores
    detected = score > params.p_th
    extended = np.where(best > params.p_th, owner, labels)
    final_sizes = np.bincount(extended, minlength=k)
    kept = (final_sizes > 0) & (detected | (final_sizes >= params.min_points))
    cluster_of = kept.cumsum() - 1
    cluster_of[~kept] = -1
    ids = cluster_of.take(extended) if k else np.zeros(0, dtype=np.intp)
    beam_labels = np.full(n, -1, dtype=np.intp)
    beam_labels[segments.beams] = ids
    clusters = _cluster_set(scan, points, beam_labels, segments, ids, final_sizes[kept])
    claim_scores = np.zeros(n)
    claim_scores[segments.beams] = best
    candidate = scores.gates & (score > CANDIDATE_SHARE)
    candidates = np.zeros(n, dtype=bool)
    candidates[segments.beams] = candidate.take(labels)
    tilted = bool((candidate & (scores.new_counts >= params.down_side_min_new)).any())
    new_valid = new.take(segments.beams)
    in_cluster = np.bincount(extended, new_valid, k) / np.maximum(final_sizes, 1)
    fitted = not np.isnan(scores.tilt_rad).all()
    return LineDetection(
        clusters=clusters,
        passes_gates=scores.gates[kept],
        share_new=in_cluster[kept],
        scores=score[kept],
        detected=detected[kept],
        new_sequence=new_sequence,
        new_points=new,
        candidates=candidates,
        tilted=tilted,
        line_distances=segments.distances[kept] if fitted else np.full(len(clusters), np.nan),
        implied_tilt_rad=scores.tilt_rad[kept],
        down_side=scores.down_side,
        plane_tilt_rad=scores.down_tilt_rad,
        motion=motion,
        claim_scores=claim_scores,
    )


def _cluster_set(
    scan: Scan,
    points: np.ndarray,
    beam_labels: np.ndarray,
    segments: Segments,
    ids: np.ndarray,
    sizes: np.ndarray,
) -> ClusterSet:
    """The clusters as a :class:`pvfilter.ClusterSet`.

    ``ids``: cluster per valid point, -1 for none; ``sizes``: points per cluster.
    Points in no cluster are summed into an extra bin ``count`` and dropped, instead of
    being filtered out first: the other bins get the same sums in the same order.
    """
    count = len(sizes)
    bins = np.where(ids < 0, count, ids)
    centroids, variances = np.empty((count, 2)), np.empty((count, 2))
    for axis in (0, 1):
        values = segments.points[:, axis]
        total = np.bincount(bins, values, count + 1)[:count]
        mean = np.divide(total, sizes, out=centroids[:, axis])
        square = np.bincount(bins, np.square(values), count + 1)[:count] / sizes
        np.maximum(np.subtract(square, np.square(mean), out=square), 0.0, out=variances[:, axis])
    return ClusterSet(scan, points, beam_labels, sizes, centroids, variances)
