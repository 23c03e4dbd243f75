"""Which segments are floor or ceiling lines: evidence, tilted-plane geometry, extension.

Per segment of the scan (:mod:`pvfilter.improved.segmentation`):

1. **Evidence**: the share of its points that are new, i.e. in space the level view saw
   as free (:func:`pvfilter.improved.memory.new_points`).
2. **Geometry of a tilted scan plane**: a floor line is straight, across the direction of
   travel, at least ``h / sin(max_tilt)`` from the sensor, and its normal leans from the
   x axis no more than a roll of ``max_roll_deg`` explains. A segment that fails gets no
   score.
3. **Score and decision**: ``P(C_pv)`` is that share; the segment is detected when it
   exceeds ``p_th``.
4. **The down side**: a tilted scan plane goes down on one side of the sensor and up on
   the other, so the floor is on one side only, the side of the scan's strongest line (the
   gated segment with the most new points, at least ``down_side_min_new``). Lines on the
   other side can only be ceilings or the undersides of tables, and are far more often
   furniture met at another height: their score is multiplied by ``up_side_weight``, so
   they are removed at low thresholds only.
5. **Extension**: a detected line takes in up to ``extend_beams`` points at each end that
   lie on it (the corner where the local fit straddled line and wall), and, with
   ``spread``, every point of the scan that lies on it (all floor hits of one scan lie on
   one line: fragments between furniture legs, and stretches too close to the structure
   behind them to be new).

With the IMU, the points on its predicted floor (:mod:`pvfilter.improved.imu`) form one
more cluster of the scan, removed whatever ``p_th`` (score 1): the IMU's evidence needs no
geometry and no history.

The state the filter carries between scans does not depend on ``p_th``, and each beam's
claim score (:func:`best_claims`) says at which thresholds it is removed, so one pass over
a sequence gives the exact result of every threshold of a precision-recall sweep.

The result is a :class:`LineDetection`: per cluster, whether it passes the geometry gates,
the share of its points that are new, its score and the decision; per beam, the evidence
and the claim scores.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from pvfilter.clusters import ClusterSet
from pvfilter.improved.claims import best_claims, extension_claims, spread_claims
from pvfilter.improved.motion import Motion
from pvfilter.improved.params import ImprovedParams
from pvfilter.improved.segmentation import Segments
from pvfilter.scan import Scan

__all__ = [
    "LineDetection",
    "best_claims",
    "detect_lines",
    "extension_claims",
    "geometry_gates",
    "spread_claims",
    "up_side_weights",
]

CANDIDATE_SHARE = 0.25  # 1: segments this new or more sit out the next ego-motion fit


@dataclasses.dataclass(frozen=True, eq=False)
class LineDetection:
    """What the improved filter decided for one scan, per cluster and per beam.

    The clusters are the segments that survive (detected, or at least ``min_points``
    points after extension), plus, with the IMU, the points on its predicted floor.

    Attributes:
        clusters: the clusters.
        passes_gates: per cluster, its segment passes the geometry gates of a floor line
            (False where nothing in the scan was new: lines are then not fitted, and for
            the IMU's cluster).
        share_new: per cluster, the share of its points that are new (in space the level
            view saw as free).
        scores: per cluster, its segment's score: the share of new points where it passes
            the gates (weighted on the up side), else 0; 1 for the IMU's cluster.
        detected: per cluster, ``score > p_th``.
        new_sequence: this scan starts a sequence (no level view yet).
        new_points: bool per beam: in space the level view saw as free.
        floor_points: bool per beam: on the IMU's floor (all False without the IMU).
        candidates: bool per beam: in a segment that passes the geometry gates with a
            score above ``CANDIDATE_SHARE``, whatever ``p_th``: the next scan's ego-motion
            fit leaves them out, and with ``hold_behind_lines`` the level view does not
            come closer behind them.
        line_distances: per cluster, distance of its fitted line from the sensor, m (NaN
            where not fitted: nothing in the scan was new).
        implied_tilt_rad: per cluster, the scan plane's tilt that puts the floor there.
        implied_roll_rad: per cluster, the roll its normal's lean needs.
        motion: the ego-motion from the previous scan.
        claim_scores: per beam, the best score of the lines that take it in (its own
            segment's, or a line's that extends or spreads over it): the beam is removed
            exactly when this exceeds ``p_th``.
    """

    clusters: ClusterSet
    passes_gates: np.ndarray
    share_new: np.ndarray
    scores: np.ndarray
    detected: np.ndarray
    new_sequence: bool
    new_points: np.ndarray
    floor_points: np.ndarray
    candidates: np.ndarray
    line_distances: np.ndarray
    implied_tilt_rad: np.ndarray
    implied_roll_rad: np.ndarray
    motion: Motion
    claim_scores: np.ndarray


def geometry_gates(segments: Segments, roll: np.ndarray, params: ImprovedParams) -> np.ndarray:
    """Per segment: it could be the floor seen by a tilted scan plane (see module doc).

    Args:
        segments: the segments.
        roll: the roll each segment's line implies, rad.
        params: ``min_points``, ``max_tilt_deg``, ``max_roll_deg``, ``lidar_height_m``.
    """
    return (
        segments.across
        & (segments.sizes >= params.min_points)
        & (segments.distances >= params.min_line_distance_m)
        & (roll <= math.radians(params.max_roll_deg))
    )


def up_side_weights(
    segments: Segments, new_counts: np.ndarray, gates: np.ndarray, params: ImprovedParams
) -> np.ndarray:
    """Per segment: ``up_side_weight`` on the far side of the strongest line, else 1.

    The strongest line is the gated segment with the most new points; with fewer than
    ``down_side_min_new`` it fixes no side, and every weight is 1. A segment is on the far
    side when its centroid lies on the other side of the sensor (negative dot product of
    the two centroids).

    Args:
        segments: the segments (their lines fitted).
        new_counts: new points per segment.
        gates: per segment, it passes the geometry gates.
        params: ``up_side_weight`` and ``down_side_min_new``.
    """
    weights = np.ones(len(segments))
    if params.up_side_weight == 1.0 or not gates.any():
        return weights
    strength = np.where(gates, new_counts, 0.0)
    strongest = int(np.argmax(strength))
    if strength[strongest] < params.down_side_min_new:
        return weights
    centroids = segments.centroids
    weights[centroids @ centroids[strongest] < 0.0] = params.up_side_weight
    return weights


def detect_lines(
    scan: Scan,
    points: np.ndarray,
    segments: Segments,
    new: np.ndarray,
    floor: np.ndarray | None,
    params: ImprovedParams,
    motion: Motion,
    new_sequence: bool,
) -> LineDetection:
    """Score every segment, detect the lines, extend them, and build the clusters.

    Args:
        scan: the scan.
        points: its points per beam, sensor frame, m, ``(n, 2)`` (NaN where invalid).
        segments: its segments.
        new: bool per beam: new (free-space) evidence.
        floor: bool per beam from the IMU, or None without it.
        params: the filter's parameters.
        motion: the ego-motion (kept in the result).
        new_sequence: this scan starts a sequence.
    """
    k, labels, n = len(segments), segments.labels, len(scan)
    sizes = np.maximum(segments.sizes, 1)
    new_valid = new.take(segments.beams)
    # most scans have no new point at all: their shares are 0, and nothing is fitted
    any_new = bool(new_valid.any())
    new_counts = np.bincount(labels, new_valid, k) if any_new else np.zeros(k)
    share_new = new_counts / sizes
    # lines are fitted only when a big enough segment across the direction of travel has
    # new points (half the scans have none)
    fitted = any_new and bool(
        (segments.across & (segments.sizes >= params.min_points) & (share_new > 0.0)).any()
    )
    if fitted:
        tilt, roll = segments.implied_tilt_roll(params.lidar_height_m)
        gates = geometry_gates(segments, roll, params)
        distances = segments.distances
    else:  # nothing to score
        gates = np.zeros(k, dtype=bool)
    score = np.where(gates, share_new, 0.0)
    if fitted:
        score *= up_side_weights(segments, new_counts, gates, params)
    if score.any():
        owner, best = best_claims(segments, score, params)
    else:  # nothing new (most scans): every point stays in its segment, unclaimed
        owner, best = labels.copy(), np.zeros(len(labels))
    # the IMU's floor points form one more cluster, certain (score 1) whatever p_th
    score, gates = np.concatenate((score, [1.0])), np.concatenate((gates, [False]))
    if floor is not None:
        on_floor = floor[segments.beams]
        owner[on_floor], best[on_floor] = k, 1.0
    detected = score > params.p_th
    extended = np.where(best > params.p_th, owner, labels)
    # clusters: the detected segments, and the others with at least min_points points
    final_sizes = np.bincount(extended, minlength=k + 1)
    kept = (final_sizes > 0) & (detected | (final_sizes >= params.min_points))
    cluster_of = kept.cumsum() - 1
    cluster_of[~kept] = -1
    ids = cluster_of.take(extended)
    beam_labels = np.full(n, -1, dtype=np.intp)
    beam_labels[segments.beams] = ids
    clusters = _cluster_set(scan, points, beam_labels, segments, ids, final_sizes[kept])
    claim_scores = np.zeros(n)
    claim_scores[segments.beams] = best
    candidates = np.zeros(n, dtype=bool)
    candidates[segments.beams] = (score[:k] > CANDIDATE_SHARE).take(labels)
    in_cluster = (
        np.bincount(extended, new_valid, k + 1) / np.maximum(final_sizes, 1)
        if any_new
        else np.zeros(k + 1)
    )
    count = len(clusters)
    if fitted:  # per cluster: its segment's line (none for the IMU's cluster)
        line_distances = np.concatenate((distances, [np.nan]))[kept]
        implied_tilt = np.concatenate((tilt, [np.nan]))[kept]
        implied_roll = np.concatenate((roll, [np.nan]))[kept]
    else:
        line_distances, implied_tilt = np.full(count, np.nan), np.full(count, np.nan)
        implied_roll = np.full(count, np.nan)
    return LineDetection(
        clusters=clusters,
        passes_gates=gates[kept],
        share_new=in_cluster[kept],
        scores=score[kept],
        detected=detected[kept],
        new_sequence=new_sequence,
        new_points=new,
        floor_points=np.zeros(n, dtype=bool) if floor is None else floor,
        candidates=candidates,
        line_distances=line_distances,
        implied_tilt_rad=implied_tilt,
        implied_roll_rad=implied_roll,
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
