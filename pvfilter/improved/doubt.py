"""How far off the level view may be along what the scan matches could not see.

The level view follows the sensor by the scan match's steps (:mod:`pvfilter.improved.egomotion`).
Where the walls a scan shares with the last one are all parallel (a corridor, or the
side walls that a pitched plane still meets while floor lines hide the walls ahead),
the drive along them is left to a few rows of clutter and to the constant-velocity
prior: the fit's support along that direction (:attr:`pvfilter.improved.motion.Motion.weak_rows`)
is small. Such a step may be off along it by as much as the prior may be
(:func:`pvfilter.improved.widestep.prior_doubt_m`: the robot braking or speeding up at
its hardest over the step: 2.5 cm at 10 Hz, 10 cm at 5 Hz; over the whole time since
the last matched scan where the filter coasted, and never more than the robot can drive
in it). The prior's velocity then comes from that step, so the next step errs the same
way: the doubts of consecutive weak steps add as distances, not as variances. (A
velocity error that grows with each weak step would add more: a robot that speeds up
hard through a long event outruns this doubt.) When the robot levels, the wall ahead
stands in front of the view by about that much: a return is new only that much more in
front of the view, along its beam, as the surface it lies on moves (``1 / cos`` of the
incidence).

The doubt is the view's, a covariance in the current sensor frame: it turns with the
sensor; it grows by the weak steps of a robot without wheel odometry while the view is
not renewed (in a pitch event, and the step out of it: a step between two level scans
lands on a view the scans teach again); after the event it shrinks as fast as the view
comes closer behind a line across the travel (``line_shrink_mps`` plus the drive:
:class:`pvfilter.improved.memory.LevelMemory`); and it is gone when a scan puts
``MIN_PAIRS`` returns on the view on surfaces that face the doubt's main direction (they
show where the view lies along it: a scan that shows nothing there, a floor that returns
no echo say, confirms nothing), when the view is re-anchored on a scan, or when the
filter starts afresh.
"""

from __future__ import annotations

import math

import numpy as np

from pvfilter.improved.beams import BeamLayout
from pvfilter.improved.egomotion import MAX_SPEED_MPS
from pvfilter.improved.motion import MIN_PAIRS
from pvfilter.improved.widestep import prior_doubt_m

WEAK_ROWS = MIN_PAIRS  # rows: a direction with less support than a fit needs is not measured
SURFACE_BEAMS = 2  # beams each side: a surface's direction through the points this far
# apart (two beams either side: one each side takes a scanner's range noise for a turn)
SURFACE_SPAN = 4.0  # a surface seen within 75 deg of its normal spans at most 1 / cos 75
# (3.9) times the arc between its beams: farther apart, the two lie on two surfaces
FACING_COS = 0.5  # a surface whose normal lies within 60 deg of a direction faces it
NEGLIGIBLE_M = 1e-6  # m: a doubt smaller than this is none
GRAZING_COS = math.cos(math.radians(75.0))  # a surface seen more obliquely than this moves
# along the beam as if seen at this angle (a shift along it moves it by 1 / cos: unbounded)


class ViewDoubt:
    """The level view's position doubt along the directions the matches could not see,
    a 2 x 2 covariance, m^2, in the current sensor frame."""

    def __init__(self) -> None:
        self.reset()

    def reset(self) -> None:
        """No doubt: the view is where the last scans saw it."""
        self.doubt = self.grown = (0.0, 0.0, 0.0)  # (xx, xy, yy), m^2

    def carry(self, turn_rad: float, weak: tuple[float, float], span_s: float) -> None:
        """The view moved into this scan's frame by a step that turned ``turn_rad``,
        fitted with ``weak`` support (:attr:`pvfilter.improved.egomotion.Match.weak`;
        inf rows: seen, or measured by the wheels) over ``span_s`` since the last matched
        scan. The step's doubt is held apart until :meth:`settle`."""
        self.doubt = _turned(self.doubt, turn_rad)
        grown = self.doubt
        weak_rows, axis_rad = weak
        if weak_rows < WEAK_ROWS and math.isfinite(axis_rad):  # (NaN compares False)
            step_m = min(prior_doubt_m(span_s), MAX_SPEED_MPS * span_s)
            grown = _grown(grown, axis_rad, step_m)
        self.grown = grown

    def settle(self, in_event: bool, creep_m: float) -> None:
        """After the scan: its step's doubt stays where the view was not renewed
        (``in_event``: this scan or the last was tilted or coasted); after a level scan
        the doubt shrinks by ``creep_m``, how far the view came closer meanwhile, m."""
        if in_event:
            self.doubt = self.grown
        else:
            self.doubt = _shrunk(self.doubt, creep_m)
        self.grown = self.doubt

    def confirmed(self, on_view: np.ndarray, directions: np.ndarray) -> bool:
        """``MIN_PAIRS`` returns on the view (``on_view``, per beam) lie on surfaces
        (local line ``directions``, rad, NaN: none) that face the doubt's main direction:
        they show where the view lies along it."""
        normals = directions.take(np.flatnonzero(on_view)) + 0.5 * math.pi
        facing = np.abs(np.cos(normals - _major_axis(self.grown))) >= FACING_COS  # NaN: False
        return np.count_nonzero(facing) >= MIN_PAIRS

    def along_beams(self, layout: BeamLayout, view_ranges: np.ndarray) -> np.ndarray | None:
        """Per beam: how far the view's surface there may lie off along the beam, m
        (``sqrt(n^T S n) / |n . b|`` for the surface's normal ``n`` and the beam ``b``; the
        beam itself where the view shows no surface through the beam's neighbours); None:
        no doubt.

        Args:
            layout: the beams.
            view_ranges: the level view in this scan's frame, m (NaN unknown, inf free).
        """
        if not (self.grown[0] or self.grown[2]):
            return None
        cos, sin = layout.cos, layout.sin
        directions = surface_directions(view_ranges, layout)
        normal_x, normal_y = -np.sin(directions), np.cos(directions)
        unknown = directions != directions  # NaN
        normal_x[unknown], normal_y[unknown] = cos[unknown], sin[unknown]
        variance = _variance_along(self.grown, normal_x, normal_y)
        facing = np.abs(normal_x * cos + normal_y * sin)
        return np.sqrt(np.maximum(variance, 0.0)) / np.maximum(facing, GRAZING_COS)


def surface_directions(view_ranges: np.ndarray, layout: BeamLayout) -> np.ndarray:
    """Per beam: the direction of the view's surface there, rad, through the points
    ``SURFACE_BEAMS`` beams either side (around the seam of a full turn; NaN where either
    is unknown or free, or the two lie farther apart than ``SURFACE_SPAN`` times the arc
    between them at their range: a jump)."""
    k, n = SURFACE_BEAMS, layout.count
    directions = np.full(n, np.nan)
    if n <= 2 * k:
        return directions
    ranges = np.where(np.isfinite(view_ranges), view_ranges, np.nan)
    points = layout.points(ranges)
    if layout.ring:  # the beams past the seam are the other end's
        after, before = np.roll(points, -k, axis=0), np.roll(points, k, axis=0)
        far = np.fmax(np.roll(ranges, -k), np.roll(ranges, k))
        rows = slice(0, n)
    else:
        after, before, far = (
            points[2 * k :],
            points[: n - 2 * k],
            np.fmax(ranges[2 * k :], ranges[: n - 2 * k]),
        )
        rows = slice(k, n - k)
    across = after - before
    span = np.hypot(across[:, 0], across[:, 1])
    reach = far * (2 * k * layout.increment * SURFACE_SPAN)
    directions[rows] = np.where(span <= reach, np.arctan2(across[:, 1], across[:, 0]), np.nan)
    return directions


def _turned(doubt: tuple[float, float, float], turn_rad: float) -> tuple[float, float, float]:
    """``R S R^T``: a direction ``d`` of the last frame is ``R d`` in this one."""
    xx, xy, yy = doubt
    if not (xx or yy) or turn_rad == 0.0:
        return doubt
    c, s = math.cos(turn_rad), math.sin(turn_rad)
    return (
        c * c * xx - 2.0 * c * s * xy + s * s * yy,
        c * s * (xx - yy) + (c * c - s * s) * xy,
        s * s * xx + 2.0 * c * s * xy + c * c * yy,
    )


def _grown(
    doubt: tuple[float, float, float], axis_rad: float, step_m: float
) -> tuple[float, float, float]:
    """``doubt`` with ``step_m`` added along ``axis_rad`` as a distance: the standard
    deviation along the axis grows from ``s`` to ``s + step_m`` (errors of one sign)."""
    xx, xy, yy = doubt
    c, s = math.cos(axis_rad), math.sin(axis_rad)
    along = math.sqrt(max(_variance_along(doubt, c, s), 0.0))
    added = (2.0 * along + step_m) * step_m
    return xx + added * c * c, xy + added * c * s, yy + added * s * s


def _shrunk(doubt: tuple[float, float, float], by_m: float) -> tuple[float, float, float]:
    """``doubt`` with the standard deviation along each of its axes less ``by_m`` (none
    left below a micrometre; none at all where the view comes closer at once: an
    unbounded ``line_shrink_mps``)."""
    if not by_m < math.inf:  # (NaN compares False)
        return (0.0, 0.0, 0.0)
    xx, xy, yy = doubt
    half_sum, spread = 0.5 * (xx + yy), math.hypot(0.5 * (xx - yy), xy)
    major_m = math.sqrt(max(half_sum + spread, 0.0)) - by_m
    minor_m = math.sqrt(max(half_sum - spread, 0.0)) - by_m
    if major_m < NEGLIGIBLE_M:
        return (0.0, 0.0, 0.0)
    major, minor = major_m * major_m, max(minor_m, 0.0) ** 2
    axis = _major_axis(doubt)
    c, s = math.cos(axis), math.sin(axis)
    return (
        major * c * c + minor * s * s,
        (major - minor) * c * s,
        major * s * s + minor * c * c,
    )


def _variance_along(doubt: tuple[float, float, float], c, s):
    """``u^T S u`` for the unit direction ``u = (c, s)`` (floats or arrays), m^2."""
    xx, xy, yy = doubt
    return xx * c * c + 2.0 * xy * c * s + yy * s * s


def _major_axis(doubt: tuple[float, float, float]) -> float:
    """The direction of the covariance's larger axis, rad (mod pi)."""
    xx, xy, yy = doubt
    return 0.5 * math.atan2(2.0 * xy, xx - yy)
