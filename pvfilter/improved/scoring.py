"""Scoring: how likely each segment is a floor or ceiling line of a tilted scan plane.

Per segment (:mod:`pvfilter.improved.segmentation`):

1. **Evidence**: the share of its points that are new, in space the level view saw as
   free (:mod:`pvfilter.improved.evidence`). A point seen through the level view (beyond
   it: the view's surface is not there) counts fully against the line; one that
   coincides with the view, or where the view is unknown, counts ``COINCIDENT_WEIGHT``:
   a floor line that settles just in front of a wall has such points, and a wall the
   view knows has nothing but them, yet no new point either.
2. **Geometry** (:mod:`pvfilter.improved.geometry`): a floor line is straight, across the
   direction of travel, no nearer than the scanner's height over ``sin(max_tilt)``, and
   its normal leans from the x axis no more than the roll, a rotating scan's bend and the
   fit's own error explain. A segment that fails gets no score.
3. **The two sides**: a tilted plane goes down on one side of the sensor and up on the
   other. The down side is the side of the strongest line (the gated segment with the
   most new points, at least ``down_side_min_new``, among those without returns beyond
   them unless none of those has that many; where no segment alone has that many, a
   segment counts all the new points of the scan that lie on its line: a full turn's
   seam, chair legs or stray returns cut one floor line into pieces; and a segment's
   own new share counts over the beams it spans without a return, up to twice its new
   points, as a floor met at a grazing angle echoes on some beams only; and a line whose
   new points span ``STRONG_LINE_M`` counts as strong, as a floor line far out spans few
   beams however long it is), or the IMU's;
   unless the strongest line of the other side, taken for the floor, explains both lines
   where the strongest, taken for the floor, cannot (:func:`_down_side`). On the up side
   there is only the ceiling, at least ``(min_ceiling - h_s) / sin(tilt)`` away for the
   steepest tilt the down side's strong lines imply (a rotating sweep measures them at
   different tilts): a nearer line there is furniture met at another height, and its
   score is multiplied by ``up_side_weight``. A scan with no strong line and no IMU shows
   no pitch event at all (a tilted plane meets the floor along a whole line): all its
   lines are weighted so, as short new structure in clutter most often is.
4. **Length, the world, what lies beyond**: a floor line spans the open space, so a
   segment shorter than ``line_length_m`` scores in proportion to its length; one whose
   points stayed put in the world while the sensor moved along them is a wall (the
   world-static test, :mod:`pvfilter.improved.evidence`), and one with returns beyond it
   on its side is not where the plane meets the floor
   (:func:`pvfilter.improved.geometry.seen_beyond`): both are weighted down.
5. **The IMU** (optional): a gated line where the IMU's pitch puts the floor (within its
   error band, :mod:`pvfilter.improved.imu`) or the ceiling gains ``IMU_SUPPORT``, as
   independent evidence (``1 - (1 - share)(1 - IMU_SUPPORT)``), weighted down as the
   score is where the scan itself says the line is not the floor (step 4: it stayed put
   in the world, or returns lie beyond it): the IMU says where the floor may be, not that
   a wall is not there. A line the IMU's pitch cannot explain (a floor line nearer than
   its tilt allows, beyond what the body can reach within the estimate's lag, where the
   IMU does not show the plane tilted down on that side; the estimate's sign counts: a
   line ahead needs the plane nose down by the line's tilt, one behind nose up, so an
   estimate 1.5° nose up is 4.5° from a floor line 3° ahead) is weighted like a line on
   the up side, and only once: on the up side of a plane the IMU shows tilted, the up
   side's own weight has applied already. A line there nearer than a ceiling can be is
   no floor line to veto again, but a surface above the scanner that the rising plane
   meets, a table's underside or a shelf (on the tenth independent generator with the
   IMU, weighting it once moved the set means 0.778 / 0.908 / 0.717 to 0.782 / 0.908 /
   0.728). The IMU's band
   widens when the scans' confident lines show it off (:mod:`pvfilter.improved.imu`).
   Only an IMU that shows the plane tilted by at least ``IMU_PLACE_FACTOR`` times its
   band supports a line: a level estimate cannot tell a tilted plane from a level one,
   and one tilted barely beyond its band puts the floor anywhere from a metre or two to
   tens of metres out, where its support would fall on every wall across the travel (and
   on walls that reappear once the robot levels, whose lines would then widen the band
   further).
6. **A tilt held through a turn in place** (optional, :class:`HeldLine`): a gated line
   that keeps the place of the floor line of the last strong scans in the sensor frame,
   while the sensor turned past what a line fixed in the world could follow, scores at
   least ``CONFIDENT_SCORE`` and counts as strong, however few of its points are new;
   unless more than half its points stayed put in the world, or returns lie beyond it
   (a wall that the turn sweeps through that place keeps it for a scan, and is a wall),
   or the IMU's pitch cannot explain it (as in step 5).
   Nor does a line most of whose points lie on the level view's surface (more than
   ``HELD_ON_VIEW``): where the turn alone moves no return along its beam, the
   world-static test cannot tell, but a wall stands where the view has it, and a floor
   line held through the turn lies in front of the view's surface.

The score is then the segment's ``P(C_pv)``: it is removed when the score exceeds ``p_th``.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from pvfilter.improved.beams import indices
from pvfilter.improved.claims import spread_claims
from pvfilter.improved.evidence import STATIC_TOLERANCE_M, WorldStatic, standing_pitch_change
from pvfilter.improved.geometry import (
    TURN_TOLERANCE,
    axle_distances,
    ceiling_min_distance,
    floor_distance,
    floor_shift,
    folded,
    implied_tilt,
    lean_ok,
    line_lean,
    seen_beyond,
)
from pvfilter.improved.imu import Attitude
from pvfilter.improved.params import ImprovedParams
from pvfilter.improved.segmentation import Segments

CONFIDENT_SCORE = 0.8  # 1: the scan's own score of a line the IMU is checked against
COINCIDENT_WEIGHT = 0.5  # 1: a point that coincides with the level view (within the
# margin) counts this much against a line's share of new points (see the module docstring)
HELD_NOT_STATIC = 0.5  # 1: a segment keeps a held floor line's place only where at most
# half its points stayed put in the world (the world-static test under a turn)
STATIC_SEEN_SHARE = 0.25  # 1: the world-static test weighs a line where the earlier scan
# saw at least this share of its points (and half of those tell): a dark or glossy
# surface echoes on some beams only, a different set each scan (the eighth generator's
# apartment face on a third to a half of them); fewer is a part of the line out of the
# earlier scan's view, not a sample of it
HELD_ON_VIEW = 2.0 / 3.0  # 1: ... nor where more than two thirds of its points lie on the
# level view's surface (within STATIC_TOLERANCE_M): a wall that the turn brings there
# stands where the view has it, while a floor line held through the turn lies in front of
# the view's surface, or where the view knows nothing (one that meets furniture just
# behind it, within the tolerance at its ends, has up to about half its points on it)
IMU_PLACE_FACTOR = 2.0  # 1: the IMU lends support only where its tilt is at least this
# many times its error: the floor then lies within a factor of about three in distance
# (h / sin(p - e) against h / sin(p + e)); at 4 deg +- 3.5 deg it could lie anywhere from
# 2 m to 30 m ahead, where every wall across the travel would "agree"
IMU_SIGN_CEILING_SHARE = 0.5  # 1: a line on the IMU's up side nearer than this share of
# the nearest a ceiling can be at its tilt can only be the floor: the estimate's sign is
# contradicted (a floor line lies h / sin p out, a ceiling (H - h) / sin p: with H over
# 3 h, under half as far)
MAX_ECHO_FILL = 2.0  # a segment's new points count at most this many times over for the
# beams it spans without a return (a grazing floor line returns on about half of them; a
# face strewn over invalid readings no more than that)
IMU_SUPPORT = 0.4  # 1: the weight of the IMU's agreement, as independent evidence; alone
# (no new point) it stays below the default p_th
STRONG_LINE_M = 1.5  # m: a gated line whose new points span this far counts as strong,
# however few beams they are (still ``min_points``): ``down_side_min_new`` asks for 10 deg
# of new returns, and a floor line far out (a small tilt, or a tall robot) crosses a hall
# in fewer (one 20 m out across a 2.8 m hall spans 8 deg: 16 beams at 0.5 deg). 20 beams
# at 0.5 deg span this length 8.6 m out: nearer lines are judged by their count as before
HELD_TILT_TOLERANCE = math.radians(1.0)  # rad: a held tilt holds its pitch: a line that
# keeps the held floor line's place lies at a tilt within this of it (a wall that the turn
# brought to the line's direction lies at its own distance, most often another tilt)


@dataclasses.dataclass(frozen=True)
class HeldLine:
    """The floor line of a tilt held while the sensor turns in place (from
    :meth:`pvfilter.improved.follow.FloorFollower.held`): the strong lines of the last
    scans (the earliest's side and tilt, the median of their directions), the sensor
    turned since the earliest by more than twice ``TURN_TOLERANCE``.

    A line fixed in the world turns the other way in the sensor frame; the floor line of a
    held tilt keeps its place there, at one distance and in one direction, while the
    structure behind it turns past. It can settle within the free-space margin of what lies
    behind (furniture the robot stopped at), and lose the new points that made it strong:
    a gated segment on its side, in its direction (within ``TURN_TOLERANCE``) and at its
    tilt (within ``HELD_TILT_TOLERANCE``) is the same line.

    Attributes:
        side: +1 ahead, -1 behind.
        tilt_rad: the tilt that puts the floor on it, rad.
        lean_rad: its normal's direction from the x axis, rad (``geometry.line_lean``).
    """

    side: int
    tilt_rad: float
    lean_rad: float


@dataclasses.dataclass(frozen=True, eq=False)
class SegmentScores:
    """What scoring found per segment.

    Attributes:
        scores: per segment, ``P(C_pv)`` in [0, 1].
        gates: per segment, it passes the geometry gates.
        share_new: per segment, the share of its points that are new (points that
            coincide with the level view weighted by ``COINCIDENT_WEIGHT``).
        new_counts: per segment, its new points: its line's, where a cut line's pieces
            count theirs together, and the beams it spans without a return at its share of
            new returns (:func:`_echo_filled_counts`), or what the length its new points
            span is worth (:func:`_long_line_counts`), whichever is most; a segment that
            keeps a held tilt's floor line's place counts as strong: at least
            ``down_side_min_new``.
        tilt_rad: per segment, the tilt that puts the floor on its line (NaN: not fitted).
        down_side: +1 (ahead) or -1 (behind) where the floor is, 0 unknown.
        down_tilt_rad: the tilt that puts the floor there, rad (NaN: unknown).
        scan_scores: per segment, the score from the scan alone (before the IMU's cue).
        imu_contradicted: a line the scan alone scores above ``p_th`` lies beyond the
            IMU's band (vetoed or not: see :class:`~pvfilter.improved.imu.Attitude`).
        scan_down_side: where the scan alone puts the floor (+1, -1, 0), every gated line
            voting: the IMU's sign is checked against it. With the IMU, 0 also where the
            scan abstains: its disagreement rests on lines with returns beyond them, and
            the others agree with the IMU.
        voters: per segment, it may say where the floor is: gated and without returns
            beyond it, or every gated line where none of those showed a side (None: the
            lines were not fitted). Where the IMU or a held line chose the side, these are
            the lines that could have.
    """

    scores: np.ndarray
    gates: np.ndarray
    share_new: np.ndarray
    new_counts: np.ndarray
    tilt_rad: np.ndarray
    down_side: int
    down_tilt_rad: float = math.nan
    scan_scores: np.ndarray | None = None
    imu_contradicted: bool = False
    scan_down_side: int = 0
    voters: np.ndarray | None = None


def geometry_gates(
    segments: Segments,
    tilt: np.ndarray,
    distances: np.ndarray,
    time_increment: float,
    params: ImprovedParams,
) -> np.ndarray:
    """Per segment: it could be the floor (or ceiling) seen by a tilted scan plane.

    ``distances`` are the lines' distances from the plane's point over the axle, m
    (:func:`pvfilter.improved.geometry.axle_distances`).
    """
    span_s = (segments.beam_spans - 1) * abs(time_increment)
    return (
        segments.across
        & (segments.sizes >= params.min_points)
        & (distances >= params.min_line_distance_m)
        & lean_ok(
            np.abs(segments.normals[:, 1]),
            tilt,
            distances,
            segments.spread_along,
            segments.spread_across,
            segments.sizes,
            span_s,
            params,
        )
    )


def score_segments(
    segments: Segments,
    new_valid: np.ndarray,
    time_increment: float,
    attitude: Attitude | None,
    params: ImprovedParams,
    static: WorldStatic | None = None,
    through_valid: np.ndarray | None = None,
    held: HeldLine | None = None,
    view_valid: np.ndarray | None = None,
    new_counts: np.ndarray | None = None,
) -> SegmentScores:
    """Score every segment (see the module docstring).

    Args:
        segments: the scan's segments.
        new_valid: per valid point, it is new.
        time_increment: the scan's time between beams, s.
        attitude: the IMU's attitude, or None.
        params: the filter's parameters.
        static: the world-static test against an earlier scan (None: no earlier scan).
        through_valid: per valid point, it lies beyond the level view (None: none does).
        held: the floor line of a tilt held through a turn in place (None: none): a
            segment that keeps its place scores at least ``CONFIDENT_SCORE``.
        view_valid: per valid point, where the level view lies along its beam, m (NaN:
            unknown, inf: free; None: unknown everywhere).
        new_counts: per segment, its new points, ``np.bincount(labels, new_valid)``, where
            the caller counted them already (None: counted here).
    """
    k, labels = len(segments), segments.labels
    # (count_nonzero: any() without Python layers)
    any_new = new_counts is not None or np.count_nonzero(new_valid) > 0
    if any_new:  # the points that tell: new ones, and those seen through the view
        sizes = np.maximum(segments.sizes, 1)
        if new_counts is None:
            new_counts = np.bincount(labels, new_valid, k)
        through = np.zeros(k) if through_valid is None else np.bincount(labels, through_valid, k)
        told = new_counts + through
        share = new_counts / np.maximum(told + COINCIDENT_WEIGHT * (sizes - told), 1.0)
    else:  # no new point: every share is 0 / size
        new_counts, share = np.zeros(k), np.zeros(k)
    imu_tilted = attitude is not None and attitude.tilted
    # lines are fitted only when a segment across the direction of travel has new points,
    # the IMU says the plane is tilted, or a held tilt's floor line is followed (most
    # scans: none of them)
    fitted = any_new or imu_tilted or held is not None
    if fitted:
        candidates = segments.across & (segments.sizes >= params.min_points)
        fitted = imu_tilted or held is not None or np.count_nonzero(candidates & (share > 0.0)) > 0
        fitted = fitted and np.count_nonzero(candidates) > 0
    if not fitted:
        unknown = np.empty(k)
        unknown.fill(np.nan)  # np.full costs a Python-level call
        return SegmentScores(np.zeros(k), np.zeros(k, bool), share, new_counts, unknown, 0)
    distances = axle_distances(segments, params)
    tilt = implied_tilt(distances, params)
    gates = geometry_gates(segments, tilt, distances, time_increment, params)
    score = np.where(gates, share, 0.0)
    side = np.sign(segments.centroids[:, 0])  # +1 ahead, -1 behind
    own_new = new_counts  # (before the pieces of a cut line count theirs together)
    new_counts = _pooled_new_counts(segments, gates, new_counts, new_valid, params)
    new_counts = np.maximum(new_counts, _echo_filled_counts(segments, own_new))
    long_counts = _long_line_counts(segments, gates, own_new, params)
    if long_counts is not None:
        new_counts = np.maximum(new_counts, long_counts)
    if params.line_length_m > 0.0:  # a floor line spans the open space: a short one scores less
        strong = gates & (new_counts >= params.down_side_min_new)
        score *= _length_shares(segments, strong, params)
    # the scan's evidence against a floor line: it stayed put in the world, or returns lie
    # beyond it; asked of every gated segment the IMU may support, else of the scored ones
    asked = gates if attitude is not None else score > 0.0
    # the segments that keep a held floor line's place are asked too: a wall fixed in the
    # world that the turn sweeps through that place keeps it for a scan, but stays put
    kept = None
    if held is not None:
        kept = _keeps_place(segments, gates, side, tilt, held)
        asked = asked | kept
    not_static, beyond = _evidence_against(segments, asked, static, tilt, time_increment, params)
    score *= not_static
    score[beyond] *= params.up_side_weight
    # a line with returns beyond it is not where the plane meets the floor: where the
    # other lines show a pitch event, it has no say in where the floor is (nose up among
    # tables, the new faces ahead outnumbered the floor line behind)
    flagged = np.count_nonzero(beyond) > 0
    voters = gates & ~beyond if flagged else gates
    down, down_tilt = _down_side(voters, new_counts, side, tilt, distances, attitude, params)
    if down == 0 and flagged:
        voters = gates
        down, down_tilt = _down_side(voters, new_counts, side, tilt, distances, attitude, params)
    scan_down = down
    if attitude is not None and attitude.tilted:  # (the IMU chose the side: the scan's own,
        # every gated line voting, checks the IMU's sign: counted without the lines with
        # returns beyond them, an IMU of the wrong sign was disowned later, the fourth
        # generator's nose-up IMU set 1 0.756 to 0.742)
        scan_down, scan_tilt = _down_side(gates, new_counts, side, tilt, distances, None, params)
        if flagged and scan_down == -attitude.down_side:
            # a contradiction that rests on lines with returns beyond them (a table face
            # ahead of a plane nose up, too near to be a ceiling), where the other lines
            # put the floor where the IMU does, is no evidence either way: the scan
            # abstains (a correct IMU was disowned among tables). Where the other lines
            # say nothing, it still counts: abstaining there let an IMU of the wrong sign
            # go on longer (the fourth generator's nose-up corridor, 0.752 to 0.671)
            # (with the IMU's side taken, the voters are the gated lines without them)
            unflagged, _ = _down_side(voters, new_counts, side, tilt, distances, None, params)
            if unflagged == attitude.down_side:
                scan_down = 0
        # a line on the estimate's up side contradicts its sign only where no ceiling can
        # be at its tilt (a low ceiling ahead of a plane nose up can hold more new points
        # than the floor line behind): nearer than IMU_SIGN_CEILING_SHARE of the nearest
        # a ceiling can be, it can only be the floor
        nearest_ceiling = ceiling_min_distance(attitude.tilt_rad, params)
        if (
            scan_down == -attitude.down_side
            and floor_distance(scan_tilt, params) >= IMU_SIGN_CEILING_SHARE * nearest_ceiling
        ):
            scan_down = 0
    if down != 0 and params.up_side_weight < 1.0:
        # a rotating scan measures its lines at different tilts: the floor side's strong
        # lines show how steep the plane got, and a ceiling can be that much nearer
        strong_down = gates & (side == down) & (new_counts >= params.down_side_min_new)
        steepest = (
            max(down_tilt, float(tilt[strong_down].max()))  # (a NaN tilt: down_tilt)
            if np.count_nonzero(strong_down)  # (any() without its Python layers)
            else down_tilt
        )
        too_near = distances < ceiling_min_distance(steepest, params)
        score[(side == -down) & too_near] *= params.up_side_weight
    elif down == 0:  # no strong line, no IMU: no sign of a pitch event in this scan
        score *= params.up_side_weight
    scan_score = score.copy()
    contradicted = False
    unexplained = None
    if attitude is not None:
        agree, unexplained, contradict = _imu_agreement(distances, side, tilt, attitude, params)
        contradicted = bool((unexplained & (scan_score > params.p_th)).any())
        # where the floor may be, unless the scan's own evidence says it is not
        support = IMU_SUPPORT * not_static
        support[beyond] *= params.up_side_weight
        score = np.where(gates & agree, 1.0 - (1.0 - score) * (1.0 - support), score)
        score[contradict] *= params.up_side_weight
    if kept is not None:
        kept &= (not_static >= HELD_NOT_STATIC) & ~beyond
        if attitude is not None:
            kept &= ~unexplained
        if view_valid is not None and np.count_nonzero(kept):
            kept &= _on_view_share(segments, view_valid) <= HELD_ON_VIEW
        if np.count_nonzero(kept):
            score = np.where(kept, np.maximum(score, CONFIDENT_SCORE), score)
            scan_score = np.where(kept, np.maximum(scan_score, CONFIDENT_SCORE), scan_score)
            new_counts = np.where(
                kept, np.maximum(new_counts, params.down_side_min_new), new_counts
            )
            if down == 0:
                down, down_tilt = held.side, held.tilt_rad
    return SegmentScores(
        score,
        gates,
        share,
        new_counts,
        tilt,
        down,
        down_tilt,
        scan_score,
        contradicted,
        scan_down,
        voters,
    )


def _pooled_new_counts(
    segments: Segments,
    gates: np.ndarray,
    new_counts: np.ndarray,
    new_valid: np.ndarray,
    params: ImprovedParams,
) -> np.ndarray:
    """Per segment, the new points of its line: its own, or, where no segment alone has
    ``down_side_min_new``, all the new points of the scan that lie on its line if more.

    All floor hits of one scan lie on one straight line: where the seam of a full turn,
    a chair leg or a stray return cut it into pieces, each piece holds too few new points
    to show the pitch event that the line as a whole shows."""
    if not params.spread:
        return new_counts
    pieces = gates & (new_counts > 0)
    if np.count_nonzero(pieces) < 2:
        return new_counts
    if float(new_counts[pieces].max()) >= params.down_side_min_new:
        return new_counts
    points, line = spread_claims(segments, indices(pieces), params)
    on_line = np.bincount(line, new_valid.take(points), len(segments))
    return np.where(pieces, np.maximum(new_counts, on_line), new_counts)


def _echo_filled_counts(segments: Segments, new_counts: np.ndarray) -> np.ndarray:
    """Per segment, its own new points counted over the beams it spans without a return
    too, at its share of new returns, up to ``MAX_ECHO_FILL`` times its count.

    A plane tilted into the floor meets it at a grazing angle, and many scanners return no
    echo there on some of the beams: a floor line behind a 360-beam scanner pitched 9°
    returns on half of them. The floor it met is as long as its span, not as its echoes.
    A segment's returns are a run of the scan's, so the beams between them gave no return
    (no echo, or none the scanner could measure); the bound keeps a few returns strewn
    over a run of such beams (a face seen through a window of invalid readings) from
    passing for a line."""
    fill = np.minimum(segments.beam_spans / np.maximum(segments.sizes, 1), MAX_ECHO_FILL)
    return new_counts * fill


def _long_line_counts(
    segments: Segments, gates: np.ndarray, new_counts: np.ndarray, params: ImprovedParams
) -> np.ndarray | None:
    """Per gated segment, the new points its new length is worth: ``down_side_min_new``
    for each ``STRONG_LINE_M`` of its line that its new points span (its length times its
    share of new points); 0 where that is shorter than ``STRONG_LINE_M``, or where it
    spans more than ``MAX_ECHO_FILL`` times its returns in beams (a few returns strewn
    over silent beams are no line, however long their spread). None where no gated
    segment's new points span ``STRONG_LINE_M`` (most line scans): all would be 0.

    The count a strong line needs is an arc of the sweep: a floor line far out spans few
    beams however long it is. Its length is that of a line of evenly spaced points with
    the segment's spread along it (``sqrt(12 var)``)."""
    new_length = segments.lengths * np.minimum(new_counts / np.maximum(segments.sizes, 1), 1.0)
    long_line = gates & (new_length >= STRONG_LINE_M)
    if not np.count_nonzero(long_line):
        return None
    long_line &= segments.beam_spans <= MAX_ECHO_FILL * segments.sizes
    return np.where(long_line, params.down_side_min_new * new_length / STRONG_LINE_M, 0.0)


def _on_view_share(segments: Segments, view_valid: np.ndarray) -> np.ndarray:
    """Per segment, the share of its points that lie on the level view's surface (within
    :data:`~pvfilter.improved.evidence.STATIC_TOLERANCE_M` plus 1 % of the range)."""
    ranges = segments.ranges
    on_view = np.abs(view_valid - ranges) <= STATIC_TOLERANCE_M + 0.01 * ranges  # NaN: no
    return np.bincount(segments.labels, on_view, len(segments)) / np.maximum(segments.sizes, 1)


def _keeps_place(
    segments: Segments, gates: np.ndarray, side: np.ndarray, tilt: np.ndarray, held: HeldLine
) -> np.ndarray:
    """Per segment: it keeps the held floor line's place in the sensor frame (its side,
    its direction within ``TURN_TOLERANCE``, its tilt within ``HELD_TILT_TOLERANCE``)."""
    normals = segments.normals
    turned = folded(line_lean(normals[:, 1], normals[:, 0]) - held.lean_rad)
    kept = gates & (side == held.side) & (np.abs(turned) <= TURN_TOLERANCE)
    return kept & (np.abs(tilt - held.tilt_rad) <= HELD_TILT_TOLERANCE)


def strongest_confident(
    segments: Segments, scores: SegmentScores, params: ImprovedParams
) -> int | None:
    """The scan's strongest confident line: the gated segment with the most new points, at
    least ``down_side_min_new`` of them, that the scan alone scores at least
    ``CONFIDENT_SCORE`` (a whole line, new, not fixed in the world, nothing beyond it);
    None if there is none."""
    if scores.scan_scores is None:
        return None
    confident = scores.gates & (scores.scan_scores >= CONFIDENT_SCORE)
    if not np.count_nonzero(confident):
        return None
    strength = np.where(confident, scores.new_counts, 0.0)
    strongest = int(np.argmax(strength))
    if strength[strongest] < params.down_side_min_new:
        return None
    return strongest


def line_pitch(segments: Segments, scores: SegmentScores, params: ImprovedParams) -> float | None:
    """The pitch (rad, positive nose down) at which the scan's strongest confident line
    (:func:`strongest_confident`) is the floor; None if there is none. The IMU's estimate
    is checked against it (:mod:`pvfilter.improved.imu`)."""
    strongest = strongest_confident(segments, scores, params)
    if strongest is None:
        return None
    return float(np.sign(segments.centroids[strongest, 0]) * scores.tilt_rad[strongest])


def _length_shares(segments: Segments, strong: np.ndarray, params: ImprovedParams) -> np.ndarray:
    """Per segment: the length of its line as a share of ``line_length_m``, at most 1. The
    length is its own (``sqrt(12 var)`` along it), or for a strong line the length of all
    the scan's points that lie on it, if longer.

    All floor hits of one scan lie on one straight line, so the pieces of it that furniture,
    a noisy stretch or a cut at a turn of direction separate are one line: its length is
    theirs together (the points :func:`pvfilter.improved.claims.spread_claims` takes in).
    Where every strong line is ``line_length_m`` long by itself (most scans with one), its
    share is 1 whatever else lies on it, and those points are not looked for.
    """
    own = segments.lengths
    lines = indices(strong)
    if not np.count_nonzero(own.take(lines) < params.line_length_m):  # no strong line short
        return np.minimum(own / params.line_length_m, 1.0)
    points, line = spread_claims(segments, lines, params)
    normals = segments.normals.take(line, axis=0)  # (take: cheaper than indexing rows)
    x, y = segments.points[:, 0].take(points), segments.points[:, 1].take(points)
    along = x * normals[:, 1] - y * normals[:, 0]
    k = len(segments)
    count = np.maximum(np.bincount(line, minlength=k), 1)
    mean = np.bincount(line, along, k) / count
    variance = np.maximum(np.bincount(line, along * along, k) / count - mean * mean, 0.0)
    length = np.maximum(own, np.sqrt(12.0 * variance))
    return np.minimum(length / params.line_length_m, 1.0)


def _evidence_against(
    segments: Segments,
    asked: np.ndarray,
    static: WorldStatic | None,
    tilt: np.ndarray,
    time_increment: float,
    params: ImprovedParams,
) -> tuple[np.ndarray, np.ndarray]:
    """The scan's own evidence that the ``asked`` segments are not the floor.

    Returns:
        Per segment, one minus the share of its points that stayed put in the world while
        the sensor moved (1: none did, or not asked); and per segment, returns lie beyond
        it (:func:`pvfilter.improved.geometry.seen_beyond`: nothing lies beyond a floor
        line, so they show a wall beside open space).
    """
    not_static = np.ones(len(segments))
    if static is not None and np.count_nonzero(asked):
        not_static -= _world_static_share(segments, asked, static, tilt, params)
    return not_static, seen_beyond(segments, asked, tilt, time_increment, params)


def _world_static_share(
    segments: Segments,
    scored: np.ndarray,
    static: WorldStatic,
    tilt: np.ndarray,
    params: ImprovedParams,
) -> np.ndarray:
    """Per scored segment: the share of its points that stayed put in the world, where at
    least half of the points the earlier scan saw tell, and it saw at least
    ``STATIC_SEEN_SHARE`` of them (else 0). A beam without a return in the earlier scan
    says nothing either way: a surface that echoes on every other beam would otherwise
    never be told to be a wall. Where the sensor stood, a steep line and a wall look
    alike, but a shallow floor line moves with the least change of pitch (``tilt``: the
    tilt each segment implies, rad; see :class:`~pvfilter.improved.evidence.WorldStatic`).
    """
    k = len(segments)
    points = indices(scored.take(segments.labels))
    labels = segments.labels.take(points)
    change = standing_pitch_change(tilt, static.hold_tilt_rad)
    shift = floor_shift(tilt, change, params).take(labels)
    offsets = static.offsets_or_farther(segments.beams.take(points), shift)
    seen_beams = offsets.seen  # (a property: worked out once here)
    told = np.bincount(labels, offsets.telling & seen_beams, k)
    seen = np.bincount(labels, seen_beams, k)
    share = np.bincount(labels, offsets.stayed, k) / np.maximum(told, 1.0)
    enough = (told >= 0.5 * seen) & (seen >= STATIC_SEEN_SHARE * segments.sizes)
    return np.where(enough, share, 0.0)


def _down_side(
    voters: np.ndarray,
    new_counts: np.ndarray,
    side: np.ndarray,
    tilt: np.ndarray,
    distances: np.ndarray,
    attitude: Attitude | None,
    params: ImprovedParams,
) -> tuple[int, float]:
    """Where the floor is (+1 ahead, -1 behind, 0 unknown) and the tilt that puts it there.

    The IMU's pitch when it says the plane is tilted; else the strongest of the voting
    lines (``voters``: bool per segment, gated lines, or those of them with no returns
    beyond), unless the strongest voting line on the other side tells otherwise. A plane
    tilts down on one side only, and on the other it meets a ceiling, never nearer than
    ``ceiling_min_distance`` for its tilt. Where the strongest line, taken for the floor,
    leaves the other side's strong line nearer than that, and that line, taken for the
    floor, puts the strongest one where a ceiling can be, the other side is the floor's:
    one tilt then explains both lines (nose up in a hall, the ceiling line ahead can hold
    more new points than the floor line behind, which the body hides in part).
    """
    if attitude is not None and attitude.tilted:
        return attitude.down_side, attitude.tilt_rad
    strength = np.where(voters, new_counts, 0.0)
    strongest = int(strength.argmax()) if strength.size else 0
    if strength.size == 0 or strength[strongest] < params.down_side_min_new:
        return 0, math.nan
    down, down_tilt = int(side[strongest]), float(tilt[strongest])
    other_side = np.where(side == -down, strength, 0.0)
    other = int(other_side.argmax())
    if other_side[other] >= params.down_side_min_new:
        other_tilt = float(tilt[other])
        if distances[other] < ceiling_min_distance(down_tilt, params) and distances[
            strongest
        ] >= ceiling_min_distance(other_tilt, params):
            return -down, other_tilt
    return down, down_tilt


def _imu_agreement(
    distances: np.ndarray,
    side: np.ndarray,
    tilt: np.ndarray,
    attitude: Attitude,
    params: ImprovedParams,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per segment: the IMU's pitch puts the floor or a ceiling on its line; or it cannot
    (a floor there would need the plane tilted down on the line's side by more than the
    IMU's pitch that way and its band allow); and it is vetoed (it would need more than
    the band and ``reach_rad`` together, and the IMU shows no tilt: where it does, such a
    line lies on its up side, which that side's own weight has weighed already)."""
    error, magnitude = attitude.error_rad, attitude.tilt_rad
    agree = np.zeros(len(distances), dtype=bool)
    if magnitude >= IMU_PLACE_FACTOR * error:  # else the IMU cannot tell where the floor is
        agree = (side == attitude.down_side) & (np.abs(tilt - magnitude) <= error)
        far = distances >= ceiling_min_distance(magnitude + error, params)
        agree |= (side == -attitude.down_side) & far
    # a line that needs more tilt than the IMU's band allows; where the IMU shows the plane
    # tilted down on the line's side, the floor is there and only its distance is in doubt
    unexplained = ~agree & ~(attitude.tilted & (side == attitude.down_side))
    # how far past the IMU's pitch the plane must have tilted down on the line's side for
    # the line to be the floor: nose down for a line ahead, nose up for one behind (the
    # estimate's sign counts: nose up by 1 deg puts a floor line ahead 1 deg farther off)
    past = tilt - side * attitude.pitch_rad
    beyond = unexplained & (past > error)
    if attitude.tilted:
        return agree, beyond, np.zeros(len(distances), dtype=bool)
    return agree, beyond, beyond & (past > error + attitude.reach_rad)
