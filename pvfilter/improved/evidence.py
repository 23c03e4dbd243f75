"""Free-space evidence: how far in front of the level view each return lies.

A floor or ceiling line always lies in front of the structure a level scanner sees along
the same beams, in space that scanner saw as free (:mod:`pvfilter.improved.memory`). A
return is **new** when it lies in front of the level view by more than a margin: range
noise and the ego-motion's error, plus a share of the range for angular error. A return
**seen through** the view lies beyond it by more than that margin.
"""

from __future__ import annotations

import dataclasses
import math
from typing import NamedTuple

import numpy as np
from scipy.ndimage import minimum_filter1d

from pvfilter.improved.beams import BeamLayout
from pvfilter.improved.motion import Motion

STANDING_PITCH_CHANGE = math.radians(0.5)  # rad: the least a standing robot's pitch
# changes over the world-static baseline while a pitch event lasts (see WorldStatic)
GRAVITY_MPS2 = 9.81  # m/s^2: a balancing body holds a tilt p only while its axle
# accelerates at g tan p
STANDING_FALL_SHARE = 0.25  # beyond the steepest tilt a standing body could hold
# (WorldStatic.hold_tilt_rad), the least share of the excess by which its pitch changes
# over the baseline: a body up to 1 m above its axle (sqrt(l / g) <= 0.32 s) that was
# still at the earlier scan falls or is caught by (cosh(T sqrt(g / l)) - 1) >= 0.48 of
# it; half that, for the margin (one still rising then can come back to the same tilt)
STATIC_TOLERANCE_M = 0.03  # m: how near where it was seen before a return of the same
# surface lies (range noise of two measurements, plus the motion's or the level view's
# error; plus 1 % of the range): the world-static test, and a return on the level view
STATIC_FAR_BASELINE_S = 1.0  # s: where the scan within the baseline does not tell (or saw
# no return), the test asks the oldest kept scan up to this long ago (WorldStatic.farther)
MIN_FACING = 0.3  # cosine between beam and surface normal below which the world-static
# test does not tell (a grazing beam slides along its surface)
WINDOW_BEAMS = 1  # beams: a beam's level view is the nearest of its neighbours this far
# on each side (absorbs sub-beam misalignment after ego-motion)


def free_space_gaps(
    ranges: np.ndarray, level: np.ndarray, layout: BeamLayout, range_max: float
) -> np.ndarray:
    """Per beam: how far in front of the level view the return lies, m (NaN: unknown).

    The level view of a beam is the nearest of the ``WINDOW_BEAMS`` beams on each side;
    beams whose own view is unknown, and invalid beams (``ranges`` NaN), get NaN. Where the
    level view saw nothing, it saw free space up to ``range_max`` and no farther: a wall
    that comes into range is not new.
    """
    # unknown and farther than range_max: range_max, before the window's minimum (the
    # least of values capped at range_max is the least of them, capped)
    gaps = window_minimum(level, WINDOW_BEAMS, layout, range_max)
    gaps -= ranges  # (in place: the window's minimum is a new array)
    np.putmask(gaps, np.isnan(level), np.nan)  # (putmask: a boolean index costs more)
    return gaps


def new_points(
    gaps: np.ndarray, ranges: np.ndarray, margin_m: float, margin_rel: float
) -> np.ndarray:
    """Per beam: the return lies in front of the level view by more than the margin.

    Args:
        gaps: from :func:`free_space_gaps`, m.
        ranges: the scan's ranges, m (NaN where invalid).
        margin_m: fixed part of the margin, m.
        margin_rel: part of the margin per metre of range, 1.
    """
    return gaps > margin_m + margin_rel * ranges  # NaN (unknown, invalid) compares False


def seen_through(
    gaps: np.ndarray, ranges: np.ndarray, margin_m: float, margin_rel: float
) -> np.ndarray:
    """Per beam: the return lies beyond the level view by more than the margin (the
    beam passed where the view had a surface: it moved away, or the motion is off).

    Args as :func:`new_points`.
    """
    return gaps < -(margin_m + margin_rel * ranges)  # NaN compares False


def free_space_evidence(
    gaps: np.ndarray, ranges: np.ndarray, margin_m: float, margin_rel: float
) -> tuple[np.ndarray, np.ndarray | None]:
    """:func:`new_points` and :func:`seen_through` in one pass: the margin is worked out
    once for both. Where no return is new, the returns seen through the view tell nothing
    (they only weigh against lines with new returns): None then, not worked out.

    Args as :func:`new_points`.
    """
    margin = margin_rel * ranges
    margin += margin_m  # margin_m + margin_rel * ranges, as the two functions add them
    new = gaps > margin  # NaN (unknown, invalid) compares False
    if not np.count_nonzero(new):
        return new, None
    return new, gaps < np.negative(margin, out=margin)


def window_minimum(
    values: np.ndarray, half: int, layout: BeamLayout, cap: float = math.inf
) -> np.ndarray:
    """The least of ``values`` over beams ``i - half .. i + half``, each capped at ``cap``
    first (NaN counts as ``cap``). A new array.

    As ``scipy.ndimage.minimum_filter1d`` (wrapping on a ring, else repeating the end
    values), but for the usual window of three beams two ``np.minimum`` calls on a padded
    copy cost a fraction of scipy's set-up; the capped values are written into that copy
    at once.
    """
    n = len(values)
    if half == 0 or n == 0:
        return np.fmin(values, cap)
    if half >= n or half > 4:
        mode = "wrap" if layout.ring else "nearest"
        return minimum_filter1d(np.fmin(values, cap), 2 * half + 1, mode=mode)
    padded = np.empty(n + 2 * half)  # (filled by slices: cheaper than np.concatenate)
    np.fmin(values, cap, out=padded[half : n + half])
    if layout.ring:
        padded[:half], padded[n + half :] = padded[n : n + half], padded[half : 2 * half]
    else:
        padded[:half], padded[n + half :] = padded[half], padded[n + half - 1]
    least = np.minimum(padded[:n], padded[1 : n + 1])
    for offset in range(2, 2 * half + 1):
        np.minimum(least, padded[offset : offset + n], out=least)
    return least


def standing_pitch_change(tilt_rad: np.ndarray, hold_rad: float) -> np.ndarray:
    """The least change of pitch over the world-static baseline of a robot that stood, for
    a line at ``tilt_rad`` (rad, per segment): ``STANDING_PITCH_CHANGE``, and beyond the
    steepest tilt the body could hold meanwhile (``hold_rad``,
    :attr:`WorldStatic.hold_tilt_rad`) a share ``STANDING_FALL_SHARE`` of the excess. A
    balancing body that stands cannot hold a steep tilt: it falls, or its controller
    drives the axle from under it (and the sensor moves)."""
    excess = np.abs(tilt_rad) - hold_rad
    return np.maximum(STANDING_PITCH_CHANGE, STANDING_FALL_SHARE * excess)


@dataclasses.dataclass(frozen=True, eq=False)
class WorldStatic:
    """Which returns an earlier scan saw at the same place in the world.

    A wall stays where it is while the sensor moves; a floor line moves with the sensor
    (it lies ``h / sin(pitch)`` from it). The earlier range on the beam the turn brings
    here, moved by the translation ``t`` as the surface through the return sees it
    (``t . n / (u . n)`` along the beam ``u``, ``n`` the surface's normal from the local
    line direction), predicts where a static return lies now. The test tells only where
    the sensor moved along the beam by more than twice the tolerance, and not where the
    beam grazes the surface (``MIN_FACING``). It is evaluated only for the beams asked
    about (those of candidate lines).

    Where the sensor stood, a floor line still moves when the pitch changes, and a
    balancing robot that stands holds one pitch only at its balance point, where its
    plane meets no floor (or meets it where it always does, a mount's tilt: structure to
    the filter too). So there the test also tells where the line a return lies on would
    move by more than twice the tolerance for the least pitch change of a robot that
    stands (:func:`standing_pitch_change`: ``STANDING_PITCH_CHANGE``, more for a steep
    tilt, which a standing body cannot hold; ``floor_shift_m``, from
    :func:`pvfilter.improved.geometry.floor_shift`): a line that stayed put is a wall that
    came back into view, not the floor. The sensor stood only where the scan matches saw
    it stand (``travel_seen``): along a corridor, or while floor lines hide the walls
    ahead, a match that cannot see the drive reads a robot that drives on as standing,
    and its floor line as a line that stayed put.

    Where the sensor turned, the floor line of a tilt held through the turn keeps its
    place in the sensor frame, and near the foot of its perpendicular the range the turn
    brings to a beam hardly differs from the beam's own: there a surface fixed in the
    world and one fixed to the sensor predict the same range, and a return tells only
    where the two predictions lie more than twice the tolerance apart.

    Attributes:
        ranges: this scan's ranges per beam (mid-scan frame, unstretched), m; NaN where
            invalid.
        previous_ranges: the earlier scan's, m; NaN where invalid.
        directions: the local line direction per beam, rad (NaN: unknown).
        layout: the beams.
        since: the motion from the earlier scan to this one.
        tolerance_m: how near the prediction a static return lies, m (plus 1 % of range).
        travel_seen: every step since the earlier scan was measured along every
            direction (by the scan match, or the wheels): only then can the sensor be
            known to have stood.
        span_s: the time since the earlier scan, s.
        first_step_s: the time from the earlier scan to the scan after it, s.
        first_speed_mps: the sensor's mean speed over that step, m/s (inf: unknown).
            By default the history is unknown, and no tilt is too steep to hold.
        farther: the same test against an older scan, up to ``STATIC_FAR_BASELINE_S``
            back (None: none older kept), asked where this one does not tell or its scan
            saw no return on the beam (:meth:`offsets_or_farther`).
    """

    ranges: np.ndarray
    previous_ranges: np.ndarray
    directions: np.ndarray
    layout: BeamLayout
    since: Motion
    tolerance_m: float
    travel_seen: bool = True
    span_s: float = 0.0
    first_step_s: float = 0.0
    first_speed_mps: float = math.inf
    farther: WorldStatic | None = None

    @property
    def hold_tilt_rad(self) -> float:
        """The steepest tilt the body could have held since the earlier scan, rad.

        Holding a tilt ``p`` takes an acceleration of ``g tan p`` (the balance point
        moves with a mount's tilt or an offset centre of mass by a degree or two, within
        ``STANDING_PITCH_CHANGE``'s margin). An axle whose mean speed over the first step
        (``dt``) was ``v`` and that ended ``T`` later within ``d`` of where it started
        decelerated at most ``2 (d + v T) / (T (T - dt))``: at least ``a`` all the way
        puts it ``v T - a T (T - dt) / 2`` along. ``d`` is the sensor's measured motion
        plus twice the tolerance (the sensor swings about the axle with the pitch, and
        the match errs). Over 0.3 s at 10 Hz from rest: 2 m/s^2, 11.5 deg; with a first
        step at 0.4 m/s, 31 deg. Where the first step spans the whole baseline (one scan
        kept, below 3.3 Hz) nothing bounds it: pi/2.
        """
        span, first = self.span_s, self.first_step_s
        if first >= span or not math.isfinite(self.first_speed_mps):
            return 0.5 * math.pi
        reach_m = math.hypot(self.since.tx_m, self.since.ty_m) + 2.0 * self.tolerance_m
        most_mps2 = 2.0 * (reach_m + self.first_speed_mps * span) / (span * (span - first))
        return math.atan(most_mps2 / GRAVITY_MPS2)

    def tolerance_at(self, range_m: np.ndarray | float) -> np.ndarray | float:
        """How near its prediction a static return ``range_m`` away lies, m:
        ``tolerance_m`` plus 1 % of the range."""
        return self.tolerance_m + 0.01 * range_m

    def _same_returns(self, other: WorldStatic) -> bool:
        """This test and ``other`` start from the same returns (this scan's ranges and line
        directions, the layout and the tolerance), as a test and its :attr:`farther` do."""
        return (
            self.ranges is other.ranges
            and self.directions is other.directions
            and self.layout is other.layout
            and self.tolerance_m == other.tolerance_m
        )

    def offsets(self, beams: np.ndarray, floor_shift_m: np.ndarray | None = None) -> Offsets:
        """For ``beams``: how far each return lies from where a surface fixed in the world
        would lie, whether the test tells, and its tolerance (:class:`Offsets`).

        Args:
            beams: the beams asked about.
            floor_shift_m: per beam asked about, how far the floor line through its
                return would move for the least pitch change of a robot that stands
                (:func:`standing_pitch_change`), m (None: the sensor's own motion alone
                tells).
        """
        return self._offsets(self._returns(beams), floor_shift_m)

    def _returns(self, beams: np.ndarray) -> _Returns:
        """This scan's returns on ``beams`` and their surfaces: what the test against any
        earlier scan starts from."""
        layout = self.layout
        angle = self.directions.take(beams)
        # the surface's normal is (-sin, cos) of its direction: the sine is kept unnegated,
        # and the products with it subtracted (exactly the sums with the negated sine)
        sin_m, cos_m = np.sin(angle), np.cos(angle)
        facing = layout.sin.take(beams) * cos_m - layout.cos.take(beams) * sin_m  # u . n
        ranges = self.ranges.take(beams)
        tolerance = self.tolerance_at(ranges)
        facing_ok = np.abs(facing) > MIN_FACING
        return _Returns(beams, sin_m, cos_m, facing, facing_ok, ranges, tolerance, 2.0 * tolerance)

    def _offsets(self, returns: _Returns, floor_shift_m: np.ndarray | None) -> Offsets:
        """:meth:`offsets`, for this scan's returns on the beams asked about."""
        layout, since, beams = self.layout, self.since, returns.beams
        shift = round(since.theta_rad / layout.increment)
        toward = since.ty_m * returns.cos_m - since.tx_m * returns.sin_m  # t . n
        facing_ok = returns.facing_ok
        # how far a static return moved along its beam, m, where the beam faces its surface;
        # 0 at grazing incidence, where the quotient divides by nearly 0 and means nothing
        # (there only the standing sensor's pitch test below tells), and without the cost
        # of an errstate to silence a division by zero
        moved = np.divide(toward, returns.facing, out=np.zeros(len(beams)), where=facing_ok)
        earlier = layout.shifted(self.previous_ranges, shift).take(beams)
        tolerance, twice = returns.tolerance_m, returns.twice_m  # farther than twice tells
        telling = (np.abs(moved) > twice) & facing_ok
        if floor_shift_m is not None and self.travel_seen:
            # the sensor stood (a return's tolerance allows for its motion): a floor line
            # moves with the pitch, where the earlier scan saw a return (NaN compares False)
            travel_m = math.hypot(since.tx_m, since.ty_m)
            pitch_tells = (floor_shift_m > twice) & (earlier == earlier)
            if travel_m > 2.0 * self.tolerance_m:  # (else it stood for every return)
                pitch_tells &= travel_m <= twice
            telling |= pitch_tells
        if shift != 0:  # the sensor turned: a surface fixed to it keeps its beam
            telling &= np.abs(earlier - self.previous_ranges.take(beams)) > twice
        return Offsets(returns.ranges - (earlier + moved), telling, tolerance)

    def offsets_or_farther(
        self, beams: np.ndarray, floor_shift_m: np.ndarray | None = None
    ) -> Offsets:
        """:meth:`offsets`, and where they do not tell (or the baseline's scan saw no return
        on the beam), those of :attr:`farther` that do, by the sensor's own motion alone.

        The test tells where the sensor moved along the beam by more than twice the
        tolerance, which grows by 1 % of the range: over the baseline's 0.3-0.4 s (the
        oldest kept scan within 0.3 s of the scan before this one) a sensor at 0.5 m/s
        moves 0.15-0.2 m, which tells only within 4.5-7 m. A wall farther out that comes
        into view (into the scanner's reach for its surface, or out from behind a floor
        line a grazing plane met without an echo) stands where a floor line would, and the
        older scan, 1.0-1.1 s back, tells it apart: it stayed put in the world over the
        sensor's longer drive, where a floor line keeps its place in the sensor frame. The
        older scan must have seen a return on the beam; where it saw free space there, the
        wall is still told by neither.
        """
        returns = self._returns(beams)
        offsets = self._offsets(returns, floor_shift_m)
        # (where the baseline's scan saw no return on the beam it tells nothing either)
        untold = ~(offsets.telling & offsets.seen)
        farther = self.farther
        if farther is None or not np.count_nonzero(untold):
            return offsets
        if not farther._same_returns(self):  # (else this scan's returns are its own too)
            returns = farther._returns(beams)
        older = farther._offsets(returns, None)
        use = older.telling & older.seen & untold
        if not np.count_nonzero(use):
            return offsets
        world_m = np.where(use, older.world_m, offsets.world_m)
        return Offsets(world_m, offsets.telling | use, offsets.tolerance_m)


class Offsets(NamedTuple):
    """Where returns lie against an earlier scan (:meth:`WorldStatic.offsets`), per beam
    asked about, m along the beam; NaN where either scan saw nothing there."""

    world_m: np.ndarray  # from where a surface fixed in the world would lie now
    telling: np.ndarray  # bool: the sensor's motion (or a standing robot's pitch) tells
    tolerance_m: np.ndarray  # how near its prediction a return lies

    @property
    def stayed(self) -> np.ndarray:
        """bool: the test tells, and the return lies where it would had it stayed put."""
        return self.telling & (np.abs(self.world_m) <= self.tolerance_m)  # NaN compares False

    @property
    def seen(self) -> np.ndarray:
        """bool: the earlier scan saw a return on the beam (and this one has one)."""
        return self.world_m == self.world_m  # NaN compares False


class _Returns(NamedTuple):
    """This scan's returns on the beams asked about (:meth:`WorldStatic.offsets`) and the
    surfaces through them, the same against every earlier scan: worked out once where
    two are asked (:meth:`WorldStatic.offsets_or_farther`)."""

    beams: np.ndarray  # the beams asked about
    sin_m: np.ndarray  # sine of the local line direction (the normal is (-sin, cos))
    cos_m: np.ndarray  # its cosine
    facing: np.ndarray  # cosine between the beam and the normal (u . n)
    facing_ok: np.ndarray  # bool: the beam faces its surface (|u . n| > MIN_FACING)
    ranges: np.ndarray  # this scan's range, m
    tolerance_m: np.ndarray  # how near its prediction a static return lies, m
    twice_m: np.ndarray  # twice that: a motion along the beam beyond it tells, m


class Earlier(NamedTuple):
    """A scan the world-static test compares with (:meth:`RecentScans.oldest`, and
    :meth:`RecentScans.oldest_farther` for :attr:`WorldStatic.farther`)."""

    ranges: np.ndarray  # its ranges (mid-scan frame, unstretched), m
    since: Motion  # the motion from it to now
    travel_seen: bool  # every step since was measured along every direction
    span_s: float  # the time from it to now, s
    first_step_s: float  # the time from it to the scan after it (now, if none kept), s
    first_speed_mps: float  # the sensor's mean speed over that first step, m/s


class _Kept(NamedTuple):
    """A scan :class:`RecentScans` keeps."""

    stamp: float  # s
    ranges: np.ndarray  # m (mid-scan frame, unstretched)
    pose: Motion  # from the fixed frame to the scan's
    unseen_before: int  # how many steps before it the matches could not see


class RecentScans:
    """The ranges of the scans of the last ``far_baseline_s`` seconds (mid-scan frame,
    unstretched) and where the sensor was for each: what the world-static test compares
    with, the scan ``baseline_s`` back and, for the returns that one does not tell, the
    oldest kept.

    The sensor's pose is kept as the motion from a fixed frame (the first scan's) to each
    scan's, so a scan costs one composition, and the motion between two of them is
    worked out only when asked for.
    """

    def __init__(self, baseline_s: float, far_baseline_s: float | None = None) -> None:
        self.baseline_s = baseline_s
        self.far_baseline_s = baseline_s if far_baseline_s is None else far_baseline_s
        self.scans: list[_Kept] = []
        self.pose = Motion()  # the fixed frame -> the latest scan's
        self.unseen_steps = 0  # steps so far whose drive the matches could not see

    def clear(self) -> None:
        """Forget them (a re-baseline). The count of unseen steps runs on: only its
        change since a kept scan is asked for."""
        self.scans.clear()
        self.pose = Motion()

    def advance(self, step: Motion, seen: bool = True) -> None:
        """Take the sensor's step to the scan now (``seen``: measured along every
        direction)."""
        self.pose = self.pose.then(step)
        self.unseen_steps += not seen

    def oldest(self, stamp: float) -> Earlier | None:
        """The oldest kept scan within ``baseline_s`` of the latest kept one, seen from
        the scan now at ``stamp`` (None: none kept)."""
        if not self.scans:
            return None
        return self._earlier(self._first_within(self.baseline_s), stamp)

    def oldest_farther(self, stamp: float) -> Earlier | None:
        """The oldest kept scan, where it is older than :meth:`oldest`'s, seen from the
        scan now at ``stamp`` (None: no such scan)."""
        if not self.scans or self._first_within(self.baseline_s) == 0:
            return None
        return self._earlier(0, stamp)

    def add(self, stamp: float, ranges: np.ndarray) -> None:
        """Take the scan now in, and drop those older than ``far_baseline_s`` (keeping
        one)."""
        self.scans.append(_Kept(stamp, ranges, self.pose, self.unseen_steps))
        while stamp - self.scans[0].stamp > self.far_baseline_s:
            self.scans.pop(0)

    def _first_within(self, span_s: float) -> int:
        """The index of the oldest kept scan within ``span_s`` of the latest kept one."""
        latest = self.scans[-1].stamp
        index = 0
        while latest - self.scans[index].stamp > span_s:
            index += 1
        return index

    def _earlier(self, index: int, stamp: float) -> Earlier:
        """The kept scan ``index``, seen from the scan now at ``stamp``."""
        earliest = self.scans[index]
        since = earliest.pose.inverse().then(self.pose)
        # the first step after it: to the next kept scan, or to now
        after_stamp, after_pose = stamp, self.pose
        if len(self.scans) > index + 1:
            after_stamp, after_pose = self.scans[index + 1].stamp, self.scans[index + 1].pose
        first_step_s = after_stamp - earliest.stamp
        first_m = earliest.pose.inverse().then(after_pose).translation_m
        speed = first_m / first_step_s if first_step_s > 0.0 else math.inf
        seen = earliest.unseen_before == self.unseen_steps
        return Earlier(earliest.ranges, since, seen, stamp - earliest.stamp, first_step_s, speed)
