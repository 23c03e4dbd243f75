"""How far off the level view may be along what the scan matches could not see.

The level view follows the sensor by the scan match's steps (:mod:`pvfilter.improved.egomotion`).
Where the walls a scan shares with the last one are all parallel (a corridor, or the
side walls that a pitched plane still meets while floor lines hide the walls ahead),
the drive along them is left to a few rows of clutter and to the constant-velocity
prior: the fit's support along that direction (:attr:`pvfilter.improved.motion.Motion.weak_rows`)
is small. Each such step may be off along it by as much as the prior may be
(:func:`pvfilter.improved.widestep.prior_doubt_m`: the robot braking or speeding up at
its hardest over the step: 2.5 cm at 10 Hz, 10 cm at 5 Hz). Over a pitch event the
doubts add up (as variances), and when the robot levels, the wall ahead stands in front
of the view by about that much: a return is new only that much more in front of the
view, along each beam.

The doubt is the view's, in the current sensor frame: it turns with the sensor, grows
with each weak step of a robot without wheel odometry (the wheels measure the drive),
and is gone when a level scan renews the view, when the view is re-anchored on the scan,
or when the filter starts afresh.
"""

from __future__ import annotations

import math

import numpy as np

from pvfilter.improved.beams import BeamLayout
from pvfilter.improved.motion import MIN_PAIRS
from pvfilter.improved.widestep import prior_doubt_m

WEAK_ROWS = MIN_PAIRS  # rows: a direction with less support than a fit needs is not measured


class ViewDoubt:
    """The level view's position doubt along the directions the matches could not see,
    a 2 x 2 covariance, m^2, in the current sensor frame."""

    def __init__(self) -> None:
        self.reset()

    def reset(self) -> None:
        """No doubt: the view is where the last level scan saw it."""
        self.xx = self.xy = self.yy = 0.0

    def carry(self, turn_rad: float, weak: tuple[float, float], dt: float) -> None:
        """The view moved into the next scan's frame by a step that turned ``turn_rad``
        and was fitted with support ``weak`` (rows, direction rad) along its least
        constrained direction, ``dt`` after the last scan."""
        if self.xx or self.yy:  # turn the doubt with the sensor: R S R^T
            c, s = math.cos(turn_rad), math.sin(turn_rad)
            xx, xy, yy = self.xx, self.xy, self.yy
            self.xx = c * c * xx - 2.0 * c * s * xy + s * s * yy
            self.xy = c * s * (xx - yy) + (c * c - s * s) * xy
            self.yy = s * s * xx + 2.0 * c * s * xy + c * c * yy
        rows, axis_rad = weak
        if rows >= WEAK_ROWS:
            return
        doubt = prior_doubt_m(dt)
        c, s = math.cos(axis_rad), math.sin(axis_rad)
        self.xx += doubt * doubt * c * c
        self.xy += doubt * doubt * c * s
        self.yy += doubt * doubt * s * s

    def along_beams(self, layout: BeamLayout) -> np.ndarray | None:
        """Per beam: the view's doubt along it, m (``sqrt(b^T S b)``); None: none."""
        if not (self.xx or self.yy):
            return None
        cos, sin = layout.cos, layout.sin
        variance = self.xx * cos * cos + 2.0 * self.xy * cos * sin + self.yy * sin * sin
        return np.sqrt(np.maximum(variance, 0.0))
