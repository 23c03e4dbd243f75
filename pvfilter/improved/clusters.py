"""The line detection of one scan: per-beam decisions now, clusters when asked for.

A beam is removed exactly when its claim score (the best score of the lines that take it
in; ``SILENT_VIEW_WEIGHT`` of it where the level view is free by silence alone) exceeds
``p_th``, whatever ``p_th``: that, and what the filter carries to the next scan, is all a
scan needs. The clusters (the detected segments with every point they
claimed, and the other segments of at least ``min_points`` points) and their per-cluster
fields are for viewers and diagnoses, and are built on first access: most scans are never
looked at.
"""

from __future__ import annotations

import dataclasses
import functools

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
SILENT_VIEW_WEIGHT = 0.8  # 1: a claim's score on a return whose level view is free
# only by silence (no echo there within range_max), against one in front of a surface the
# view saw. Silence is weaker evidence of free space: a dark or far surface returns no
# echo until the sensor comes near enough, and its first echoes then stand in front of
# that free space where a floor line could. At 0.8 a line the evidence makes certain
# (1.0) is still removed at the default p_th, and it ranks below the lines in front of
# surfaces seen (see build_detection)


@dataclasses.dataclass(frozen=True, eq=False)
class LineDetection:
    """What the improved filter decided for one scan, per beam and per cluster.

    Attributes:
        scan: the scan.
        points: its points per beam, sensor frame, m, ``(n, 2)`` (NaN where invalid).
        segments: its segments.
        segment_scores: what scoring found per segment.
        owner: per valid point, the segment whose line claims it best.
        best: per valid point, that line's claim on it (``SILENT_VIEW_WEIGHT`` of it
            where the level view is free by silence alone).
        p_th: the threshold the clusters are built for.
        min_points: segments smaller than this are no cluster unless detected.
        new_sequence: this scan starts a sequence (or the filter re-baselined at it):
            nothing in it was compared with a level view.
        new_points: bool per beam: in space the level view saw as free.
        candidates: bool per beam: in a candidate line (see ``CANDIDATE_SHARE``).
        tilted: the scan has a candidate line with at least ``down_side_min_new`` new
            points: its plane was tilted (the level view does not learn from it).
        motion: the ego-motion from the previous scan.
        claim_scores: per beam, ``best`` (the best claim of the lines that take it in),
            and at least ``new_return_score`` where the return is new: the beam is
            removed exactly when this exceeds ``p_th``.
        level_view_m: per beam, where the level view the scan was compared with lies
            along it, m: the remembered level scans moved into this scan's frame. NaN
            where the view is unknown (everywhere when ``new_sequence``), ``+inf`` where it
            saw nothing within ``range_max``. A return nearer than this by more than
            ``free_margin_m + free_margin_rel * range`` is new; where the view is free,
            nearer than where it is known free (``range_max`` from where the sensor stood
            when it saw no echo: :meth:`~pvfilter.improved.memory.LevelView.known_free_m`).
        coasted: the scan's motion is the prior's (its match could not be trusted in a
            pitch event): a return was new only by the margin widened by what the robot
            could have driven meanwhile, without odometry.
    """

    scan: Scan
    points: np.ndarray
    segments: Segments
    segment_scores: SegmentScores
    owner: np.ndarray
    best: np.ndarray
    p_th: float
    min_points: int
    new_sequence: bool
    new_points: np.ndarray
    candidates: np.ndarray
    tilted: bool
    motion: Motion
    claim_scores: np.ndarray
    level_view_m: np.ndarray
    coasted: bool = False

    @property
    def down_side(self) -> int:
        """+1 floor ahead, -1 behind, 0 unknown."""
        return self.segment_scores.down_side

    @property
    def plane_tilt_rad(self) -> float:
        """The tilt that puts the floor on the strongest line that chose the down side
        (:func:`pvfilter.improved.scoring.score_segments`), or the IMU's, rad; NaN when the
        scan has no such line."""
        return self.segment_scores.down_tilt_rad

    @functools.cached_property
    def _kept(self) -> tuple[np.ndarray, np.ndarray, ClusterSet]:
        """The segments kept as clusters, each point's final segment (``len(segments)``:
        none), and the clusters."""
        segments, k = self.segments, len(self.segments)
        detected = self.segment_scores.scores > self.p_th
        extended = np.where(self.best > self.p_th, self.owner, segments.labels)
        # a detected segment's own return whose claim stays at or below p_th (weighed down
        # in front of a view free by silence alone) is not removed: it leaves the cluster,
        # whose returns are all removed, and joins none
        left = (self.best <= self.p_th) & detected.take(extended)
        if np.count_nonzero(left):  # (most scans: none)
            extended = np.where(left, k, extended)
        sizes = np.bincount(extended, minlength=k + 1)[:k]
        kept = (sizes > 0) & (detected | (sizes >= self.min_points))
        cluster_of = np.append(kept.cumsum() - 1, -1)
        cluster_of[:k][~kept] = -1
        ids = cluster_of.take(extended)
        beam_labels = np.full(len(self.scan), -1, dtype=np.intp)
        beam_labels[segments.beams] = ids
        clusters = _cluster_set(self.scan, self.points, beam_labels, segments, ids, sizes[kept])
        return kept, extended, clusters

    @property
    def clusters(self) -> ClusterSet:
        """The clusters: detected segments with what they claimed, and the other segments of
        at least ``min_points`` points."""
        return self._kept[2]

    @property
    def passes_gates(self) -> np.ndarray:
        """Per cluster, its segment passes the geometry gates of a floor line."""
        return self.segment_scores.gates[self._kept[0]]

    @property
    def scores(self) -> np.ndarray:
        """Per cluster, its segment's score."""
        return self.segment_scores.scores[self._kept[0]]

    @property
    def detected(self) -> np.ndarray:
        """Per cluster, ``score > p_th``."""
        return self.scores > self.p_th

    @property
    def share_new(self) -> np.ndarray:
        """Per cluster, the share of its points that are new."""
        kept, extended, _ = self._kept
        k = len(self.segments)
        new_valid = self.new_points.take(self.segments.beams)
        sizes = np.bincount(extended, minlength=k + 1)[:k]
        return (np.bincount(extended, new_valid, k + 1)[:k] / np.maximum(sizes, 1))[kept]

    @property
    def line_distances(self) -> np.ndarray:
        """Per cluster, the distance of its segment's fitted line from the sensor, m (NaN
        where the lines were not fitted: nothing new in the scan)."""
        if np.isnan(self.segment_scores.tilt_rad).all():
            return np.full(len(self.clusters), np.nan)
        return self.segments.distances[self._kept[0]]

    @property
    def implied_tilt_rad(self) -> np.ndarray:
        """Per cluster, the scan plane's tilt that puts the floor on its line, rad."""
        return self.segment_scores.tilt_rad[self._kept[0]]


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
    scored: bool = True,
    level_view_m: np.ndarray | None = None,
    coasted: bool = False,
) -> LineDetection:
    """The per-beam results of a scan (its clusters are built when asked for).

    Args:
        scan: the scan.
        points: its points per beam, m, ``(n, 2)``.
        segments: its segments.
        scores: their scores.
        owner: per valid point, the segment whose line claims it best.
        best: per valid point, that line's score.
        new: bool per beam: new.
        params: ``p_th``, ``min_points`` and ``down_side_min_new``.
        motion: the ego-motion (kept in the result).
        new_sequence: nothing in the scan was compared with a level view.
        scored: some segment scores above 0 (False: no claim and no candidate, as on
            most scans, and ``best`` is all 0).
        level_view_m: the level view per beam, m (None: none, all NaN).
        coasted: the scan's motion is the prior's.
    """
    n, labels = len(scan), segments.labels
    claim_scores = np.zeros(n)
    candidates = np.zeros(n, dtype=bool)
    tilted = False
    if not scored:
        candidate = None
    else:
        best = _weighed_by_view(best, segments, level_view_m)
        claim_scores[segments.beams] = best
        candidate = scores.gates & (scores.scores > CANDIDATE_SHARE)
    # a new return no line takes in ranks above the returns the view knows: pitch
    # variation far more often than they (on the independent sequences about 10 % against
    # under 1 %), far less often than a scored line's returns; below p_th it is ranked,
    # not removed
    if params.new_return_score > 0.0 and np.count_nonzero(new):  # (most scans: none new)
        np.maximum(claim_scores, params.new_return_score, out=claim_scores, where=new)
    if candidate is not None and np.count_nonzero(candidate):  # (count_nonzero: any())
        candidates[segments.beams] = candidate.take(labels)
        strong = candidate & (scores.new_counts >= params.down_side_min_new)
        tilted = np.count_nonzero(strong) > 0
    if level_view_m is None:
        level_view_m = np.empty(n)
        level_view_m.fill(np.nan)  # np.full costs a Python-level call
    return LineDetection(
        scan=scan,
        points=points,
        segments=segments,
        segment_scores=scores,
        owner=owner,
        best=best,
        p_th=params.p_th,
        min_points=params.min_points,
        new_sequence=new_sequence,
        new_points=new,
        candidates=candidates,
        tilted=tilted,
        motion=motion,
        claim_scores=claim_scores,
        level_view_m=level_view_m,
        coasted=coasted,
    )


def _weighed_by_view(
    best: np.ndarray, segments: Segments, level_view_m: np.ndarray | None
) -> np.ndarray:
    """The claims' scores per valid point, those whose level view is free by silence alone
    (``+inf``) at ``SILENT_VIEW_WEIGHT`` of theirs.

    On the tenth independent generator's sequences (the filter before this weight and
    the world-static test's older scan), of the returns scored above 0.1 in front of a
    view free by silence 58 % were pitch variation, against 82 % of those in front of a
    surface the view saw: the far wall a scanner comes within reach of, and a
    garage's wall behind a ramp's floor a grazing plane met without an echo, ranked with
    the surest floor lines. The weight ranks them below those, and leaves the filter's
    state alone: it carries nothing of the claims' scores to the next scan.
    """
    if level_view_m is None:
        return best
    silent = level_view_m.take(segments.beams) == np.inf
    if not np.count_nonzero(silent):  # (most scans)
        return best
    return np.where(silent, SILENT_VIEW_WEIGHT * best, best)


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
