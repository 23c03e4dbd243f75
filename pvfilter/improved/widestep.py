"""Scan matching across steps longer than the beam pairing reaches (a low scan rate).

:func:`~pvfilter.improved.motion.estimate_motion` pairs each beam with the previous scan's
beam after a coarse turn, within ``association_m`` of where the prior puts it. At 10 Hz
the constant-velocity prior is off by millimetres; at 1-2 Hz a robot that speeds up or
brakes is off by tens of centimetres, the walls across the drive no longer pair, the
walls along it alone read a robot standing still, and the wall ahead then looks new.

So where the prior's doubt exceeds the pairing's reach, the drive is searched first:

- over turns around the prior's, in ``TURN_STEP_RAD`` steps (the fit refines them);
- for each, along the sensor's x axis only: a two-wheeled robot drives along its heading
  (its wheels do not slide sideways), so one distance is unknown, not two;
- against the previous scan's every return, new ones included (a wall a bad match made
  new is still a wall), counting only the scan's returns on lines across the x axis (a
  wall along the drive fits every distance);
- then the previous scan, moved by the best turn and distance, is binned into this
  scan's beams (the nearest return wins a beam) and the usual fit refines the motion.

The result is taken only when it pairs a good part of the scan (``MIN_SHARE``) and puts
more returns across x on the previous scan than the fit from the prior does; otherwise
the usual match stands, and with it the usual trust check.
"""

from __future__ import annotations

import math

import numpy as np

from pvfilter.improved.beams import BeamLayout, indices
from pvfilter.improved.memory import nearest_first
from pvfilter.improved.motion import MIN_PAIRS, STILL, Motion, estimate_motion, motion_of

MAX_ACCEL_MPS2 = 5.0  # m/s^2: a balancing robot's hardest braking or speeding up (harder and
# it falls); over dt the constant-velocity prior may be off by half this times dt^2
SEARCH_STEP_M = 0.1  # m: the search's step (the fit from it reaches association_m)
ON_LINE_M = 0.05  # m: a moved return this close in range to the scan's is on it
TURN_STEP_RAD = math.radians(2.0)  # rad: the search's turn step (the fit refines it)
MIN_SHARE = 0.25  # of the scan's returns on lines: a wide step must pair this many
MAX_TURN_STEPS = 30  # the turns searched either side of the prior's: up to 60 deg
MAX_SEARCH_M = 2.5  # m: the farthest drive searched from the prior's
ACROSS = 0.5  # |cos| of a line's direction below which it lies across the x axis (60-120 deg)


def prior_doubt_m(since_s: float) -> float:
    """How far the constant-velocity prior may be off after ``since_s``, m."""
    return 0.5 * MAX_ACCEL_MPS2 * since_s * since_s


def wide_step(
    points: np.ndarray,
    ranges: np.ndarray,
    directions: np.ndarray,
    reference: np.ndarray,
    layout: BeamLayout,
    turn_span_rad: float,
    expected: Motion,
    span_m: float,
    association_m: float,
    turn_spread_rad: float,
    plain: Motion,
) -> Motion | None:
    """The motion from the reference scan to this one, searched; None: the search found
    too little of the scan on the reference, or no better motion than ``plain``.

    Args:
        points: this scan's points per beam (unstretched, mid-scan), m; NaN rows: none.
        ranges: their ranges, m (NaN: none).
        directions: the local line direction per beam, rad (NaN: none).
        reference: the previous scan's points per beam, every return (unstretched), m.
        layout: the beams of both scans.
        turn_span_rad: how far the turn may be from the prior's, rad (at most
            ``MAX_TURN_STEPS`` steps are searched either side).
        expected: the prior's motion since the reference.
        span_m: the farthest the drive may be from the prior's, m.
        association_m: the fit's pairing reach, m.
        turn_spread_rad: the prior's turn spread, rad.
        plain: the fit from the prior; the searched motion must put more of the scan's
            returns across the x axis on the reference than it does.
    """
    every = reference[indices(reference[:, 0] == reference[:, 0])]
    across = np.abs(np.cos(directions)) < ACROSS  # NaN compares False
    seen = np.where(across, ranges, np.nan)
    best_hits, start = -1, None
    steps = min(math.ceil(turn_span_rad / TURN_STEP_RAD), MAX_TURN_STEPS)
    turns = expected.theta_rad + TURN_STEP_RAD * np.arange(-steps, steps + 1)
    for theta in turns:
        guess = motion_of(float(theta), expected.tx_m, expected.ty_m)
        shift, hits = _best_shift(guess.apply(every), seen, layout, span_m)
        if hits > best_hits:
            best_hits, start = hits, motion_of(float(theta), expected.tx_m + shift, expected.ty_m)
    if start is None or best_hits < MIN_PAIRS // 2:
        return None
    binned = _binned(start.apply(reference), layout)
    spread = (turn_spread_rad, association_m)
    correction = estimate_motion(
        points, directions, binned, layout, 0, association_m, STILL, spread
    )
    usable = np.count_nonzero(directions == directions)  # NaN compares False
    if correction.pairs < max(MIN_PAIRS, MIN_SHARE * usable):
        return None
    fine = start.then(correction)
    if plain.pairs >= MIN_PAIRS and _hits(fine, every, seen, layout) <= _hits(
        plain, every, seen, layout
    ):
        return None
    wide = motion_of(fine.theta_rad, fine.tx_m, fine.ty_m, correction.pairs, correction.residual_m)
    wide.__dict__["weak_rows"] = correction.weak_rows  # what the refit saw of the drive
    wide.__dict__["weak_axis_rad"] = correction.weak_axis_rad
    return wide


def _hits(motion: Motion, reference: np.ndarray, ranges: np.ndarray, layout: BeamLayout) -> int:
    """How many ``reference`` points ``motion`` puts on the scan's ``ranges``."""
    return _best_shift(motion.apply(reference), ranges, layout, 0.0)[1]


def _best_shift(
    moved: np.ndarray, ranges: np.ndarray, layout: BeamLayout, span_m: float
) -> tuple[float, int]:
    """The shift along x, within ``span_m``, that puts the most ``moved`` points on the
    scan's ``ranges`` (the first of equals), and how many it puts there."""
    count = math.floor(span_m / SEARCH_STEP_M)
    shifts = SEARCH_STEP_M * np.arange(-count, count + 1)
    hits = layout.hits_along_x(moved, ranges, shifts, ON_LINE_M)
    best = int(hits.argmax())
    return float(shifts[best]), int(hits[best])


def _binned(points: np.ndarray, layout: BeamLayout) -> np.ndarray:
    """``points`` (any order, NaN rows skipped) per beam of ``layout``, the nearest winning
    a beam (:func:`~pvfilter.improved.memory.nearest_first`); NaN rows where none lands."""
    points = points.take(indices(points[:, 0] == points[:, 0]), axis=0)
    beams = layout.beam_of(points)
    order = nearest_first(beams, np.hypot(points[:, 0], points[:, 1]), layout)
    binned = np.full((layout.count, 2), np.nan)
    binned[beams.take(order)] = points.take(order, axis=0)
    return binned
