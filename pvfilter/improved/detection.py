"""Line detection, the recipe: score the segments, let the lines claim points, build the
clusters.

0. **Corners** (:mod:`pvfilter.improved.corners`): a segment that may score (one with
   new points; any, when the IMU shows the plane tilted or a floor line is held through a
   turn) that is two lines meeting at an angle, a floor line running into an oblique
   wall, is cut in two; the points stay in their order.
1. **Scoring** (:mod:`pvfilter.improved.scoring`): per segment, the share of its points in
   previously free space, the tilted-plane geometry gates, the two sides of a tilted
   plane, the IMU's agreement, and the place of a floor line held through a turn in
   place (:class:`~pvfilter.improved.scoring.HeldLine`).
2. **Claims** (:mod:`pvfilter.improved.claims`): a scored line takes in the points at its
   ends that lie on it and, with ``spread``, every point of the scan on it (on a full
   turn, across the seam too); each point goes to the best-scoring line that takes it in.
3. **Clusters** (:mod:`pvfilter.improved.clusters`): the detected segments with what they
   claimed, and the other segments of at least ``min_points`` points.

The state the filter carries between scans does not depend on ``p_th``, and each beam's
claim score says at which thresholds it is removed, so one pass over a sequence gives the
exact result of every threshold of a precision-recall sweep.
"""

from __future__ import annotations

import numpy as np

from pvfilter.improved.claims import best_claims
from pvfilter.improved.clusters import LineDetection, build_detection
from pvfilter.improved.corners import split_at_corners
from pvfilter.improved.evidence import WorldStatic
from pvfilter.improved.imu import Attitude
from pvfilter.improved.motion import Motion
from pvfilter.improved.params import ImprovedParams
from pvfilter.improved.scoring import HeldLine, score_segments
from pvfilter.improved.segmentation import Segments
from pvfilter.scan import Scan

__all__ = ["LineDetection", "detect_lines"]


def detect_lines(
    scan: Scan,
    points: np.ndarray,
    segments: Segments,
    new: np.ndarray,
    attitude: Attitude | None,
    params: ImprovedParams,
    motion: Motion,
    new_sequence: bool,
    static: WorldStatic | None = None,
    through: np.ndarray | None = None,
    level_view_m: np.ndarray | None = None,
    coasted: bool = False,
    held: HeldLine | None = None,
) -> LineDetection:
    """Score every segment, detect the lines, extend them, and build the clusters.

    Args:
        scan: the scan.
        points: its points per beam, sensor frame, m, ``(n, 2)`` (NaN where invalid).
        segments: its segments.
        new: bool per beam: new (free-space) evidence.
        attitude: the IMU's attitude, or None.
        params: the filter's parameters.
        motion: the ego-motion (kept in the result).
        new_sequence: this scan starts a sequence (nothing is new).
        static: the world-static test against an earlier scan (None: none).
        through: bool per beam: beyond the level view (None: none).
        level_view_m: the level view per beam the scan was compared with, m (kept in the
            result; None: none).
        coasted: the scan's motion is the prior's (kept in the result).
        held: the floor line of a tilt held through a turn in place (None: none).
    """
    new_valid = new.take(segments.beams)
    through_valid = None if through is None else through.take(segments.beams)
    tilted = attitude is not None and attitude.tilted
    new_counts = None  # per segment, its new points: the scoring counts them too
    if tilted or held is not None:  # any gated segment may score
        segments = split_at_corners(segments, params)
    elif np.count_nonzero(new_valid):  # only a segment with new points can score
        new_counts = np.bincount(segments.labels, new_valid, len(segments))
        split = split_at_corners(segments, params, new_counts > 0)
        if split is not segments:  # cut at a corner (few scans): counted again
            segments, new_counts = split, None
    view_valid = None
    if held is not None and level_view_m is not None:
        view_valid = level_view_m.take(segments.beams)
    scores = score_segments(
        segments,
        new_valid,
        scan.time_increment,
        attitude,
        params,
        static,
        through_valid,
        held,
        view_valid,
        new_counts,
    )
    scored = np.count_nonzero(scores.scores) > 0
    if scored:
        owner, best = best_claims(
            segments,
            scores.scores,
            params,
            scores.tilt_rad,
            scores.down_side,
            scan.time_increment,
            new_valid,
        )
    else:  # nothing scored (most scans): every point stays in its segment, unclaimed
        owner, best = segments.labels.copy(), np.zeros(len(segments.labels))
    return build_detection(
        scan,
        points,
        segments,
        scores,
        owner,
        best,
        new,
        params,
        motion,
        new_sequence,
        scored,
        level_view_m,
        coasted,
    )
