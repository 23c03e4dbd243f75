"""Free-space evidence: how far in front of the level view each return lies.

A floor or ceiling line always lies in front of the structure a level scanner sees along
the same beams, in space that scanner saw as free (:mod:`pvfilter.improved.memory`). A
return is **new** when it lies in front of the level view by more than a margin: range
noise and the ego-motion's error, plus a share of the range for angular error.
"""

from __future__ import annotations

import numpy as np
from scipy.ndimage import minimum_filter1d

from pvfilter.improved.beams import BeamLayout
from pvfilter.improved.motion import Motion

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
    unknown = np.isnan(level)
    nearest = window_minimum(np.where(unknown, np.inf, level), WINDOW_BEAMS, layout)
    np.minimum(nearest, range_max, out=nearest)
    gaps = nearest - ranges
    gaps[unknown] = np.nan
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


def window_minimum(values: np.ndarray, half: int, layout: BeamLayout) -> np.ndarray:
    """The least of ``values`` over beams ``i - half .. i + half`` (no NaN in ``values``).

    As ``scipy.ndimage.minimum_filter1d`` (wrapping on a ring, else repeating the end
    values), but for the usual window of three beams two ``np.minimum`` calls on a padded
    copy cost a fraction of scipy's set-up.
    """
    n = len(values)
    if half == 0 or n == 0:
        return values
    if half >= n or half > 4:
        mode = "wrap" if layout.ring else "nearest"
        return minimum_filter1d(values, 2 * half + 1, mode=mode)
    if layout.ring:
        padded = np.concatenate((values[n - half :], values, values[:half]))
    else:
        padded = np.concatenate((values[:1].repeat(half), values, values[-1:].repeat(half)))
    least = padded[:n].copy()
    for offset in range(1, 2 * half + 1):
        np.minimum(least, padded[offset : offset + n], out=least)
    return least


def world_static(
    ranges: np.ndarray,
    previous_ranges: np.ndarray,
    layout: BeamLayout,
    since: Motion,
    tolerance_m: float,
) -> tuple[np.ndarray, np.ndarray]:
    """Per beam: an earlier scan saw this return at the same place in the world.

    A wall stays where it is while the sensor moves; a floor line moves with the sensor
    (it lies ``h / sin(pitch)`` from it). The earlier range on the beam the turn brings
    here, moved by the translation along the beam (first order: exact for a surface
    across the beam, as floor lines and the walls they are mistaken for are), predicts
    where a static return lies now. The test tells only where the sensor moved along the
    beam by more than twice the tolerance.

    Args:
        ranges: this scan's ranges per beam (mid-scan frame, unstretched), m; NaN where
            invalid.
        previous_ranges: the earlier scan's, m; NaN where invalid.
        layout: the beams.
        since: the motion from the earlier scan to this one.
        tolerance_m: how near the prediction a static return lies, m (plus 1 % of range).

    Returns:
        Per beam, the return is where the earlier scan saw it; and whether the test tells
        there (the sensor moved far enough along the beam).
    """
    shift = round(since.theta_rad / layout.increment)
    moved = since.tx_m * layout.cos + since.ty_m * layout.sin  # a static point's range change
    predicted = layout.shifted(previous_ranges, shift) + moved
    tolerance = tolerance_m + 0.01 * ranges
    telling = np.abs(moved) > 2.0 * tolerance  # NaN: False
    static = telling & (np.abs(ranges - predicted) <= tolerance)
    return static, telling


class RecentScans:
    """The ranges of the scans of the last ``baseline_s`` seconds (mid-scan frame,
    unstretched), with the motion from each to the latest: what the world-static test
    compares with."""

    def __init__(self, baseline_s: float) -> None:
        self.baseline_s = baseline_s
        self.scans: list[tuple[float, np.ndarray, Motion]] = []

    def clear(self) -> None:
        """Forget them (a re-baseline)."""
        self.scans.clear()

    def moved(self, step: Motion) -> tuple[np.ndarray, Motion] | None:
        """Move every scan by ``step``; the oldest one's ranges and motion (None: none)."""
        self.scans = [(t, r, since.then(step)) for t, r, since in self.scans]
        return (self.scans[0][1], self.scans[0][2]) if self.scans else None

    def add(self, stamp: float, ranges: np.ndarray) -> None:
        """Take a scan in, and drop those older than ``baseline_s`` (keeping one)."""
        self.scans.append((stamp, ranges, Motion()))
        while stamp - self.scans[0][0] > self.baseline_s:
            self.scans.pop(0)
