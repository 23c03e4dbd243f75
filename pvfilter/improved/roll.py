"""The scan plane's roll, measured on its own confident floor lines.

A plane pitched by ``p`` and rolled by ``r`` meets the floor along a line whose normal
leans from the sensor's x axis by ``atan(sin r / tan p)``
(:mod:`pvfilter.improved.geometry`); the lean gate lets a line lean as far as a roll of
``max_roll_deg`` explains. A LiDAR mounted a degree or two off level on a robot that
stands on a sloping floor rolls more than a default bound for every robot allows, and
then every shallow floor line it meets leans past the gate: the steeper lines of its
pitch events still pass (their lean is small), and they tell the roll. From a confident
line whose normal leans by ``lambda`` the roll follows (:func:`line_roll_deg`): about
``sin r = tan(lambda) tan(p)``, so a degree of lean measured on a line at 10 deg is a
fifth of a degree of roll.

The bound the gates use is then the larger of ``max_roll_deg`` and the median of the
latest ``ROLL_LINES`` measurements plus ``ROLL_MARGIN_DEG`` (the floor's own slope
changes as the robot drives). It is never narrower than the one given, so a robot whose
plane is level keeps it, and a wall taken for the floor now and then is a minority the
median passes over. The segmentation's bound on "across the direction of travel"
(``line_angle_deg``) widens with it, to the lean of the floor line as far out as the
given bounds reached (``tan`` of that lean grows with ``sin`` of the roll).

Only lines that pass the gates are measured: a roll far beyond ``max_roll_deg`` leans
even the steepest floor lines past them, and is never learnt (the bend a rotating sweep
may put in a line widens the gate enough for about a degree more). Set ``max_roll_deg``
for such a robot.
"""

from __future__ import annotations

import dataclasses
import math
from collections import deque

import numpy as np

from pvfilter.improved.medians import median_of_few
from pvfilter.improved.params import ImprovedParams

ROLL_LINES = 25  # confident lines: the roll is the median of the latest this many
ROLL_MIN_LINES = 5  # confident lines measured before the bound may widen
ROLL_MARGIN_DEG = 1.0  # deg: how much the roll may differ from the measured (floor slope)


def line_roll_deg(normal: np.ndarray, tilt_rad: float) -> float:
    """The roll, deg (its magnitude), of a plane that meets the floor along a line with
    unit ``normal`` (x, y in the sensor frame) at the distance a tilt of ``tilt_rad`` puts
    it (:func:`pvfilter.improved.geometry.implied_tilt`).

    The line ``x sin p - y cos p sin r = h`` lies ``h / sin(theta)`` from the sensor, where
    ``sin(theta)^2 = sin(p)^2 + cos(p)^2 sin(r)^2`` (``theta``: the plane's whole tilt, what
    the distance implies), and its normal is ``(sin p, -cos p sin r) / sin(theta)``. So
    ``sin p = |n_x| sin(theta)`` and ``sin r = |n_y| sin(theta) / cos p``.
    """
    sin_tilt = math.sin(tilt_rad)
    sin_pitch = min(abs(float(normal[0])) * sin_tilt, 1.0)
    cos_pitch = math.sqrt(1.0 - sin_pitch * sin_pitch)
    sin_roll = abs(float(normal[1])) * sin_tilt / max(cos_pitch, 1e-9)
    return math.degrees(math.asin(min(sin_roll, 1.0)))


class RollBound:
    """The roll the lean gates allow: ``max_roll_deg``, or what the scans measured."""

    def __init__(self, params: ImprovedParams) -> None:
        self.params = params
        self.measured_deg: deque[float] = deque(maxlen=ROLL_LINES)

    def reset(self) -> None:
        """Forget the measurements (another robot, another sequence)."""
        self.measured_deg.clear()

    def learn(self, normal: np.ndarray, tilt_rad: float) -> None:
        """Take in a confident floor line: its unit normal and its tilt, rad."""
        self.measured_deg.append(line_roll_deg(normal, tilt_rad))

    @property
    def bound_deg(self) -> float:
        """The roll the gates allow now, deg."""
        if len(self.measured_deg) < ROLL_MIN_LINES:
            return self.params.max_roll_deg
        measured = median_of_few(self.measured_deg) + ROLL_MARGIN_DEG
        return max(self.params.max_roll_deg, measured)

    def applied(self, params: ImprovedParams) -> ImprovedParams:
        """``params`` with the roll the lean gates allow now (``max_roll_deg``)."""
        bound = self.bound_deg
        if bound == params.max_roll_deg:
            return params
        return dataclasses.replace(params, max_roll_deg=bound)

    def segmenting(self, params: ImprovedParams) -> ImprovedParams:
        """``params`` for the segmentation under the roll the gates allow now: a point lies
        across the direction of travel within ``line_angle_deg`` widened as far as the
        floor line at the distance where the default roll reached that bound now leans
        (``tan`` of the angle grows with ``sin`` of the roll)."""
        bound = self.bound_deg
        if bound == params.max_roll_deg:  # (max_roll_deg > 0: the parameters check it)
            return params
        reach = math.sin(math.radians(bound)) / math.sin(math.radians(params.max_roll_deg))
        widened = math.atan(math.tan(math.radians(params.line_angle_deg)) * reach)
        return dataclasses.replace(params, line_angle_deg=math.degrees(widened))
