"""The scanner's range noise, measured on one scan alone.

The ego-motion's scan match is judged by its residuals
(:func:`pvfilter.improved.egomotion.fit_trusted`): a right fit leaves about the range
noise, a wrong one far more. A fixed bound for them suits one class of LiDAR only: a
scanner with 5 cm of range noise leaves about 5 cm on right fits, and a 5 cm bound refused
44 % of its matches.

Consecutive beams are a fraction of a degree apart: along a surface the range changes
smoothly from beam to beam, and its second difference, ``r[i-1] - 2 r[i] + r[i+1]``, is
the noise of three ranges (``sqrt(6)`` times the noise) plus the surface's curvature
(a flat wall at 60 deg incidence and 3 m adds 1.6 mm at 0.5 deg between beams). Its median
over the scan is not moved by the few beams at range jumps and corners.
"""

from __future__ import annotations

import math

import numpy as np

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
    # r[i-1] - 2 r[i] + r[i+1], written into one array (a level scan's fit over the bound
    # is rare: this runs on noisy scanners' scans only)
    second = returns[:-2] - 2.0 * returns[1:-1]
    second += returns[2:]
    second = second[second == second]  # NaN where a beam has no return
    if second.size == 0:
        return math.nan
    return float(np.median(np.abs(second, out=second))) / _MEDIAN_PER_SIGMA


NOISE_WINDOW_SCANS = 25  # the scanner's noise is the median of this many estimates
NOISE_EVERY_SCANS = 4  # scans: one is measured in every so many (the noise is the
# scanner's and changes slowly, if at all; measuring every scan cost 7 % of the filter's time)
NOISE_STEP_M = 0.0025  # m: the noise the parameters follow is rounded up to this step
# (the parameters are worked out again only when it changes)


class RangeNoise:
    """The scanner's range noise, followed over the scans: the median of the last
    ``NOISE_WINDOW_SCANS`` estimates (:func:`range_noise_m`) of one scan in every
    ``NOISE_EVERY_SCANS``, rounded up to ``NOISE_STEP_M``. One scan's estimate varies with
    the scene (clutter inflates it); the scanner's noise does not."""

    def __init__(self) -> None:
        self._estimates: list[float] = []
        self._scans = 0  # scans taken since the last reset
        self.noise_m = math.nan  # m (NaN: no estimate yet)

    def reset(self) -> None:
        """Forget the estimates (another scanner's scans may follow)."""
        self._estimates.clear()
        self._scans = 0
        self.noise_m = math.nan

    def update(self, ranges: np.ndarray) -> bool:
        """Take a scan's ranges (m, NaN or inf where no return); True where the noise the
        parameters follow changed."""
        self._scans += 1
        if (self._scans - 1) % NOISE_EVERY_SCANS:
            return False
        estimate = range_noise_m(ranges)
        if estimate != estimate:  # NaN: no three consecutive returns
            return False
        self._estimates.append(estimate)
        if len(self._estimates) > NOISE_WINDOW_SCANS:
            del self._estimates[0]
        noise = math.ceil(float(np.median(self._estimates)) / NOISE_STEP_M) * NOISE_STEP_M
        changed = noise != self.noise_m
        self.noise_m = noise
        return changed
