"""Claims: which detected line each point joins, beyond its own segment.

A segment's points belong to it; a line with a score may also take in points outside it
(:mod:`pvfilter.improved.detection`, step 2): those at its ends that lie on it and, with
``spread``, every point of the scan on it and the other half of a floor line that the
seam of a full turn cuts in two. Each point then goes to the best-scoring line that takes
it in, so one score per point says at which thresholds it is removed.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from pvfilter.improved.beams import indices
from pvfilter.improved.geometry import floor_distance
from pvfilter.improved.medians import median_of_few
from pvfilter.improved.params import ImprovedParams
from pvfilter.improved.segmentation import Segments

OUTWARD = np.array([-1, 1])  # beam steps: before a line's first point, after its last


def extension_claims(
    segments: Segments, lines: np.ndarray, params: ImprovedParams
) -> tuple[np.ndarray, np.ndarray]:
    """The points at the ends of each line that lie on it: (point index, line) pairs.

    Going outward from each end, a point joins while it is within ``extend_tolerance_m``
    (plus 1 % of its range) of the line and within ``break_distance_m`` (plus 2 %) of the
    point before it, for at most ``extend_beams`` points, and unless it belongs to another
    segment of at least ``min_points`` points whose own line it lies nearer, by more than
    the scatter of that segment's points about its line: the wall a floor line runs into.
    Near the corner both lines pass within the tolerance of the wall's points, and on a
    0.25° scanner in a corridor that was 12-16 wall beams a scan at the line's two ends,
    in every scan of a pitch event; a point at the corner itself, within the noise of both
    lines, still joins.

    Args:
        segments: the segments.
        lines: the segments that may extend, ascending.
        params: ``extend_beams``, ``extend_tolerance_m``, ``break_distance_m``,
            ``min_points``.
    """
    reach, m = params.extend_beams, len(segments.points)
    if reach == 0 or lines.size == 0:
        return np.zeros(0, dtype=np.intp), np.zeros(0, dtype=np.intp)
    points, labels = segments.points, segments.labels
    # (2, lines, reach) candidate points: before each line's first point, then after its
    # last; the line's first point and the point after its last are its segment's bounds
    ends = segments.bounds.take(np.concatenate((lines, lines + 1))).reshape(2, -1, 1)
    beyond, previous = _outward_steps(reach)
    index, before = ends + beyond, ends + previous
    # most lines end well inside the scan: every candidate (and the point before it) is a
    # point, and nothing needs clipping; else as np.clip, without its Python layers (the
    # lines ascend, and so do their bounds: the first and last bound are the extremes)
    inside = None
    if not (ends[0, 0, 0] >= reach and ends[1, -1, 0] <= m - reach):
        inside = (index >= 0) & (index < m)
        np.minimum(np.maximum(index, 0, out=index), m - 1, out=index)
        np.minimum(np.maximum(before, 0, out=before), m - 1, out=before)
    candidate = points.take(index, axis=0)
    step = candidate - points.take(before, axis=0)
    ranges = segments.ranges.take(index)
    # rows gathered by take: indexing rows with an index array costs several times more;
    # each line's centre and normal broadcast over both ends and every candidate
    normal = segments.normals.take(lines, axis=0)[:, None, :]
    centre = segments.centroids.take(lines, axis=0)[:, None, :]
    off_line = _distance_to_line(candidate, centre, normal)
    on = off_line <= params.extend_tolerance_m + 0.01 * ranges
    if inside is not None:
        on &= inside
    on &= np.hypot(step[..., 0], step[..., 1]) <= params.break_distance_m + 0.02 * ranges
    if not np.count_nonzero(on[..., 0]):  # the point next to each end is off: none joins
        return np.zeros(0, dtype=np.intp), np.zeros(0, dtype=np.intp)
    # a point of another segment that lies nearer that segment's own line, by more than
    # the scatter of its points about it, is the wall the line runs into: at the corner
    # both lines pass within the tolerance of its points
    own = labels.take(index)
    own_centre, own_normal = (
        segments.centroids.take(own, axis=0),
        segments.normals.take(own, axis=0),
    )
    own_off = _distance_to_line(candidate, own_centre, own_normal)
    own_off += np.sqrt(segments.spread_across.take(own))
    other = (own != lines[:, None]) & (segments.sizes.take(own) >= params.min_points)
    on &= ~(other & (own_off < off_line))
    joined = np.logical_and.accumulate(on, axis=-1)  # up to the first point that is off
    per_row = np.add.reduce(joined, axis=-1).ravel()  # joined per end, as index[joined]
    return index[joined], np.concatenate((lines, lines)).repeat(per_row)


@functools.cache
def _outward_steps(reach: int) -> tuple[np.ndarray, np.ndarray]:
    """Beam steps from a line's bounds (its first point, the point after its last) to its
    ``reach`` candidates on each side and to the point before each, going outward,
    ``(2, 1, reach)``: before the first point, then after the last."""
    beyond = np.empty((2, 1, reach), dtype=np.intp)
    beyond[0, 0] = -np.arange(1, reach + 1)
    beyond[1, 0] = np.arange(reach)
    previous = beyond - OUTWARD[:, None, None]
    for steps in (beyond, previous):  # shared by every call: none may change them
        steps.flags.writeable = False
    return beyond, previous


def _distance_to_line(points: np.ndarray, centres: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """Distance of each point from the line through its centre with its unit normal, m
    (the last axis holds x and y; the others broadcast)."""
    products = points - centres
    products *= normals
    # the two products added as np.add.reduce adds them, without its reduction set-up
    distance = products[..., 0] + products[..., 1]
    return np.abs(distance, out=distance)


def spread_claims(
    segments: Segments, lines: np.ndarray, params: ImprovedParams
) -> tuple[np.ndarray, np.ndarray]:
    """Points anywhere in the scan that lie on a line: (point index, line) pairs.

    All floor hits of one scan lie on one straight line, so fragments of it between
    furniture legs, too short or too noisy to be segments of their own, and stretches of it
    too close to the structure behind to count as new, are found by their distance to the
    line (within ``extend_tolerance_m`` plus 1 % of the range, on the line's side of the
    sensor) and their local direction (within ``line_angle_deg`` of the line's): a wall
    that the line runs into crosses it, and stays out.

    Scoring (the lines' lengths) and the claims ask for the same lines on most scans: the
    answer is kept in ``segments.memo`` and given again for the same question.

    Args:
        segments: the segments.
        lines: the segments that may claim points.
        params: ``extend_tolerance_m`` and ``line_angle_deg``.
    """
    if lines.size == 0 or len(segments.points) == 0:
        return np.zeros(0, dtype=np.intp), np.zeros(0, dtype=np.intp)
    key = ("spread", lines.dtype.str, lines.tobytes(), params.extend_tolerance_m)
    key += (params.line_angle_deg,)
    if key not in segments.memo:
        pairs = _spread_claims(segments, lines, params)
        for values in pairs:  # given to every caller that asks: none may change them
            values.flags.writeable = False
        segments.memo[key] = pairs
    return segments.memo[key]


def _spread_claims(
    segments: Segments, lines: np.ndarray, params: ImprovedParams
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`spread_claims`, worked out."""
    points = segments.points
    normals, centres = segments.normals.take(lines, axis=0), segments.centroids.take(lines, axis=0)
    # dot: the same BLAS call as @, without the matmul ufunc's layers
    offsets = np.abs(points.dot(normals.T) - segments.offsets.take(lines))
    near = offsets <= (params.extend_tolerance_m + 0.01 * segments.ranges)[:, None]
    near &= points.dot(centres.T) > 0.0  # on the line's side of the sensor
    point, line = near.nonzero()  # (few: most points lie on no line)
    normal = normals.take(line, axis=0)
    along = _runs_along(segments.directions.take(point), normal[:, 0], normal[:, 1], params)
    return point[along], lines.take(line[along])


def seam_claims(
    segments: Segments,
    lines: np.ndarray,
    tilt_rad: np.ndarray,
    down_side: int,
    time_increment: float,
    params: ImprovedParams,
) -> tuple[np.ndarray, np.ndarray]:
    """The other half of a floor line cut by a full turn's seam: (point index, line) pairs.

    A rotating LiDAR whose sweep starts and ends on a floor line cuts it in two, measured a
    turn apart. The pitch changes meanwhile, and a floor line moves with it, parallel to
    itself (centimetres a degree when steep, metres near level): the later half lies
    beyond the spread's tolerance of the earlier, and may settle within the margin of the
    structure behind it (not new). Where the segmentation joins the two across the seam
    (:attr:`Segments.seam_joined`), a scored line on the floor's side takes in the points
    of the other half that lie on it moved by the jump at the seam (the median offset of
    the ``min_points`` points next to the seam), along it as :func:`spread_claims` asks.
    The jump must be one the pitch can make between the halves (``max_pitch_rate_rad_s``):
    a wall behind the line is no farther than that.

    Args:
        segments: the segments.
        lines: the segments that may claim points.
        tilt_rad: per segment, the tilt that puts the floor on its line.
        down_side: +1 (ahead) or -1 (behind) where the floor is, 0 unknown (no claims).
        time_increment: the scan's time between beams, s.
        params: ``min_points``, ``max_pitch_rate_rad_s`` and the spread's tolerances.
    """
    none = np.zeros(0, dtype=np.intp)
    if not segments.seam_joined or down_side == 0 or lines.size == 0:
        return none, none
    last = len(segments) - 1
    bounds, claimed, owners = segments.bounds, [], []
    for line, other in ((0, last), (last, 0)):
        if line not in (lines[0], lines[-1]):  # (lines ascend: only there can it be)
            continue
        normal, centre = segments.normals[line], segments.centroids[line]
        if math.copysign(1.0, centre[0]) != down_side:
            continue
        level = float(centre.dot(normal))  # (dot: @'s BLAS call, without its layers)
        outward = math.copysign(1.0, level)  # the normal, away from the sensor
        half = np.arange(bounds[other], bounds[other + 1])
        seam_end = half[-params.min_points :] if other == last else half[: params.min_points]
        seam_offsets_m = segments.points.take(seam_end, axis=0).dot(normal) - level
        jump_m = median_of_few(seam_offsets_m.tolist()) * outward
        if abs(jump_m) <= params.extend_tolerance_m:  # on the line itself: the spread's
            continue
        if abs(jump_m) > _pitch_jump_bound(
            segments, line, other, tilt_rad, jump_m, time_increment, params
        ):
            continue
        offset_m = (segments.points.take(half, axis=0).dot(normal) - level) * outward
        tolerance = params.extend_tolerance_m + 0.01 * segments.ranges.take(half)
        on = np.abs(offset_m - jump_m) <= tolerance
        on &= _runs_along(segments.directions.take(half), normal[0], normal[1], params)
        claimed.append(half[on])
        owners.append(np.full(np.count_nonzero(on), line, dtype=np.intp))
    if not claimed:
        return none, none
    return np.concatenate(claimed), np.concatenate(owners)


def _runs_along(
    directions: np.ndarray,
    normal_x: np.ndarray | float,
    normal_y: np.ndarray | float,
    params: ImprovedParams,
) -> np.ndarray:
    """Per point: its local direction runs along its line (within ``line_angle_deg``), not
    across it as a wall the line runs into does (NaN directions: False)."""
    crossing = np.abs(np.cos(directions) * normal_x + np.sin(directions) * normal_y)
    return crossing < math.sin(math.radians(params.line_angle_deg))


def _pitch_jump_bound(
    segments: Segments,
    line: int,
    other: int,
    tilt_rad: np.ndarray,
    jump_m: float,
    time_increment: float,
    params: ImprovedParams,
) -> float:
    """How far a floor line can move, m, outward (``jump_m > 0``) or inward, while the
    pitch changes at ``max_pitch_rate_rad_s`` from ``line``'s middle beam to ``other``'s."""
    tilt = float(tilt_rad[line])
    if not math.isfinite(tilt):  # not fitted: no floor line to move
        return 0.0
    bounds, beams = segments.bounds, segments.beams
    middle_line = beams[bounds[line] : bounds[line + 1]].mean()
    middle_other = beams[bounds[other] : bounds[other + 1]].mean()
    change = params.max_pitch_rate_rad_s * abs(middle_other - middle_line) * abs(time_increment)
    moved = max(tilt - change, 1e-6) if jump_m > 0.0 else min(tilt + change, 0.5 * math.pi)
    return abs(float(floor_distance(moved, params) - floor_distance(tilt, params)))


def best_claims(
    segments: Segments,
    score: np.ndarray,
    params: ImprovedParams,
    tilt_rad: np.ndarray | None = None,
    down_side: int = 0,
    time_increment: float = 0.0,
    new_valid: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Per valid point: the highest-scoring line that takes it in, and that score.

    A point belongs to its own segment, and may be claimed by the lines with a score:
    at their ends, and with ``spread`` anywhere on them and, given the lines' tilts, on
    the other half of a floor line cut by a full turn's seam. A claimed point that is new
    takes the line's own score, so a piece of the floor line that is new only in part
    carries the rest of its new points as far as its evidence goes, and a line the scan
    doubts claims nothing it would remove. A claimed point that is not new (on the level
    view's surface, beyond it, or where the view knows nothing) takes
    ``claimed_not_new_weight`` of it: there the floor line settles in front of the wall
    behind it, but the foot of that wall, and of the wall the line runs into, lies on the
    line just as well (on the fourth independent generator's sequences such points were
    pitch variation 45 % of the time, new ones 99 %; in the simulator's stress episodes 57
    and 99.7 %). At a threshold
    ``p_th`` a point is removed exactly when the best claim's score exceeds ``p_th``; the
    best claimer is then detected, and the point joins its cluster.

    Args:
        segments: the segments.
        score: per segment, its score.
        params: ``spread``, ``claimed_not_new_weight`` and the claims' tolerances.
        tilt_rad: per segment, the tilt that puts the floor on its line (None: no seam
            claims).
        down_side: +1 (ahead) or -1 (behind) where the floor is, 0 unknown.
        time_increment: the scan's time between beams, s.
        new_valid: per valid point, it is new (None: every claim at the line's score);
            a claimed point that is not new takes ``claimed_not_new_weight`` of it.

    Returns:
        The owning segment per point, and its score (for a claimed point, its claim's).
    """
    owner = segments.labels.copy()
    lines = indices(score > 0.0)
    pairs = [extension_claims(segments, lines, params)]
    if params.spread:
        pairs.append(spread_claims(segments, lines, params))
        if tilt_rad is not None:
            pairs.append(seam_claims(segments, lines, tilt_rad, down_side, time_increment, params))
    points = np.concatenate([p for p, _ in pairs])
    claimer = np.concatenate([c for _, c in pairs])
    claim = score[claimer]
    if new_valid is not None:  # a point on the view's surface is the wall's as much
        weight = params.claimed_not_new_weight
        claim = np.where(new_valid.take(points), claim, weight * claim)
    order = claim.argsort(kind="stable")  # the best claim is written last
    points, claimer, claim = points[order], claimer[order], claim[order]
    best = score[owner]
    better = claim > best[points]
    owner[points[better]] = claimer[better]
    best[points[better]] = claim[better]
    return owner, best
