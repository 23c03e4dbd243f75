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
"""

from __future__ import annotations

import numpy as np

from pvfilter.improved.beams import BeamLayout
from pvfilter.improved.egomotion import MAX_RESIDUAL_M
from pvfilter.improved.motion import MIN_PAIRS, STILL, Motion, estimate_motion

ASSOCIATION_M = 0.5  # m: the largest view error a pitch event leaves (pairs farther
# apart take no part in the registration)
SPREAD = (0.05, 0.5)  # (rad, m): the prior's spread; the registration starts from no
# correction and may move about as far as ASSOCIATION_M
MIN_GAIN = 0.2  # share: a correction must put this many more returns on the view


def register_view(
    level_ranges: np.ndarray,
    directions: np.ndarray,
    view_ranges: np.ndarray,
    layout: BeamLayout,
) -> Motion | None:
    """The correction that moves the level view onto the scan, or None (no usable fit).

    Args:
        level_ranges: the scan's ranges, unstretched (as the scan match sees them), m;
            NaN where invalid.
        directions: the local line direction per beam, rad (NaN: none).
        view_ranges: the level view in this scan's frame, m (NaN unknown, ``+inf`` free).
        layout: the beams.

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
        ASSOCIATION_M,
        STILL,
        SPREAD,
    )
    if correction.pairs < MIN_PAIRS or not correction.residual_m <= MAX_RESIDUAL_M:
        return None
    return correction


def explains_view_error(
    gaps_before: np.ndarray, gaps_after: np.ndarray, margin: np.ndarray
) -> bool:
    """A corrected view explains the scan better, through returns seen beyond it.

    Args:
        gaps_before: per beam, how far in front of the view the return lies, m (NaN:
            unknown), before the correction (:func:`~pvfilter.improved.evidence.free_space_gaps`).
        gaps_after: the same after it.
        margin: the free-space margin per beam, m.
    """
    on_before = np.count_nonzero(np.abs(gaps_before) <= margin)  # NaN compares False
    on_after = np.count_nonzero(np.abs(gaps_after) <= margin)
    through_before = np.count_nonzero(gaps_before < -margin)
    through_after = np.count_nonzero(gaps_after < -margin)
    return on_after > (1.0 + MIN_GAIN) * on_before and through_before - through_after >= MIN_PAIRS
