"""Free-space evidence: how far in front of the level view each return lies.

A floor or ceiling line always lies in front of the structure a level scanner sees along
the same beams, in space that scanner saw as free (:mod:`pvfilter.improved.memory`). A
return is **new** when it lies in front of the level view by more than a margin: range
noise and the ego-motion's error, plus a share of the range for angular error. A return
**seen through** the view lies beyond it by more than that margin.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy.ndimage import minimum_filter1d

from pvfilter.improved.beams import BeamLayout
from pvfilter.improved.motion import Motion

STANDING_PITCH_CHANGE = math.radians(0.5)  # rad: the least a standing robot's pitch
# changes over the world-static baseline while a pitch event lasts (see WorldStatic)
STATIC_TOLERANCE_M = 0.03  # m: how near where it was seen before a return of the same
# surface lies (range noise of two measurements, plus the motion's or the level view's
# error; plus 1 % of the range): the world-static test, and a return on the level view
MIN_FACING = 0.3  # cosine between beam and surface normal below which the world-static
# test does not tell (a grazing beam slides along its surface)
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
    nearest = window_minimum(np.fmin(level, np.inf), WINDOW_BEAMS, layout)  # NaN: inf
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


def seen_through(
    gaps: np.ndarray, ranges: np.ndarray, margin_m: float, margin_rel: float
) -> np.ndarray:
    """Per beam: the return lies beyond the level view by more than the margin (the
    beam passed where the view had a surface: it moved away, or the motion is off).

    Args as :func:`new_points`.
    """
    return gaps < -(margin_m + margin_rel * ranges)  # NaN compares False


def free_space_evidence(
    gaps: np.ndarray, ranges: np.ndarray, margin_m: float, margin_rel: float
) -> tuple[np.ndarray, np.ndarray | None]:
    """:func:`new_points` and :func:`seen_through` in one pass: the margin is worked out
    once for both. Where no return is new, the returns seen through the view tell nothing
    (they only weigh against lines with new returns): None then, not worked out.

    Args as :func:`new_points`.
    """
    margin = margin_rel * ranges
    margin += margin_m  # margin_m + margin_rel * ranges, as the two functions add them
    new = gaps > margin  # NaN (unknown, invalid) compares False
    if not np.count_nonzero(new):
        return new, None
    return new, gaps < np.negative(margin, out=margin)


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
    padded = np.empty(n + 2 * half)  # (filled by slices: cheaper than np.concatenate)
    padded[half : n + half] = values
    if layout.ring:
        padded[:half], padded[n + half :] = values[n - half :], values[:half]
    else:
        padded[:half], padded[n + half :] = values[0], values[n - 1]
    least = np.minimum(padded[:n], padded[1 : n + 1])
    for offset in range(2, 2 * half + 1):
        np.minimum(least, padded[offset : offset + n], out=least)
    return least


@dataclasses.dataclass(frozen=True, eq=False)
class WorldStatic:
    """Which returns an earlier scan saw at the same place in the world.

    A wall stays where it is while the sensor moves; a floor line moves with the sensor
    (it lies ``h / sin(pitch)`` from it). The earlier range on the beam the turn brings
    here, moved by the translation ``t`` as the surface through the return sees it
    (``t . n / (u . n)`` along the beam ``u``, ``n`` the surface's normal from the local
    line direction), predicts where a static return lies now. The test tells only where
    the sensor moved along the beam by more than twice the tolerance, and not where the
    beam grazes the surface (``MIN_FACING``). It is evaluated only for the beams asked
    about (those of candidate lines).

    Where the sensor stood, a floor line still moves when the pitch changes, and a
    balancing robot that stands holds one pitch only at its balance point, where its
    plane meets no floor (or meets it where it always does, a mount's tilt: structure to
    the filter too). So there the test also tells where the line a return lies on would
    move by more than twice the tolerance for a pitch change of ``STANDING_PITCH_CHANGE``
    (``floor_shift_m``, from :func:`pvfilter.improved.geometry.floor_shift`): a shallow
    line that stayed put is a wall that came back into view, not the floor.

    Where the sensor turned, the floor line of a tilt held through the turn keeps its
    place in the sensor frame, and near the foot of its perpendicular the range the turn
    brings to a beam hardly differs from the beam's own: there a surface fixed in the
    world and one fixed to the sensor predict the same range, and a return tells only
    where the two predictions lie more than twice the tolerance apart.

    Attributes:
        ranges: this scan's ranges per beam (mid-scan frame, unstretched), m; NaN where
            invalid.
        previous_ranges: the earlier scan's, m; NaN where invalid.
        directions: the local line direction per beam, rad (NaN: unknown).
        layout: the beams.
        since: the motion from the earlier scan to this one.
        tolerance_m: how near the prediction a static return lies, m (plus 1 % of range).
    """

    ranges: np.ndarray
    previous_ranges: np.ndarray
    directions: np.ndarray
    layout: BeamLayout
    since: Motion
    tolerance_m: float

    def at(
        self, beams: np.ndarray, floor_shift_m: np.ndarray | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """For ``beams``: the return is where the earlier scan saw it; the test tells.

        Args:
            beams: the beams asked about.
            floor_shift_m: per beam asked about, how far the floor line through its
                return would move for a pitch change of ``STANDING_PITCH_CHANGE``, m
                (None: the sensor's own motion alone tells).
        """
        layout, since = self.layout, self.since
        shift = round(since.theta_rad / layout.increment)
        angle = self.directions.take(beams)
        normal_x, normal_y = -np.sin(angle), np.cos(angle)
        facing = layout.cos.take(beams) * normal_x + layout.sin.take(beams) * normal_y
        toward = since.tx_m * normal_x + since.ty_m * normal_y  # t . n
        facing_ok = np.abs(facing) > MIN_FACING
        # how far a static return moved along its beam, m, where the beam faces its surface;
        # 0 at grazing incidence, where the quotient divides by nearly 0 and means nothing
        # (there only the standing sensor's pitch test below tells), and without the cost
        # of an errstate to silence a division by zero
        moved = np.divide(toward, facing, out=np.zeros(len(beams)), where=facing_ok)
        earlier = layout.shifted(self.previous_ranges, shift).take(beams)
        ranges = self.ranges.take(beams)
        tolerance = self.tolerance_m + 0.01 * ranges
        twice = 2.0 * tolerance  # farther than this tells
        telling = (np.abs(moved) > twice) & facing_ok
        if floor_shift_m is not None:  # the sensor stood: a floor line moves with the pitch
            stood = math.hypot(since.tx_m, since.ty_m) <= twice
            telling |= stood & (floor_shift_m > twice) & ~np.isnan(earlier)
        if shift != 0:  # the sensor turned: a surface fixed to it keeps its beam
            telling &= np.abs(earlier - self.previous_ranges.take(beams)) > twice
        static = telling & (np.abs(ranges - (earlier + moved)) <= tolerance)  # NaN: False
        return static, telling


class RecentScans:
    """The ranges of the scans of the last ``baseline_s`` seconds (mid-scan frame,
    unstretched) and where the sensor was for each: what the world-static test compares
    with.

    The sensor's pose is kept as the motion from a fixed frame (the first scan's) to each
    scan's, so a scan costs one composition, and the motion between two of them is
    worked out only when asked for.
    """

    def __init__(self, baseline_s: float) -> None:
        self.baseline_s = baseline_s
        self.scans: list[tuple[float, np.ndarray, Motion]] = []  # (stamp, ranges, pose)
        self.pose = Motion()  # the fixed frame -> the latest scan's

    def clear(self) -> None:
        """Forget them (a re-baseline)."""
        self.scans.clear()
        self.pose = Motion()

    def moved(self, step: Motion) -> tuple[np.ndarray, Motion] | None:
        """Take the sensor's step to the scan now; the oldest kept scan's ranges and the
        motion from it to now (None: none kept)."""
        self.advance(step)
        return self.oldest()

    def advance(self, step: Motion) -> None:
        """Take the sensor's step to the scan now."""
        self.pose = self.pose.then(step)

    def oldest(self) -> tuple[np.ndarray, Motion] | None:
        """The oldest kept scan's ranges and the motion from it to now (None: none kept)."""
        if not self.scans:
            return None
        _, ranges, pose = self.scans[0]
        return ranges, pose.inverse().then(self.pose)

    def add(self, stamp: float, ranges: np.ndarray) -> None:
        """Take the scan now in, and drop those older than ``baseline_s`` (keeping one)."""
        self.scans.append((stamp, ranges, self.pose))
        while stamp - self.scans[0][0] > self.baseline_s:
            self.scans.pop(0)
