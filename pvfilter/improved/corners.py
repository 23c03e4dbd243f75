"""Corners: a segment that is two lines meeting at an angle is cut where they meet.

The segmentation (:mod:`pvfilter.improved.segmentation`) cuts at range jumps and where
the local direction leaves the band of lines across the direction of travel. A floor
line that runs into a wall standing obliquely to it (rooms are not square to the robot's
path) meets it without a jump, and a wall within ``line_angle_deg`` of the floor line's
direction is also "across": the two become one segment, mostly wall, whose fitted line
is neither, whose share of new points is diluted by the wall, and which the scoring
weighs as one. All floor hits of a scan lie on one straight line, so a segment that two
straight lines at an angle explain far better than one is two segments.

Per long segment across the direction of travel that is not straight (its spread across
its line above ``STRAIGHT_SPREAD_M``), every cut point is tried at once from cumulative
moments: the total-least-squares residual of the points before and after it. The best cut
is kept when the two lines explain the points ``CORNER_FIT_GAIN`` better than one and
turn by more than ``CORNER_TURN_DEG`` (range noise alone moves neither that far), and
each piece keeps at least ``min_points``. A piece is cut again once at most (a floor line
between two oblique walls).

Only scans with something to score are cut (:func:`pvfilter.improved.detection.detect_lines`):
most scans show no new point and keep their segments as they are.
"""

from __future__ import annotations

import math

import numpy as np

from pvfilter.improved.geometry import folded
from pvfilter.improved.params import ImprovedParams
from pvfilter.improved.segmentation import Segments, line_spreads, segments_at

CORNER_TURN_DEG = 10.0  # deg: two lines whose directions differ by more than this meet
# at a corner (the fitted directions of pieces of min_points points err by a few degrees)
CORNER_FIT_GAIN = 0.5  # 1: the two lines' squared residuals are at most this share of
# the one line's
STRAIGHT_SPREAD_M = 0.01  # m: a segment whose points lie within this (one standard
# deviation) of its line is straight: no cut is tried (range noise of a few centimetres
# at most: a corner that bends less leaves the fit as it is)
CUT_ROUNDS = 2  # a segment is cut at most this many times in turn (three pieces)


def split_at_corners(segments: Segments, params: ImprovedParams) -> Segments:
    """``segments`` with every long, bent segment across the direction of travel cut at
    its corner (the same segments, as they are, when none is).

    Args:
        segments: the scan's segments.
        params: ``min_points``: each piece keeps at least this many points.
    """
    min_points = params.min_points
    long_bent = (
        segments.across
        & (segments.sizes >= 2 * min_points)
        & (segments.spread_across > STRAIGHT_SPREAD_M * STRAIGHT_SPREAD_M)
    )
    if not np.count_nonzero(long_bent):
        return segments
    bounds, points = segments.bounds, segments.points
    pieces = [(int(bounds[s]), int(bounds[s + 1])) for s in np.flatnonzero(long_bent)]
    cuts: list[int] = []
    for _ in range(CUT_ROUNDS):
        cut_pieces = []
        for first, end in pieces:
            if end - first < 2 * min_points:
                continue
            at = corner(points[first:end], min_points)
            if at is not None:
                cuts.append(first + at)
                cut_pieces += [(first, first + at), (first + at, end)]
        pieces = cut_pieces
    if not cuts:
        return segments
    return _cut(segments, np.array(cuts, dtype=np.intp))


def corner(points: np.ndarray, min_points: int) -> int | None:
    """Where two straight lines meeting at an angle explain ``points`` (in scan order)
    far better than one: the index of the first point of the second line, or None.

    Args:
        points: a segment's points, m, ``(n, 2)`` with ``n >= 2 * min_points``.
        min_points: each line keeps at least this many points.
    """
    n = len(points)
    x, y = points[:, 0], points[:, 1]
    moments = np.empty((n + 1, 6))
    moments[0] = 0.0
    np.cumsum(np.column_stack((np.ones(n), x, y, x * x, x * y, y * y)), axis=0, out=moments[1:])
    whole, _ = _line_residual(moments[n])
    cut = np.arange(min_points, n - min_points + 1)  # points before the cut
    before = moments[cut].T
    after = moments[n][:, None] - before
    residual_before, direction_before = _line_residual(before)
    residual_after, direction_after = _line_residual(after)
    total = residual_before + residual_after
    best = int(np.argmin(total))
    turn = abs(folded(direction_before[best] - direction_after[best]))
    if turn <= math.radians(CORNER_TURN_DEG) or total[best] > CORNER_FIT_GAIN * whole:
        return None
    return int(cut[best])


def _line_residual(moments: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The total-least-squares line of points from their summed moments ``(count, x, y,
    xx, xy, yy)`` (along the first axis): its sum of squared distances, m^2, and its
    direction, rad."""
    count, sx, sy, sxx, sxy, syy = moments
    mean_x, mean_y = sx / count, sy / count
    cxx, cxy, cyy = (
        sxx / count - mean_x * mean_x,
        sxy / count - mean_x * mean_y,
        syy / count - mean_y * mean_y,
    )
    direction, _, across = line_spreads(cxx, cxy, cyy)
    return across * count, direction


def _cut(segments: Segments, cuts: np.ndarray) -> Segments:
    """``segments`` with the points at ``cuts`` starting new segments."""
    return segments_at(
        segments.beams,
        segments.points,
        segments.directions,
        segments.across.take(segments.labels),
        segments.ranges,
        np.union1d(segments.bounds[1:-1], cuts),
        segments.seam_joined,
    )
