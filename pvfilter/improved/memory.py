"""The level-view memory: what each beam saw when the scan plane was level.

The paper's likelihood field compares a scan with the scan just before it, so a floor
line is "new" only in its first frame. Physics gives a cue that lasts the whole pitch
event: a floor (or ceiling) line always lies **in front of** the structure a level
scanner sees along the same beams, in space the scanner saw as free a moment ago
(:mod:`pvfilter.improved.evidence`). The structure itself does not come closer faster
than the sensor moves, and the sensor's motion is known (:mod:`pvfilter.improved.motion`).

So the memory keeps, per beam, the range of the level view in the current sensor frame:

- each scan, it is moved by the ego-motion (points transformed, then binned back into
  beams; the nearest point wins a beam; one-beam holes take a neighbour's view);
- only **level** scans teach it (scans with no candidate line, and, with an IMU, a small
  tilt): a tilted plane sees past furniture and under tables, and what it sees there must
  not become free space that a level scan later finds occupied. While the plane is
  tilted the view only moves, and its clock stands still;
- space newly seen as free (a level return farther than the view) joins the view only
  once it has been seen for ``confirm_free_s``;
- behind a segment that may be a floor line (``hold_behind_lines``: a candidate line,
  or one that continues a recent strong line, :mod:`pvfilter.improved.follow`) the view
  does not come closer at all. Behind any other segment across the direction of travel,
  where a floor line can lie, it comes closer by at most ``line_shrink_mps`` times the
  time step plus the sensor's travel in it: a floor line that a scan or two fail to
  detect (they count as level; a held tilt's line whose pitch drifted, say) stays in
  front of the view, new, and is found again; and the ego-motion's error along x, which
  shows on exactly those segments, is at most the travel. Elsewhere a return pulls it
  closer by at most ``memory_shrink_mps`` times the time step (a person walking in, an
  ego-motion error);
- a surface the view gave up for space seen free beyond it, that a return finds where it
  stood within ``memory_timeout_s``, is back (:meth:`LevelView.surfaces_back`): it is not
  new, and a level scan puts it back into the view at once. A low top or a cabinet that
  the plane passes over as the robot rocks on a rough floor comes and goes; it is
  structure, not a line sweeping in;
- beams with no return within range (``+inf``) remember free space up to ``range_max``
  where the view knew nothing (a sequence's first scan leaves them unknown: one scan's
  silence, a sensor blinded by a person touching it, is not space seen free, and the
  wall behind would be new in the next scan; a second silent scan frees them); but a
  beam without an echo next to a beam that returns on the view or in front of it frees
  nothing: a dark surface, or one met at grazing incidence, echoes on some beams and
  some scans only, and its silent beams are dropouts, not space seen free. Nor does
  silence free a surface the view holds: a plane tilted by two or three degrees, too
  little to show a floor line, meets the floor at a grazing angle that returns no echo
  on a whole run of beams and hides the wall behind it; taken for free space, the wall
  would be new when the plane levels and it returns. The surface stays in the view,
  unconfirmed, until it is forgotten (below), and then a silent beam frees it. Nor does
  a silent beam beside a beam the scanner could not measure (``NaN``, ``-inf``) free
  anything: a body at the edge of ``range_min`` reads now too close, now no echo;
- free space stays free as the view moves (a free point moved off ``range_max`` is no
  surface just inside it), except where a turn carries it from a beam that is still
  silent onto a beam that returns now: silence that keeps to its beams while the sensor
  turns is fixed to the sensor, not to the world (a sector the robot's body blocks,
  which some drivers report as no echo), and the walls the turn brings beside it stand
  in front of nothing the scanner saw free. There the view knows nothing. Free space in
  the world moves off its beams with the turn, and where it came from the scan sees
  something now;
- a beam's view is forgotten (NaN, unknown) after ``memory_timeout_s`` without a return;
- so is a beam whose near return is fixed to the sensor, the robot's own body
  (:mod:`pvfilter.improved.body`, :meth:`LevelMemory.forget`): it moves with the sensor,
  and carried with the motion as a surface of the world it slid across the beams beside
  it and stood, decimetres away, in front of everything there. Where the body has
  stayed on its beams for a while (a mast), its returns teach the view nothing, and the
  view keeps the world it knew behind it: as the robot turns, that knowledge turns with
  it onto the beams beside;
- a remembered surface that the sensor passes on the way the motion carries it, nearer
  than the scanner measures (``range_min``, and at least ``NEAREST_SURFACE_M``, its own
  housing), was never one the sensor could meet: a ramp's slope or a floor met at a
  grazing angle that a level scan took for a wall, which the robot then drove onto. It
  leaves the view; carried on, it came out behind the sensor, a few centimetres away, in
  front of everything there, and the floor line behind a robot climbing that ramp lay
  beyond the view, not new. (The robot's own body at the edge of ``range_min`` mostly
  ends near the sensor without being passed, and stays until it is found fixed to the
  sensor, above; where a drive does pass it, the next scan returns it again.) Only a
  strip as wide as the scanner's housing is cleared: the rest of such a surface beside
  the path stays until forgotten or replaced;
- a return that has stayed in front of the view for ``max_event_s`` (longer than a pitch
  event lasts) replaces it: the view was wrong. A level scan in which the beam returned
  no echo says nothing of what stands there: it neither stops that clock nor starts it
  (in a tilted scan it does stop it: a floor line moves with the pitch, and where it
  went silent it has moved on).

The memory does not depend on what the filter removed (the segments it holds behind are
chosen whatever ``p_th``), so the filter's state, and with it every threshold of a
precision-recall sweep, follows from the scans alone.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from pvfilter.improved.beams import BeamLayout, indices
from pvfilter.improved.motion import Motion
from pvfilter.improved.params import ImprovedParams
from pvfilter.improved.sweep import move_xy

NEAREST_SURFACE_M = 0.05  # m: no surface the scanner saw lies nearer to it than its own
# housing (a LiDAR's radius is a few centimetres)


def _carried_row(row: int, doc: str) -> property:
    """A property reading row ``row`` of a :class:`LevelView`'s ``carried`` block."""
    return property(lambda view: view.carried[row], doc=doc)


@dataclasses.dataclass(frozen=True, eq=False)
class LevelView:
    """The level view per beam of one scan.

    Attributes:
        ranges: m; NaN unknown, ``+inf`` free up to ``range_max``.
        carried: the values each beam carries along besides its range, one row each
            (``ages``, ``ahead_s``, ``farther_s``, ``dropped_s``, ``dropped_m``), ``(5,
            count)``: moving the view gathers them in one take, and a scan advances the
            four clocks in one add.
        free_m: per free beam (``ranges`` ``+inf``), how far the space along it is known
            free, m: ``range_max`` where a level scan last saw no echo there, less as the
            sensor comes closer (NaN elsewhere; None: ``range_max`` on every free beam).
    """

    ranges: np.ndarray
    carried: np.ndarray
    free_m: np.ndarray | None = None

    # the rows of ``carried``, by name (views: a write changes the block)
    ages = _carried_row(0, "s since a level return last confirmed the beam.")
    ahead_s = _carried_row(1, "s for which the beam's returns have been in front of the view.")
    farther_s = _carried_row(2, "s for which the beam's level returns have been beyond the view.")
    dropped_s = _carried_row(3, "s since the view gave up the surface of :attr:`dropped_m`.")
    dropped_m = _carried_row(
        4,
        "How far in front of the view stood the surface it gave up when space seen free "
        "beyond it joined, m (NaN: none).",
    )

    def known_free_m(self) -> np.ndarray:
        """Per beam, where the view lies for new returns, m: its surface, or on a free
        beam as far as the space is known free (``+inf``: as far as the scan reaches; NaN
        unknown). ``free_m`` is NaN wherever the beam is not free, so one ``fmin`` picks."""
        return self.ranges if self.free_m is None else np.fmin(self.ranges, self.free_m)

    def surfaces_back(self, ranges: np.ndarray, params: ImprovedParams) -> np.ndarray | None:
        """Per beam: the return lies where a surface the view gave up stood, within the
        free-space margin, given up at most ``memory_timeout_s`` ago: that surface is back
        (None: the view gave none up that recently)."""
        recent = self.dropped_s <= params.memory_timeout_s
        if not np.count_nonzero(recent):  # (most scans)
            return None
        margin = params.free_margin_m + params.free_margin_rel * np.fmin(ranges, 1e9)
        # NaN (nothing given up, an invalid return) compares False
        return recent & (np.abs(self.ranges - ranges - self.dropped_m) <= margin)

    @classmethod
    def empty(cls, n: int) -> LevelView:
        """A view that knows nothing, of ``n`` beams."""
        return cls.seen(np.full(n, np.nan), np.full(n, np.inf))

    @classmethod
    def seen(cls, ranges: np.ndarray, ages: np.ndarray) -> LevelView:
        """A view of ``ranges`` with ``ages``, its clocks at 0, no surface given up."""
        carried = np.empty((len(_NOTHING), len(ranges)))
        carried[:] = _NOTHING
        carried[0] = ages
        return cls(ranges, carried)


class LevelMemory:
    """Per-beam level view of the scans so far, in the last scan's sensor frame."""

    def __init__(self) -> None:
        self.state: LevelView | None = None
        self.velocity = Motion()  # the sensor's motion per second during the last scan
        self.time_increment = 0.0  # s between the beams of the last scan

    def reset(self) -> None:
        """Forget everything (a new sequence)."""
        self.state = None

    def view(
        self,
        layout: BeamLayout,
        range_max: float,
        motion: Motion,
        velocity: Motion,
        time_increment: float,
        params: ImprovedParams,
        no_echo: np.ndarray | None = None,
        returned: np.ndarray | None = None,
        range_min: float = 0.0,
    ) -> LevelView:
        """The level view of each beam of the current scan: the memory moved by ``motion``.

        With a rotating LiDAR the remembered beams are first moved to the last scan's
        mid-scan frame, and after the motion to where the current scan's beams see them
        (``velocity``: the sensor's motion per second now). Does not change the memory;
        :meth:`update` does, with what this returns.

        ``no_echo`` and ``returned`` (bool per beam of the current scan: no echo within
        range, a valid return; None: not known) let free space that the motion carries
        from a beam still silent onto another beam that returns be taken for what it is:
        no sight of free space (see the module docstring: a sector the body blocks).
        ``range_min``: the scanner's, m; a remembered point that the sensor passes nearer
        than it (or than ``NEAREST_SURFACE_M``) leaves the view (see the module docstring).
        """
        state = self.state
        # free space is a point where it is known free to, an unknown beam (fmin ignores
        # NaN) one at range_max: every beam has a point to move (range_max is finite), so
        # no beam is left out
        remembered = np.fmin(state.ranges, range_max)
        if state.free_m is not None:  # (state.known_free_m(), without its own array)
            np.fmin(remembered, state.free_m, out=remembered)
        before_x, before_y = remembered * layout.cos, remembered * layout.sin
        x, y = move_xy(
            before_x,
            before_y,
            layout.every_beam(),
            layout,
            motion,
            (self.time_increment, self.velocity),
            (time_increment, velocity),
        )
        ranges = np.sqrt(x * x + y * y)  # (np.hypot costs twice as much; no overflow in m)
        beams = layout.beam_at(x, y, finite=True)  # (remembered: at most range_max)
        # the moved points, by their beams; each beam's nearest range is its view already,
        # but points the sensor passed were no surfaces it could meet and are left out (a
        # point moves by the motion's translation, and by the sensor's during half a scan
        # before and after it, at most: only points that near now can have come near)
        half_count = 0.5 * layout.count  # beams from mid-scan to either end
        travel_m = motion.translation_m + half_count * (
            abs(self.time_increment) * self.velocity.translation_m
            + abs(time_increment) * velocity.translation_m
        )
        nearest_m = max(range_min, NEAREST_SURFACE_M)
        too_near = _passed_near(before_x, before_y, x, y, ranges, travel_m + nearest_m, nearest_m)
        if too_near is not None:  # (mostly none)
            kept = indices(~too_near)
            order, nearest, holes = nearest_by_beam(beams.take(kept), ranges.take(kept), layout)
            order = kept.take(order)
        else:
            order, nearest, holes = nearest_by_beam(beams, ranges, layout)
        # per beam, the remembered beam whose values it carries on (-1: none); worked out
        # first, so that each of the values a beam carries is gathered once
        source = np.empty(layout.count, dtype=np.intp)
        source.fill(-1)  # (np.full costs a Python-level call)
        source[beams.take(order)] = order
        unseen = _fill_single_holes(nearest, source, holes, layout)
        view = LevelView(nearest, state.carried.take(source, axis=1))
        # no point landed on the unseen beams or beside them: the view knows nothing there
        if unseen.size:  # (mostly none: on a full turn, double holes only)
            view.carried[:, unseen] = _NOTHING
        # free space stays free where a beam was carried from a free one (as a surface,
        # the moved point that bounds it would put every wall coming into view in front
        # of it; a beam no point landed on, source -1, takes the last beam's here, and its
        # infinite age makes it unknown just below), known free as far as that point lies:
        # the sensor that came 0.2 m closer knows the space free 0.2 m less far, and a
        # wall that comes into range there stands beyond it, not new
        carried_free = state.ranges.take(source) == np.inf
        free_m = None  # (a closed room: no beam free, nothing to bound)
        if np.count_nonzero(carried_free):
            free_m = np.where(carried_free, view.ranges, np.nan)
            view.ranges[carried_free] = np.inf
        # (putmask: a boolean index costs a third more)
        np.putmask(view.ranges, view.ranges >= range_max - 1e-6, np.inf)
        np.putmask(view.ranges, view.ages > params.memory_timeout_s, np.nan)
        if no_echo is not None and returned is not None:
            _forget_carried_silence(view, state.ranges, source, no_echo, returned)
        if free_m is not None:
            free_m[view.ranges != np.inf] = np.nan  # (unseen, forgotten: not free)
            object.__setattr__(view, "free_m", free_m)
        return view

    def forget(self, beams: np.ndarray) -> None:
        """The view knows nothing on ``beams`` (bool per beam): they return the robot's
        own body (:mod:`pvfilter.improved.body`), which moves with the sensor and is no
        surface of the world the ego-motion could carry."""
        state = self.state
        if state is None:
            return
        # (in place: the state is this memory's own; view() builds new arrays from it)
        forget = indices(beams)
        state.carried[:, forget] = _NOTHING
        state.ranges[forget] = np.nan
        if state.free_m is not None:
            state.free_m[forget] = np.nan

    def update(
        self,
        ranges: np.ndarray,
        no_return: np.ndarray,
        view: LevelView | None,
        dt: float,
        params: ImprovedParams,
        level: bool,
        hold: np.ndarray | None = None,
        velocity: Motion | None = None,
        time_increment: float = 0.0,
        across: np.ndarray | None = None,
        back: np.ndarray | None = None,
        range_max: float = math.inf,
        travelling: np.ndarray | None = None,
    ) -> None:
        """Take a scan into the memory.

        Args:
            ranges: the scan's ranges per beam, m; NaN where invalid.
            no_return: per beam, nothing within ``range_max`` (``+inf``).
            view: what :meth:`view` returned for it; None for the first scan of a sequence.
            dt: time since the previous scan, s.
            params: the margins, ``memory_shrink_mps``, ``line_shrink_mps``,
                ``confirm_free_s``, ``max_event_s``.
            level: the scan plane was level: the scan may teach the view.
            hold: bool per beam: the view does not come closer there (None: nowhere).
            velocity: the sensor's motion per second during the scan (None: standing).
            time_increment: the scan's time between beams, s.
            across: bool per beam: it lies on a segment across the direction of travel,
                long enough to be a floor line (None: none does).
            back: bool per beam: a surface the view gave up is back there, as
                :meth:`LevelView.surfaces_back` finds for this scan (None: nowhere).
            range_max: the scan's range limit, m: how far its silent beams see free.
            travelling: bool per beam: on a floor line that travels with the sensor, which
                stays in front of the view past ``max_event_s`` without settling onto it
                (:func:`pvfilter.improved.follow.travelling_line`; None: nowhere).
        """
        self.velocity = velocity if velocity is not None else Motion()
        self.time_increment = time_increment
        valid = ranges == ranges  # NaN compares False
        if view is None:  # the first scan of a sequence: its returns (its silent beams
            # stay unknown: one scan's silence, a blinded sensor or a dark wall, is not
            # space seen free; the next silent scan frees them)
            level_ranges = ranges.copy()
            seen = np.where(valid, 0.0, np.inf)
            self.state = LevelView.seen(level_ranges, seen)
            return
        current = view.ranges.copy()
        # a return beyond where a free beam is known free stands where the view knew
        # nothing: not in front of it (a wall coming into range), but beyond it, as space
        # newly seen free is: a level scan takes it once it has stood there for
        # confirm_free_s (the far end of a floor line as the plane starts to tilt, taken
        # at once, became a surface that the closer returns of the growing tilt pulled
        # along, and the line was never new)
        past_free = _past_free(current, view.free_m, ranges, valid, range_max, params)
        if past_free.size and hold is not None:  # behind a candidate line it stays as it is
            past_free = past_free.take(indices(~hold.take(past_free)))
        shrink = params.memory_shrink_mps * dt
        floor = current - shrink if shrink < np.inf else np.full(len(ranges), -np.inf)
        travel_m = math.hypot(self.velocity.tx_m, self.velocity.ty_m) * dt
        creep = params.line_shrink_mps * dt + travel_m
        if creep < shrink and across is not None and np.count_nonzero(across):
            np.subtract(current, creep, out=floor, where=across)
        if hold is not None and np.count_nonzero(hold):  # (most scans hold nowhere)
            np.copyto(floor, current, where=hold)
        # the four clocks run on by dt (a tilted scan puts back the two that stand still
        # in it), the surfaces given up are kept: one add over all five rows, the last
        # then put back, costs less than an add into four of them
        carried = view.carried + dt
        carried[4] = view.carried[4]
        ages, ahead, farther, dropped_s, dropped_m = carried
        if level and back is not None and np.count_nonzero(back):  # taken back at once
            floor[back] = -np.inf
            dropped_m[back] = np.nan
        np.fmax(floor, -np.inf, out=floor)  # NaN (unknown) becomes -inf
        in_front = ranges < floor  # NaN (invalid) compares False
        if past_free.size:
            in_front[past_free] = False
        # in front of the view this long (ahead: ahead_s + dt): the clocks are finite and
        # >= 0 (sums of time steps), so times True or False is np.where(in_front, ahead_s +
        # dt, 0.0), cheaper. In a level scan a beam without an echo says nothing of what
        # stands in front of the view (a dark wall echoes on some scans only): its clock
        # runs on if it ran, and a return settles the view only when there is one (in a
        # tilted scan the floor line moves with the pitch: where it went silent, it has
        # moved on)
        ahead *= in_front | (no_return & (view.ahead_s > 0.0)) if level else in_front
        settling = (ahead > params.max_event_s) & in_front
        if travelling is not None:  # (a floor line held past an event's length: not yet)
            settling &= ~travelling
        settled = indices(settling)  # (indices: mostly none)
        if settled.size:
            ahead[settled] = 0.0
        if not level:  # a tilted plane: the view only moves, and its clock stands still
            free_m = view.free_m
            if settled.size:
                current[settled] = ranges.take(settled)
                if free_m is not None:  # (no longer free there)
                    free_m = free_m.copy()
                    free_m[settled] = np.nan
            carried[0], carried[2] = view.ages, view.farther_s  # (tilted: these stand still)
            self.state = LevelView(current, carried, free_m)
            return
        # free_margin_m + free_margin_rel * ranges (finite), then the view plus it, in place
        margin = np.fmin(ranges, 1e9)
        margin *= params.free_margin_rel
        margin += params.free_margin_m
        beyond = ranges > np.add(current, margin, out=margin)
        if past_free.size:
            beyond[past_free] = True
        silent = no_return & (current != np.inf)
        measured = valid | no_return  # (an echo, or none within range: no NaN, no -inf)
        lost = None
        if np.count_nonzero(silent):
            # no echo beside a return on the view or in front of it: a dropout of that
            # surface, not space seen free (the first and last beams have one neighbour
            # each, on a full turn too: one pair of beams, not worth a wrap)
            no_surface = beyond | ~valid
            silent[1:] &= no_surface[:-1]
            silent[:-1] &= no_surface[1:]
            # nor where the view holds a surface: an echo lost (a floor met at a grazing
            # angle by a plane tilted too little to show a line hides the wall behind it
            # on a whole run of beams) is not space seen free; the surface stays in the
            # view, unconfirmed, until it times out (``memory_timeout_s``)
            lost = silent & (current < np.inf)  # (NaN, unknown, compares False)
            # nor beside a beam the scanner could not measure (NaN, -inf): a body at the
            # edge of range_min reads now too close, now no echo
            freed = silent ^ lost  # (silent & ~lost: lost lies within silent)
            freed[1:] &= measured[:-1]
            freed[:-1] &= measured[1:]
            beyond |= freed
        farther *= beyond  # np.where(beyond, farther_s + dt, 0.0), as for ahead
        unknown = np.isnan(current)
        take = beyond & ((farther >= params.confirm_free_s) | unknown)
        # (in a room where nothing changes, the throughput benchmark's, no scan takes a
        # beam: the nine array operations for the beams taken are then skipped in one test)
        taken = np.count_nonzero(take) > 0
        if taken:
            gave_up = indices(take & valid & (current < np.inf))  # NaN compares False
            if gave_up.size:  # the surface the view held there, remembered for a while
                dropped_m[gave_up] = ranges.take(gave_up) - current.take(gave_up)
                dropped_s[gave_up] = 0.0
        # a return near the view, or in front of it, moves it (closer: at most the shrink)
        # where valid & ~beyond (for bools, a > b is a & ~b: one operation, not two)
        np.fmax(ranges, floor, out=current, where=valid > beyond)
        if settled.size:
            current[settled] = ranges.take(settled)
        if taken:  # space seen free long enough joins the view (beyond it: none of the
            # beams written above, which lie on the view or in front of it)
            np.copyto(current, ranges, where=valid & take)
            current[no_return & take] = np.inf
            farther[take] = 0.0
        confirmed = measured  # a lost echo confirms nothing
        if lost is not None:
            confirmed &= ~lost
        np.putmask(ages, confirmed, 0.0)  # (a boolean index costs a third more)
        # free where the view is free; as far as range_max where this scan saw no echo
        free = current == np.inf
        free_m = None  # (no beam free: nothing to bound)
        if np.count_nonzero(free):
            free_m = np.full(len(current), np.nan) if view.free_m is None else view.free_m.copy()
            free_m[~free] = np.nan
            free_m[no_return & free] = range_max
        self.state = LevelView(current, carried, free_m)


def nearest_first(beams: np.ndarray, ranges: np.ndarray, layout: BeamLayout) -> np.ndarray:
    """The moved points to write into their beams, in an order in which each beam's
    nearest point comes last (and wins it); points outside the scan's angles left out
    (``ranges``: the points' ranges, m, all finite).

    Each beam's nearest point is found with one unbuffered minimum per beam, about a
    third of the cost of sorting all points by range; then each beam has one point to
    write. Where two points tie for a beam's nearest, the sort by range decides, as it
    always did (its order among equal ranges picks the one written last).
    """
    return nearest_by_beam(beams, ranges, layout)[0]


def nearest_by_beam(
    beams: np.ndarray, ranges: np.ndarray, layout: BeamLayout
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`nearest_first`, per beam the range of its nearest point (NaN: no point
    lands on it): the very ranges that order writes (ties have equal ranges), and the
    beams no point lands on (indices, ascending)."""
    nearest = np.empty(layout.count)
    nearest.fill(np.nan)  # no point yet: fmin takes any range over NaN
    if layout.ring:  # on a ring every point lands on a beam
        np.fmin.at(nearest, beams, ranges)
        order = indices(ranges == nearest.take(beams))
    else:
        inside = indices(beams >= 0)
        inside_beams = beams.take(inside)
        np.fmin.at(nearest, inside_beams, ranges.take(inside))
        order = inside.take(indices(ranges.take(inside) == nearest.take(inside_beams)))
    holes = indices(np.isnan(nearest))
    if order.size == layout.count - holes.size:  # one nearest point per beam
        return order, nearest, holes
    order = np.argsort(-ranges)
    if not layout.ring:
        order = order[beams[order] >= 0]
    return order, nearest, holes


def _passed_near(
    before_x: np.ndarray,
    before_y: np.ndarray,
    x: np.ndarray,
    y: np.ndarray,
    ranges: np.ndarray,
    reach_m: float,
    nearest_m: float,
) -> np.ndarray | None:
    """Per remembered point: on its way from ``(before_x, before_y)`` to ``(x, y)`` (its
    place in the sensor's frame before and after the motion, m; ``ranges``: after) it
    passed the sensor within ``nearest_m`` (None: none did). Only points within
    ``reach_m`` now (the most a point moved, plus ``nearest_m``) are looked at. A point
    moves along a nearly straight path in one scan's time: one that came out behind the
    sensor passed through it. One that only ends near it stays: the robot's own body,
    at the edge of ``range_min``, moves a little as the view moves it, but the sensor
    does not pass it (the view forgets it once it is found fixed to the sensor:
    :meth:`LevelMemory.forget`)."""
    candidates = indices(ranges < reach_m)
    if candidates.size == 0:
        return None
    start_x, start_y = before_x.take(candidates), before_y.take(candidates)
    along_x = x.take(candidates) - start_x
    along_y = y.take(candidates) - start_y
    length2 = np.maximum(along_x * along_x + along_y * along_y, 1e-18)
    nearest_at = -(start_x * along_x + start_y * along_y) / length2  # 0-1: on the way
    gap = np.hypot(start_x + nearest_at * along_x, start_y + nearest_at * along_y)
    passed = (gap < nearest_m) & (nearest_at > 0.0) & (nearest_at < 1.0)
    came_near = candidates.take(indices(passed))
    if came_near.size == 0:
        return None
    near = np.zeros(len(ranges), dtype=bool)
    near[came_near] = True
    return near


def _forget_carried_silence(
    view: LevelView,
    remembered: np.ndarray,
    source: np.ndarray,
    no_echo: np.ndarray,
    returned: np.ndarray,
) -> None:
    """Make unknown (in place) the free space (``remembered``: the memory's ranges, +inf
    free) the motion carried onto a beam that returns now from another beam that is
    still silent: silence that stays on its beam while the sensor turns is fixed to the
    sensor, not to the world (a sector the robot's body blocks, read as no echo), and
    the walls beside it stand in front of no free space. Free space seen in the world
    moves off its beams with the turn: where it came from, the scan sees something now
    (a wall, the floor line of a pitch event).

    A beam that returns now and carries its own silent beam's values cannot be (it is
    not silent), so no test of "moved" is needed; a beam no point landed on (source -1)
    is unknown already.
    """
    # per remembered beam: free (or unknown, which a silent scan confirmed and the move
    # makes free space too) and silent now; +inf and NaN both fail "< inf"
    # no_echo & ~(remembered < inf): for bools, a > b is a & ~b, in one operation
    from_silence = no_echo > (remembered < np.inf)
    if not np.count_nonzero(from_silence):  # (a closed room: no silence to carry)
        return
    carries_silence = returned & from_silence.take(source)
    if not np.count_nonzero(carries_silence):  # (most scans: no turn, no silence to carry)
        return
    forget = indices(carries_silence)
    view.carried[:, forget] = _NOTHING
    view.ranges[forget] = np.nan


def _past_free(
    current: np.ndarray,
    free_m: np.ndarray | None,
    ranges: np.ndarray,
    valid: np.ndarray,
    range_max: float,
    params: ImprovedParams,
) -> np.ndarray:
    """The beams (indices) the view holds free whose return lies beyond where they are
    known free, less the free-space margin: as far as ``free_m`` says (``range_max``
    where it says nothing)."""
    returned = indices(valid & (current == np.inf))
    if returned.size == 0:
        return returned
    at = ranges.take(returned)
    bound = np.full(returned.size, range_max) if free_m is None else free_m.take(returned)
    np.fmin(bound, range_max, out=bound)
    margin = params.free_margin_m + params.free_margin_rel * at
    return returned.take(indices(at >= bound - margin))


def _fill_single_holes(
    ranges: np.ndarray, source: np.ndarray, hole: np.ndarray, layout: BeamLayout
) -> np.ndarray:
    """Give beams that no remembered point landed on (``hole``: indices, ascending) their
    nearer neighbour's range and source (in place; ``ranges``: NaN where no point landed,
    ``source``: per beam, the remembered beam whose values it carries on; on a ring, beam
    0 and the last are neighbours). Returns the beams left without (indices): no point
    landed on them or beside them.

    The two edges of a scan that covers less than a full turn are no neighbours: a turn
    that vacated the first beams had filled beam 0 with the view at the other edge of the
    field of view, 120 to 180 degrees away, and that surface, metres off the wall the beam
    sees, stayed in the view as the turn carried it on (a 240-degree scanner turning in
    place: the wall at the edge 1 m in front of it, new, removed at score 1).
    """
    if hole.size == 0 or hole.size == layout.count:
        return hole
    # each hole's neighbours (holes, 2) and their ranges, in one gather each from the
    # layout's table (off a ring, an edge beam's own NaN stands for the side beyond the
    # field of view)
    sides = layout.neighbours().take(hole, axis=0)
    on_sides = ranges.take(sides)
    on_left = on_sides[:, 0]
    # the nearer neighbour's range, the left one's on a tie (NaN only where both are NaN)
    value = np.fmin(on_left, on_sides[:, 1])
    neighbour = np.where(value == on_left, sides[:, 0], sides[:, 1])
    known = value == value  # NaN (both neighbours unknown) compares False
    fill = indices(known)
    left_without = _NO_BEAMS
    if fill.size < hole.size:
        left_without = hole.take(indices(~known))
        hole, neighbour, value = hole.take(fill), neighbour.take(fill), value.take(fill)
    ranges[hole] = value
    source[hole] = source.take(neighbour)
    return left_without


_NO_BEAMS = np.empty(0, dtype=np.intp)  # (not to be changed)
_NO_BEAMS.flags.writeable = False

# the values of :attr:`LevelView.carried` where the view knows nothing (as
# :meth:`LevelView.seen` with an infinite age): never confirmed, no clock running, no
# surface given up; a column, to write into the rows at once
_NOTHING = np.array([[np.inf], [0.0], [0.0], [np.inf], [np.nan]])
_NOTHING.flags.writeable = False
