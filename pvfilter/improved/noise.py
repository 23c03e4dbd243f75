"""The scanner's range noise, measured on its scans.

Two stages ask for it. The ego-motion's scan match is judged by its residuals
(:func:`pvfilter.improved.egomotion.fit_trusted`): a right fit leaves about the range
noise, a wrong one far more. A fixed bound for them suits one class of LiDAR only: a
scanner with 5 cm of range noise leaves about 5 cm on right fits, and a 5 cm bound refused
44 % of its matches. And the distances that say which returns lie on one line (the
segmentation's break distance, a line's tolerance) follow the scanner's noise, as
:class:`RangeNoise` follows it over the scans
(:meth:`pvfilter.improved.params.ImprovedParams.for_range_noise`).

Consecutive beams are a fraction of a degree apart: along a surface the range changes
smoothly from beam to beam, and its second difference, ``r[i-1] - 2 r[i] + r[i+1]``, is
the noise of three ranges (``sqrt(6)`` times the noise) plus the surface's curvature
(a flat wall at 60 deg incidence and 3 m adds 1.6 mm at 0.5 deg between beams). Its median
over the scan is not moved by the few beams at range jumps and corners.
"""

from __future__ import annotations

import collections
import math

import numpy as np

from pvfilter.improved.medians import median_in_place, median_of_few

# |N(0, 6 sigma^2)| has the median 0.6745 sqrt(6) sigma
_MEDIAN_PER_SIGMA = 0.6745 * math.sqrt(6.0)


def range_noise_m(ranges: np.ndarray) -> float:
    """The scan's range noise (one standard deviation), m.

    Clutter inflates it: where range jumps spoil most triples of consecutive beams, the
    median second difference measures the scene, not the scanner (its user caps what it
    lets the estimate vouch for: :data:`pvfilter.improved.egomotion.MAX_NOISE_RESIDUAL_M`).

    Args:
        ranges: per beam, m; NaN or infinite where the beam has no usable return.

    Returns:
        The median absolute second difference over every three consecutive beams that all
        return (a beam between returns of beams farther apart would add the surface's
        slope), over ``0.6745 sqrt(6)``; NaN where no three consecutive beams return.
    """
    returns = np.where(np.isfinite(ranges), ranges, np.nan)  # inf - inf would warn
    # r[i-1] - 2 r[i] + r[i+1], written into one array
    second = returns[:-2] - 2.0 * returns[1:-1]
    second += returns[2:]
    second = second[second == second]  # NaN where a beam has no return
    if second.size == 0:
        return math.nan
    return median_in_place(np.abs(second, out=second)) / _MEDIAN_PER_SIGMA


NOISE_WINDOW = 25  # the scanner's noise is the median of this many scans' estimates
NOISE_EVERY_SCANS = 4  # scans: one is measured in every so many (the noise is the
# scanner's and changes slowly, if at all; measuring every scan cost 7 % of the filter's time)
NOISE_MIN_ESTIMATES = 3  # the median of fewer estimates is no measure: one cluttered scan
# at the start would set the parameters alone
NOISE_HYSTERESIS = 0.25  # the noise followed moves only where the median of the window
# differs from it by more than this share: the parameters are worked out again rarely, and
# a scanner does not flap between two values (the median of 25 estimates varies by a few
# per cent)
MAX_LINE_NOISE_M = 0.1  # m: the noise followed is never more: no scanner a filter can use
# scatters more, while a scene of range jumps (clutter, a garbled scan) measures more


class RangeNoise:
    """The scanner's range noise (one standard deviation), followed over the scans: the
    median of the estimates (:func:`range_noise_m`) of the last ``NOISE_WINDOW`` scans
    measured, one in every ``NOISE_EVERY_SCANS``, once there are ``NOISE_MIN_ESTIMATES``;
    it moves only by more than ``NOISE_HYSTERESIS`` and never beyond ``MAX_LINE_NOISE_M``.
    One scan's estimate varies with the scene (clutter inflates it); the scanner's noise
    does not.

    The estimate is the noise at the ranges most returns lie at: where the noise grows
    with the range, lines nearer the sensor scatter less than it says.
    """

    def __init__(self) -> None:
        self._estimates: collections.deque[float] = collections.deque(maxlen=NOISE_WINDOW)
        self._due = 0  # scans until the next is measured
        self.noise_m = math.nan  # m (NaN: no measure yet)

    def reset(self) -> None:
        """Forget the estimates (another scanner's scans may follow)."""
        self._estimates.clear()
        self._due = 0
        self.noise_m = math.nan

    def update(self, ranges: np.ndarray) -> bool:
        """Take a scan's ranges (m, NaN or inf where no return); True where the noise
        followed changed (the parameters follow it)."""
        if self._due > 0:
            self._due -= 1
            return False
        estimate = range_noise_m(ranges)
        if estimate != estimate:  # NaN: no three consecutive returns; the next scan is due
            return False
        self._due = NOISE_EVERY_SCANS - 1
        self._estimates.append(estimate)
        if len(self._estimates) < NOISE_MIN_ESTIMATES:
            return False
        median = min(median_of_few(self._estimates), MAX_LINE_NOISE_M)
        if abs(median - self.noise_m) <= NOISE_HYSTERESIS * self.noise_m:  # NaN: False
            return False
        self.noise_m = median
        return True
