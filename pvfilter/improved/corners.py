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

Only segments that may score are cut (:func:`pvfilter.improved.detection.detect_lines`):
those with new points, or every one when the IMU shows the plane tilted or a held floor
line is followed. Most scans show no new point and keep their segments as they are.
"""

from __future__ import annotations

import math

import numpy as np

from pvfilter.improved.beams import indices
from pvfilter.improved.geometry import folded
from pvfilter.improved.params import ImprovedParams
from pvfilter.improved.segmentation import (
    Segments,
    line_direction,
    line_variances,
    segments_at,
)

CORNER_TURN_DEG = 10.0  # deg: two lines whose directions differ by more than this meet
# at a corner (the fitted directions of pieces of min_points points err by a few degrees)
CORNER_FIT_GAIN = 0.5  # 1: the two lines' squared residuals are at most this share of
# the one line's
STRAIGHT_SPREAD_M = 0.01  # m: a segment whose points lie within this (one standard
# deviation) of its line is straight: no cut is tried (range noise of a few centimetres
# at most: a corner that bends less leaves the fit as it is)
CUT_ROUNDS = 2  # a segment is cut at most this many times in turn (three pieces)


def split_at_corners(
    segments: Segments, params: ImprovedParams, tried: np.ndarray | None = None
) -> Segments:
    """``segments`` with every long, bent segment across the direction of travel cut at
    its corner (the same segments, as they are, when none is).

    All segments of a round are tried at once, from one cumulative sum of the scan's
    point moments: a scan has a few bent segments, and a loop over them, each with its
    own sums, cost a quarter of the filter's time.

    Args:
        segments: the scan's segments.
        params: ``min_points``: each piece keeps at least this many points.
        tried: per segment, it may be cut (None: every one may).
    """
    min_points = params.min_points
    long_bent = segments.across & (segments.sizes >= 2 * min_points)
    if tried is not None:
        long_bent &= tried
    # the lines are fitted only where a long segment may be cut: on most scans none is,
    # and its lines may never be asked for
    if not np.count_nonzero(long_bent):
        return segments
    long_bent &= segments.spread_across > STRAIGHT_SPREAD_M * STRAIGHT_SPREAD_M
    if not np.count_nonzero(long_bent):
        return segments
    bounds = segments.bounds
    firsts, ends = bounds[:-1][long_bent], bounds[1:][long_bent]
    # the sums run up to the last piece's end: no piece asks for the points after it
    moments = _cumulative_moments(segments.points[: ends[-1]])
    cuts = []
    for _ in range(CUT_ROUNDS):
        long_enough = ends - firsts >= 2 * min_points
        firsts, ends = firsts[long_enough], ends[long_enough]
        if firsts.size == 0:
            break
        at = _corners(moments, firsts, ends, min_points)
        cut = at >= 0
        if not np.count_nonzero(cut):
            break
        firsts, ends, at = firsts[cut], ends[cut], at[cut]
        cuts.append(at)
        firsts, ends = np.concatenate((firsts, at)), np.concatenate((at, ends))
    if not cuts:
        return segments
    return _cut(segments, np.concatenate(cuts))


def corner(points: np.ndarray, min_points: int) -> int | None:
    """Where two straight lines meeting at an angle explain ``points`` (in scan order)
    far better than one: the index of the first point of the second line, or None.

    Args:
        points: a segment's points, m, ``(n, 2)`` with ``n >= 2 * min_points``.
        min_points: each line keeps at least this many points.
    """
    whole = np.array([0]), np.array([len(points)])
    at = int(_corners(_cumulative_moments(points), *whole, min_points)[0])
    return None if at < 0 else at


def _cumulative_moments(points: np.ndarray) -> np.ndarray:
    """Column i: the moments ``(count, x, y, xx, xy, yy)`` summed over the first i points,
    ``(6, n + 1)`` (each moment a contiguous row: the sums run along it, and the corner
    search gathers whole columns of moments at once)."""
    x, y = points[:, 0], points[:, 1]
    each = np.empty((6, len(points)))
    each[0], each[1], each[2] = 1.0, x, y
    np.multiply(x, x, out=each[3])
    np.multiply(x, y, out=each[4])
    np.multiply(y, y, out=each[5])
    moments = np.empty((6, len(points) + 1))
    moments[:, 0] = 0.0
    np.cumsum(each, axis=1, out=moments[:, 1:])
    return moments


def _corners(
    moments: np.ndarray, firsts: np.ndarray, ends: np.ndarray, min_points: int
) -> np.ndarray:
    """Per piece ``[first, end)`` of the points, the index of its corner (the first point
    of the second line), or -1 where two lines do not explain it far better than one.

    The lines before and after every cut, and each whole piece's line, are fitted in one
    pass over one block of summed moments (the fit is a few dozen ufunc calls, each
    dearer to set up than to run on these few hundred columns).

    Args:
        moments: the points' cumulative moments (:func:`_cumulative_moments`).
        firsts, ends: the pieces, each of at least ``2 * min_points`` points.
        min_points: each line keeps at least this many points.
    """
    split, starts = _split_moments(moments, firsts, ends, min_points)
    n = (split.shape[1] - firsts.size) // 2  # cut points tried, over every piece
    residual, covariance = _line_residual(split)
    total = residual[:n] + residual[n : 2 * n]
    whole = residual[2 * n :]
    # each piece's best cut: the first of its least totals, as np.argmin takes (the tries
    # are in piece order, so a piece's first is where the piece changes)
    least = np.minimum.reduceat(total, starts)
    # the fit test first: on most pieces two lines explain the points little better than
    # one, and the directions at the best cut (the dearer half of the test) are then not
    # needed (a piece is cut where both tests pass, whichever is asked first)
    fits_better = least <= CORNER_FIT_GAIN * whole  # least: the total at the best cut
    if not np.count_nonzero(fits_better):  # (most scans)
        none = np.empty(firsts.size, dtype=np.intp)
        none.fill(-1)  # (np.full costs a Python-level call)
        return none
    tries = ends - firsts - 2 * min_points + 1  # cut points per piece
    piece = np.repeat(np.arange(firsts.size), tries)
    cut = firsts.take(piece) + min_points + (np.arange(n) - starts.take(piece))
    best_tries = indices(total == least.take(piece))
    of_piece = piece.take(best_tries)
    first_of_piece = np.empty(of_piece.size, dtype=bool)
    first_of_piece[:1] = True
    np.not_equal(of_piece[1:], of_piece[:-1], out=first_of_piece[1:])
    best = best_tries.compress(first_of_piece)
    before_and_after = np.concatenate((best, best + n))
    cxx, cxy, cyy = (c.take(before_and_after) for c in covariance)
    direction = line_direction(cxx, cxy, cyy)  # before, then after each best cut
    turn = np.abs(folded(direction[: best.size] - direction[best.size :]))
    corner_found = (turn > math.radians(CORNER_TURN_DEG)) & fits_better
    return np.where(corner_found, cut.take(best), -1)


def _split_moments(
    moments: np.ndarray, firsts: np.ndarray, ends: np.ndarray, min_points: int
) -> tuple[np.ndarray, np.ndarray]:
    """The summed moments of the points before every cut point of the pieces ``[first,
    end)``, then after it (the cut points in piece order, each piece's ascending), then of
    each whole piece, ``(6, 2 * cuts + pieces)``, and each piece's first cut's column.

    Each piece's cut points are a run of columns of ``moments``: the sums before and after
    them are two subtractions of that run, not gathers of every column (a scan has one
    or two such pieces; the gathers and their index arithmetic cost more).
    """
    bounds = list(zip(firsts.tolist(), ends.tolist(), strict=True))
    tries = [end - first - 2 * min_points + 1 for first, end in bounds]  # per piece
    n = sum(tries)
    split = np.empty((6, 2 * n + len(bounds)))
    starts, start = np.empty(len(bounds), dtype=np.intp), 0
    for i, ((first, end), count) in enumerate(zip(bounds, tries, strict=True)):
        starts[i] = start
        cuts = moments[:, first + min_points : first + min_points + count]
        np.subtract(cuts, moments[:, first, None], out=split[:, start : start + count])
        np.subtract(moments[:, end, None], cuts, out=split[:, n + start : n + start + count])
        np.subtract(moments[:, end], moments[:, first], out=split[:, 2 * n + i])  # whole
        start += count
    return split, starts


def _line_residual(
    moments: np.ndarray,
) -> tuple[np.ndarray, tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """The total-least-squares line of points from their summed moments ``(count, x, y,
    xx, xy, yy)`` (along the first axis): its sum of squared distances, m^2, and the
    points' covariance ``(cxx, cxy, cyy)``, m^2 (:func:`line_direction` of it: the line's
    direction)."""
    count, sx, sy, sxx, sxy, syy = moments
    mean_x, mean_y = sx / count, sy / count
    cxx, cxy, cyy = (
        sxx / count - mean_x * mean_x,
        sxy / count - mean_x * mean_y,
        syy / count - mean_y * mean_y,
    )
    _, across = line_variances(cxx, cxy, cyy)
    return across * count, (cxx, cxy, cyy)


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
