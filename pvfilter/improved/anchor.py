"""Re-anchoring the level view: the remembered view registered against the current scan.

The level view follows the sensor by dead reckoning: each scan it is moved by the scan
match's step (:mod:`pvfilter.improved.egomotion`). Over a pitch event the steps are the
least sure: the walls a tilted plane still meets are stretched, and floor lines hide the
walls that show the motion. The errors add up, and after the event the view sits tens of
centimetres (and a few degrees) off. The wall ahead then stands in front of the view and
looks like a floor line, for as long as ``max_event_s``; on the independent sequences
with counter-pitching robots that was most of the false alarms.

Physics gives an asymmetry that tells such a view from a floor line. A tilted scan plane
can put returns **in front of** the level structure (the floor or ceiling it meets
first), never **beyond** it. Returns seen through the view are explained only by a view
that is off (or by something that moved away). So a scan with new returns is registered
against the view (the scan match's point-to-line fit, from no motion, with a wide spread
and a wide association; a fit as poor as the scan match would not trust is not used),
and the correction is taken only when both hold:

- it moves the view onto the scan: ``MIN_GAIN`` (20 %) more returns lie on the view
  (within the free-space margin) than before;
- it explains returns seen through the view: at least ``MIN_PAIRS`` fewer of them.

A floor line in front of a wall parallel to it fits a correction that moves the wall
onto the line, but that correction explains no return seen through the view: it is left
alone, and the line stays new.

A registration that moves no point of the view by more than the free-space margin
(:func:`within_margin`) finds the view where the scan says it is: the evidence already
allows for an error that small, and nothing else is tried (no search along x). Most
tries end there; moving the view and searching it along x had been most of the time
re-anchoring took.

The registration pairs the scan with the view within ``ASSOCIATION_M``. Where the scans
could not see the travel (floor and ceiling lines hide the walls ahead and behind, and
without wheel odometry the dead reckoning guesses it), the view can be off by more along
the sensor's x axis: a 5 Hz scanner in a corridor, a hard stop from 1 m/s. Then the view
is first searched along x (:func:`offset_along_x`: the shift, up to ``SEARCH_SPAN_M``,
that puts the most of the scan's returns on it), and registered from there with the
narrower ``REFINE_ASSOCIATION_M``. Such a correction is taken on the same two
conditions and a third (:func:`explains_both_ends`): it puts more returns on the view
both ahead of the sensor and behind it. A view left off by unseen travel is off at both
ends; a shift that moves the wall ahead onto a floor line helps on that side only.
With wheel odometry the travel is measured, and an IMU that shows the plane tilted says
that a line ahead is more likely a floor line than a wall the view lost: the filter does
not search then.
"""

from __future__ import annotations

import math

import numpy as np

from pvfilter.improved.beams import BeamLayout
from pvfilter.improved.egomotion import MAX_RESIDUAL_M
from pvfilter.improved.motion import MIN_PAIRS, STILL, Motion, estimate_motion
from pvfilter.improved.params import ImprovedParams

ASSOCIATION_M = 0.5  # m: the largest view error a pitch event leaves (pairs farther
# apart take no part in the registration)
SPREAD = (0.05, 0.5)  # (rad, m): the prior's spread; the registration starts from no
# correction and may move about as far as ASSOCIATION_M
MIN_GAIN = 0.2  # share: a correction must put this many more returns on the view
SEARCH_SPAN_M = 1.0  # m: the largest view error along x searched for (the unseen travel
# of a pitch event: a hard stop from 1 m/s, or its constant-velocity guess, in a second)
SEARCH_STEP_M = 0.1  # m: the search's step (the registration from it reaches twice that)
REFINE_ASSOCIATION_M = 0.2  # m: the registration's association from the search's shift
CROSSING_DEG = 30.0  # deg: returns this far off a line's direction are on another surface


def register_view(
    level_ranges: np.ndarray,
    directions: np.ndarray,
    view_ranges: np.ndarray,
    layout: BeamLayout,
    start: Motion = STILL,
    association_m: float = ASSOCIATION_M,
) -> Motion | None:
    """The correction that moves the level view onto the scan, or None (no usable fit).

    Args:
        level_ranges: the scan's ranges, unstretched (as the scan match sees them), m;
            NaN where invalid.
        directions: the local line direction per beam, rad (NaN: none).
        view_ranges: the level view in this scan's frame, m (NaN unknown, ``+inf`` free).
        layout: the beams.
        start: the correction the fit starts from (no correction, or a search's shift).
        association_m: pairs farther apart than this from ``start`` take no part, m.

    Returns:
        The motion that takes a point of the view to where the scan sees it (the
        :mod:`pvfilter.improved.motion` convention); None when too few pairs or a poor fit.
    """
    known = np.where(np.isfinite(view_ranges), view_ranges, np.nan)
    correction = estimate_motion(
        layout.points(level_ranges),
        directions,
        layout.points(known),
        layout,
        0,
        association_m,
        start,
        SPREAD,
    )
    if correction.pairs < MIN_PAIRS or not correction.residual_m <= MAX_RESIDUAL_M:
        return None
    return correction


def within_margin(correction: Motion, params: ImprovedParams) -> bool:
    """``correction`` moves no point of the view by more than the free-space margin: a
    point at range r moves by at most ``|t| + |theta| r``, and the margin is
    ``free_margin_m + free_margin_rel r`` (so both parts must be within theirs)."""
    return (
        math.hypot(correction.tx_m, correction.ty_m) <= params.free_margin_m
        and abs(correction.theta_rad) <= params.free_margin_rel
    )


def explains_view_error(
    gaps_before: np.ndarray, gaps_after: np.ndarray, margin: np.ndarray, directions: np.ndarray
) -> bool:
    """A corrected view explains the scan better: it puts ``MIN_GAIN`` more returns on the
    view, and explains returns seen through it or new returns on surfaces that cross.

    Args:
        gaps_before: per beam, how far in front of the view the return lies, m (NaN:
            unknown), before the correction (:func:`~pvfilter.improved.evidence.free_space_gaps`).
        gaps_after: the same after it.
        margin: the free-space margin per beam, m.
        directions: the local line direction per beam, rad (NaN: none).
    """
    on_before = np.count_nonzero(np.abs(gaps_before) <= margin)  # NaN compares False
    on_after = np.count_nonzero(np.abs(gaps_after) <= margin)
    if not on_after > (1.0 + MIN_GAIN) * on_before:
        return False
    through_before = np.count_nonzero(gaps_before < -margin)
    through_after = np.count_nonzero(gaps_after < -margin)
    if through_before - through_after >= MIN_PAIRS:
        return True
    explained = (gaps_before > margin) & (np.abs(gaps_after) <= margin)
    return on_crossing_surfaces(directions[explained])


def on_crossing_surfaces(directions: np.ndarray) -> bool:
    """Returns with these local line directions (rad) lie on surfaces that cross: at least
    ``MIN_PAIRS`` of them, and ``MIN_PAIRS // 2`` more than ``CROSSING_DEG`` off their
    main direction.

    A floor or ceiling line is where a plane meets the scan plane: a straight line. New
    returns that a correction puts on the view along a corner, or on walls and furniture
    at several angles, are no such line: the view had drifted (unseen travel with no
    wall behind within range to show it, so no return is seen through the view).
    """
    known = directions[directions == directions]  # NaN compares False
    if known.size < MIN_PAIRS:
        return False
    doubled = 2.0 * known  # a direction and its opposite are one line
    main = 0.5 * math.atan2(float(np.sin(doubled).sum()), float(np.cos(doubled).sum()))
    off = np.abs(np.sin(known - main)) > math.sin(math.radians(CROSSING_DEG))
    return np.count_nonzero(off) >= MIN_PAIRS // 2


def offset_along_x(
    level_ranges: np.ndarray, view_ranges: np.ndarray, layout: BeamLayout
) -> Motion | None:
    """The shift of the view along the sensor's x axis, within ``SEARCH_SPAN_M``, that puts
    the most of the scan's returns on it (within half a ``SEARCH_STEP_M``, so that the
    best shift stands out), where it is farther from no shift than the registration's
    own reach; else None.

    Each shift moves the view's points and reads the scan's range on the beam each lands
    on: one pass over every shift at once, on the view's points.
    """
    # only returns across the x axis tell a shift along it (a wall along it looks the same)
    telling = np.isfinite(view_ranges) & (np.abs(layout.cos) > 0.5)
    view = layout.points(np.where(telling, view_ranges, np.nan))[telling]
    shifts = np.arange(-SEARCH_SPAN_M, SEARCH_SPAN_M + 0.5 * SEARCH_STEP_M, SEARCH_STEP_M)
    best = int(layout.hits_along_x(view, level_ranges, shifts, 0.5 * SEARCH_STEP_M).argmax())
    if abs(shifts[best]) < 0.5 * ASSOCIATION_M:  # the registration from no shift reaches it
        return None
    return Motion(0.0, float(shifts[best]), 0.0)


def explains_both_ends(
    gaps_before: np.ndarray, gaps_after: np.ndarray, margin: np.ndarray, layout: BeamLayout
) -> bool:
    """A shift along x puts more returns on the view both ahead and behind the sensor.

    A view left off by unseen travel is off at both ends: the walls ahead and behind
    come onto it together. A shift that moves a wall onto a floor line helps on the
    line's side only.

    Args as :func:`explains_view_error`, and the beams.
    """
    on_before = np.abs(gaps_before) <= margin  # NaN compares False
    on_after = np.abs(gaps_after) <= margin
    for side in (layout.cos > 0.5, layout.cos < -0.5):
        if np.count_nonzero(on_after & side) - np.count_nonzero(on_before & side) < MIN_PAIRS // 2:
            return False
    return True
