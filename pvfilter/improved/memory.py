"""The level-view memory: what each beam saw when the scan plane was level.

The paper's likelihood field compares a scan with the scan just before it, so a floor
line is "new" only in its first frame. Physics gives a cue that lasts the whole pitch
event: a floor (or ceiling) line always lies **in front of** the structure a level
scanner sees along the same beams, in space the scanner saw as free a moment ago. The
structure itself does not come closer faster than the sensor moves, and the sensor's
motion is known (:mod:`pvfilter.improved.motion`).

So the memory keeps, per beam, the range of the level view in the current sensor frame:

- each scan, it is moved by the ego-motion (points transformed, then binned back into
  beams; the nearest point wins a beam; one-beam holes take a neighbour's view);
- behind a segment that may be a floor line (``hold_behind_lines``) the view does not
  come closer at all: the line stays "new" until the event ends, even one that creeps in
  slowly as the robot leans into an acceleration;
- elsewhere a beam's return replaces the view when farther, and otherwise pulls it closer
  by at most ``memory_shrink_mps`` times the time step: a person walking in or an
  ego-motion error is absorbed within a frame or two, while a line that jumps in front of
  the view faster than that is new in its first frame, and held from then on;
- beams with no return within range (``+inf``) remember free space up to ``range_max``;
- a beam's view is forgotten (NaN, unknown) after ``memory_timeout_s`` without a return;
- a return that has stayed in front of the view for ``max_event_s`` (longer than a pitch
  event lasts: the balance controller levels the robot) replaces it: the view was wrong.

The memory does not depend on what the filter removed (the segments it holds behind are
chosen whatever ``p_th``), so the filter's state, and with it every threshold of a
precision-recall sweep, follows from the scans alone.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from scipy.ndimage import minimum_filter1d

from pvfilter.improved.beams import BeamLayout, indices
from pvfilter.improved.motion import Motion
from pvfilter.improved.params import ImprovedParams


@dataclasses.dataclass(frozen=True, eq=False)
class LevelView:
    """The level view per beam of one scan.

    Attributes:
        ranges: m; NaN unknown, ``+inf`` free up to ``range_max``.
        ages: s since a return last confirmed the beam.
        ahead_s: s for which the beam's returns have been in front of the view.
    """

    ranges: np.ndarray
    ages: np.ndarray
    ahead_s: np.ndarray


class LevelMemory:
    """Per-beam level view of the scans so far, in the last scan's sensor frame."""

    def __init__(self) -> None:
        self.state: LevelView | None = None

    def reset(self) -> None:
        """Forget everything (a new sequence)."""
        self.state = None

    def view(
        self, layout: BeamLayout, range_max: float, motion: Motion, params: ImprovedParams
    ) -> LevelView:
        """The level view of each beam of the current scan: the memory moved by ``motion``.

        Does not change the memory; :meth:`update` does, with what this returns.
        """
        state = self.state
        remembered = np.fmin(state.ranges, range_max)  # free space: a point at range_max
        known = indices(~np.isnan(remembered))
        moved = motion.apply(layout.points(remembered).take(known, axis=0))
        ranges = np.hypot(moved[:, 0], moved[:, 1])
        beams = layout.beam_of(moved)
        order = np.argsort(-ranges)  # the nearest point is written last and wins its beam
        if not layout.ring:  # on a ring every point lands on a beam
            order = order[beams[order] >= 0]
        target, source = beams[order], known[order]
        n = layout.count
        level, ages, ahead = np.full(n, np.nan), np.full(n, np.inf), np.zeros(n)
        level[target] = ranges[order]
        ages[target] = state.ages[source]
        ahead[target] = state.ahead_s[source]
        _fill_single_holes(level, ages, ahead)
        level[level >= range_max - 1e-6] = np.inf  # free space stays free (rounding)
        level[ages > params.memory_timeout_s] = np.nan
        return LevelView(level, ages, ahead)

    def update(
        self,
        ranges: np.ndarray,
        no_return: np.ndarray,
        view: LevelView | None,
        dt: float,
        params: ImprovedParams,
        hold: np.ndarray | None = None,
    ) -> None:
        """Take a scan into the memory.

        Args:
            ranges: the scan's ranges per beam, m; NaN where invalid.
            no_return: per beam, nothing within ``range_max`` (``+inf``).
            view: what :meth:`view` returned for it; None for the first scan of a sequence.
            dt: time since the previous scan, s.
            params: ``memory_shrink_mps`` and ``max_event_s`` are used.
            hold: bool per beam: the view does not come closer there (None: nowhere).
        """
        n = len(ranges)
        valid = ~np.isnan(ranges)
        if view is None:  # the first scan of a sequence
            level, ages, ahead = np.full(n, np.nan), np.full(n, np.inf), np.zeros(n)
        else:
            level, ages, ahead = view.ranges.copy(), view.ages + dt, view.ahead_s
        shrink = params.memory_shrink_mps * dt
        floor = level - shrink if shrink < np.inf else np.full(n, -np.inf)
        if hold is not None:
            np.copyto(floor, level, where=hold)
        floor[np.isnan(floor)] = -np.inf
        held = ranges < floor  # NaN (invalid) compares False
        ahead = np.where(held, ahead + dt, 0.0)  # in front of the view for this long
        settled = ahead > params.max_event_s
        np.copyto(level, np.fmax(ranges, floor), where=valid)
        level[settled] = ranges[settled]
        ahead[settled] = 0.0
        ages[valid] = 0.0
        level[no_return] = np.inf
        ages[no_return] = 0.0
        self.state = LevelView(level, ages, ahead)


def free_space_gaps(
    ranges: np.ndarray, level: np.ndarray, layout: BeamLayout, params: ImprovedParams
) -> np.ndarray:
    """Per beam: how far in front of the level view the return lies, m (NaN: unknown).

    The level view of a beam is the nearest of the ``memory_window_beams`` beams on each
    side; beams whose own view is unknown, and invalid beams (``ranges`` NaN), get NaN.
    ``+inf`` means the level view saw nothing within ``range_max`` along the beam.
    """
    unknown = np.isnan(level)
    nearest = window_minimum(np.where(unknown, np.inf, level), params.memory_window_beams, layout)
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


def _fill_single_holes(level: np.ndarray, ages: np.ndarray, ahead: np.ndarray) -> None:
    """Give beams that no remembered point landed on their nearer neighbour's values."""
    hole = indices(np.isnan(level))
    if hole.size == 0 or hole.size == len(level):
        return
    n = len(level)
    left, right = (hole - 1) % n, (hole + 1) % n
    take_left = ~np.isnan(level[left]) & ~(level[right] < level[left])
    source = np.where(take_left, left, right)
    fill = ~np.isnan(level[source])
    hole, source = hole[fill], source[fill]
    level[hole], ages[hole], ahead[hole] = level[source], ages[source], ahead[source]
