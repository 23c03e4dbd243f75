"""Segmentation that splits a floor or ceiling line from the structure it touches.

A tilted scan plane meets the floor along the straight line ``x = h / sin(pitch)`` in the
sensor frame, across the direction of travel, and meets the walls beside it in one
continuous curve: distance-based clustering joins the two (the paper's filter then sees a
cluster that is mostly wall). Here every point gets the direction of its neighbourhood in
scan order (not across a range jump), and a segment is a run of consecutive points that

- are at most ``break_distance_m`` (plus 2 % of the range) apart, farther where beams
  that returned no echo lie between them (:func:`break_distances`: a floor met at a
  grazing angle echoes on a few beams only), and
- all lie on a line across the direction of travel (local direction within
  ``line_angle_deg`` of the sensor's y axis), or all do not; a lone point whose two
  neighbours agree takes their side (:func:`single_flips_smoothed`: a floor line leaning
  with the roll, met by a noisy scanner, lies near that bound).

The neighbourhood is a chord of about ``chord_m``: near the sensor, where the range noise
is large against the beam spacing, it spans more beams. Each segment then gets a
total-least-squares line: its normal, its distance from the sensor, its spread along the
line and across it.
"""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np

from pvfilter.improved.beams import indices, row_norms
from pvfilter.improved.params import ImprovedParams

MIN_HALF_WIDTH = 3  # beams: the chord spans at least this many neighbours on each side
MAX_HALF_WIDTH = 40  # beams: and at most this many (20 deg at 2 beams per degree)
BRIDGE_INCIDENCE_DEG = 70.0  # deg: beams without a return between two points of one
# line widen the gap allowed between them by the spacing of beams on a line met at up to
# this angle from its normal, r * increment / cos(angle) per missing beam (a floor line at
# grazing incidence returns no echo on many of its beams, and comes in fragments)
BRIDGE_MAX_DEG = 5.0  # deg: wider stretches of missing beams are not bridged
SINE_BAND_RAD = 1e-6  # rad: a direction this far from a sine bound's angle is on one
# side of it: the sine differs from the bound by at least 2 sin^2(band / 2) = 5e-13 even
# next to pi/2, where the sine is flattest, far more than its rounding (1e-16)


def local_directions(
    points: np.ndarray, half_width: np.ndarray | int, runs: np.ndarray | None = None
) -> np.ndarray:
    """Direction of the line through each point's neighbourhood in scan order, rad.

    The chord from the point ``half_width`` before to the one ``half_width`` after (fewer
    at the ends of the scan or of a run): on a line of points with noise ``sigma`` and a
    chord of length ``L``, its angle errs by about ``sigma / L``.

    Args:
        points: valid points in beam order, sensor frame, m, shape ``(m, 2)``.
        half_width: neighbours on each side, points (one for all, or one per point).
        runs: run id per point (ascending); a chord never reaches into another run
            (across a range jump). None: one run.

    Returns:
        Angle of each local line from the x axis, in ``(-pi/2, pi/2]``, shape ``(m,)``.
    """
    m = len(points)
    if m == 0:
        return np.zeros(0)
    if runs is None:
        return _chord_directions(points, half_width, np.zeros(0, dtype=np.intp))
    return _chord_directions(points, half_width, (runs[1:] != runs[:-1]).nonzero()[0] + 1)


def _chord_directions(
    points: np.ndarray, half_width: np.ndarray | int, ends: np.ndarray
) -> np.ndarray:
    """:func:`local_directions` of ``m > 0`` points whose later runs start at ``ends``.

    Each point's run bounds are its run's first and last point, repeated over the run:
    a run's first point is >= 0 and its last <= m - 1, so they bound the scan too.
    """
    m = len(points)
    at = np.arange(m)
    bounds = bounds_of(ends, m)
    first, after = bounds[:-1], bounds[1:]
    lengths = after - first
    low = np.maximum(at - half_width, first.repeat(lengths))
    high = np.minimum(at + half_width, (after - 1).repeat(lengths))
    chord = points.take(high, axis=0)
    chord -= points.take(low, axis=0)
    angle = np.arctan2(chord[:, 1], chord[:, 0])
    # a line has no sense of direction: fold into (-pi/2, pi/2], in place (on the indices
    # of the angles to fold: a masked ufunc costs more than gathering the few there are)
    folded = indices(angle > 0.5 * np.pi)
    angle[folded] -= np.pi
    folded = indices(angle <= -0.5 * np.pi)
    angle[folded] += np.pi
    return angle


def bounds_of(cuts: np.ndarray, m: int) -> np.ndarray:
    """``0``, the ``cuts``, then ``m``: the first index of every run and the end of the last
    (np.concatenate with a list converts the list to an array first, at more cost)."""
    bounds = np.empty(cuts.size + 2, dtype=np.intp)
    bounds[0], bounds[-1] = 0, m
    bounds[1:-1] = cuts
    return bounds


def line_spreads(
    cxx: np.ndarray, cxy: np.ndarray, cyy: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The total-least-squares line of points whose covariance is ``(cxx, cxy, cyy)``, m^2:
    its direction from the x axis, rad, and the variances of the points along it and
    across it, m^2 (the covariance's two eigenvalues)."""
    return line_direction(cxx, cxy, cyy), *line_variances(cxx, cxy, cyy)


def line_direction(cxx: np.ndarray, cxy: np.ndarray, cyy: np.ndarray) -> np.ndarray:
    """The direction of :func:`line_spreads`' line from the x axis, rad (apart: the corner
    search needs it only for the best cut of each segment, and ``arctan2`` is dear)."""
    return 0.5 * np.arctan2(2.0 * cxy, cxx - cyy)


def line_variances(
    cxx: np.ndarray, cxy: np.ndarray, cyy: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The variances of :func:`line_spreads`' points along its line and across it, m^2."""
    half_sum, root = 0.5 * (cxx + cyy), np.hypot(0.5 * (cxx - cyy), cxy)
    return half_sum + root, np.maximum(half_sum - root, 0.0)


def chord_half_widths(ranges: np.ndarray, increment: float, chord_m: float) -> np.ndarray:
    """Neighbours on each side that make a chord of about ``chord_m`` at each range, beams."""
    beams = np.maximum(ranges, 1e-3)
    beams *= increment
    np.ceil(np.divide(0.5 * chord_m, beams, out=beams), out=beams)
    # np.clip's bounds, without its Python layers
    np.minimum(np.maximum(beams, MIN_HALF_WIDTH, out=beams), MAX_HALF_WIDTH, out=beams)
    return beams.astype(np.intp)


def across_travel(directions: np.ndarray, line_angle_deg: float) -> np.ndarray:
    """Per point: its local direction lies within ``line_angle_deg`` of the y axis,
    ``|sin(direction)| > cos(line_angle)``, for directions in ``[-pi/2, pi/2]``.

    ``|sin|`` rises with ``|direction|`` there, so only directions within
    ``SINE_BAND_RAD`` of the bound's angle need the sine; the rest compare ``|direction|``
    with that angle, at a fraction of the sine's cost, and decide the same.
    """
    bound, angle = _sine_bound(line_angle_deg)
    size = np.abs(directions)
    across = size > angle + SINE_BAND_RAD
    near = indices((size >= angle - SINE_BAND_RAD) & ~across)
    if near.size:
        across[near] = np.abs(np.sin(directions.take(near))) > bound
    return across


def single_flips_smoothed(across: np.ndarray) -> np.ndarray:
    """``across`` with every point whose two neighbours in scan order agree with each
    other and not with it given their value: the majority of three.

    A point's local direction is measured over a chord of several beams, so a real turn
    of direction (a wall meeting the floor line) changes it over a run of points; one
    point alone across the direction of travel, or alone not, is range noise. A floor line
    leaning with the roll, met by a noisy scanner, sits near the ``line_angle_deg`` bound,
    and such lone points would cut it into pieces too short to score. In place; the first
    and last point keep their values.
    """
    if across.size > 2:
        before, after = across[:-2], across[2:]
        across[1:-1] = np.where(before == after, before, across[1:-1])
    return across


@functools.cache
def _sine_bound(line_angle_deg: float) -> tuple[np.float64, float]:
    """``cos(line_angle)`` (as numpy works it out from degrees) and the angle whose sine
    it is, rad: the same two numbers for every scan, worked out once."""
    bound = np.cos(np.radians(line_angle_deg))
    return bound, math.asin(bound)


@dataclasses.dataclass(frozen=True, eq=False)
class Segments:
    """A scan cut into segments; each segment's line is fitted when first asked for.

    Attributes:
        beams: beam index of every valid point, ascending, shape ``(m,)``.
        points: those points, sensor frame, m, ``(m, 2)``.
        labels: segment id of every valid point (0..k-1 in scan order), ``(m,)``.
        directions: local line direction per valid point, rad, ``(m,)``.
        across: per segment, its points lie on a line across the direction of travel.
        sizes: points per segment, ``(k,)``.
        seam_joined: the scan is a full turn and its last segment continues its first
            across the seam, where the sweep starts and ends: the two would be one
            segment had the sweep started elsewhere
            (:func:`pvfilter.improved.claims.seam_claims`).
        memo: what later stages work out from the segments and would otherwise work out
            twice (the points' ranges, the points that lines claim), by what was asked.
    """

    beams: np.ndarray
    points: np.ndarray
    labels: np.ndarray
    directions: np.ndarray
    across: np.ndarray
    sizes: np.ndarray
    seam_joined: bool = False
    memo: dict = dataclasses.field(default_factory=dict, init=False, repr=False)

    def __len__(self) -> int:
        return int(self.sizes.size)

    @property
    def ranges(self) -> np.ndarray:
        """Distance of each point from the sensor, m, ``(m,)`` (kept in ``memo``: the
        segmentation works it out, and the line stages ask for it again)."""
        if "ranges" not in self.memo:
            self.memo["ranges"] = row_norms(self.points)
        return self.memo["ranges"]

    @property
    def bounds(self) -> np.ndarray:
        """Each segment's first point, then the number of points, ``(k + 1,)``: segment
        ``i`` is points ``bounds[i] .. bounds[i + 1] - 1`` (kept in ``memo``: the
        segmentation works it out)."""
        if "bounds" not in self.memo:
            bounds = np.zeros(len(self) + 1, dtype=np.intp)
            np.cumsum(self.sizes, out=bounds[1:])
            self.memo["bounds"] = bounds
        return self.memo["bounds"]

    @property
    def beam_spans(self) -> np.ndarray:
        """Each segment's beams from its first point to its last, both counted, ``(k,)``
        (kept in ``memo``): a segment's points are a run of the scan's valid points, so
        the beams among them that are not its own gave no valid return."""
        if "beam_spans" not in self.memo:
            bounds = self.bounds
            first, last = self.beams.take(bounds[:-1]), self.beams.take(bounds[1:] - 1)
            self.memo["beam_spans"] = last - first + 1
        return self.memo["beam_spans"]

    @functools.cached_property
    def _fit(self) -> tuple[np.ndarray, ...]:
        """Centroids, unit normals, distances, the two spreads and the signed offsets of
        the fitted lines."""
        k, labels, x, y = len(self), self.labels, self.points[:, 0], self.points[:, 1]
        mean_x = np.bincount(labels, x, k) / self.sizes
        mean_y = np.bincount(labels, y, k) / self.sizes
        # second moments about the mean, from raw sums (ranges are metres: no cancellation)
        cxx = np.bincount(labels, x * x, k) / self.sizes - mean_x * mean_x
        cyy = np.bincount(labels, y * y, k) / self.sizes - mean_y * mean_y
        cxy = np.bincount(labels, x * y, k) / self.sizes - mean_x * mean_y
        angle, along, across = line_spreads(cxx, cxy, cyy)
        normals, centroids = np.empty((k, 2)), np.empty((k, 2))  # (np.stack is slower)
        np.negative(np.sin(angle), out=normals[:, 0])
        np.cos(angle, out=normals[:, 1])
        centroids[:, 0], centroids[:, 1] = mean_x, mean_y
        offsets = mean_x * normals[:, 0] + mean_y * normals[:, 1]
        return centroids, normals, np.abs(offsets), along, across, offsets

    @property
    def centroids(self) -> np.ndarray:
        """Mean point per segment, m, ``(k, 2)``."""
        return self._fit[0]

    @property
    def normals(self) -> np.ndarray:
        """Unit normal of each segment's fitted line (total least squares), ``(k, 2)``."""
        return self._fit[1]

    @property
    def distances(self) -> np.ndarray:
        """Distance of each segment's fitted line from the sensor, m, ``(k,)``."""
        return self._fit[2]

    @property
    def offsets(self) -> np.ndarray:
        """Signed offset of each segment's fitted line from the sensor along its normal,
        ``centroid . normal``, m (``distances`` is its size): the geometry and the claims
        ask for it too, and would otherwise work it out again."""
        return self._fit[5]

    @property
    def spread_along(self) -> np.ndarray:
        """Variance of each segment's points along its line, m^2 (length^2 / 12)."""
        return self._fit[3]

    @property
    def lengths(self) -> np.ndarray:
        """Each segment's length along its line, m: that of evenly spaced points with its
        spread along it, ``sqrt(12 var)`` (kept in ``memo``: the scoring asks twice)."""
        if "lengths" not in self.memo:
            self.memo["lengths"] = np.sqrt(12.0 * np.maximum(self.spread_along, 0.0))
        return self.memo["lengths"]

    @property
    def spread_across(self) -> np.ndarray:
        """Variance of each segment's points across its line, m^2 (noise, curvature)."""
        return self._fit[4]


def break_distances(
    ranges: np.ndarray,
    beams: np.ndarray,
    increment: float,
    break_distance_m: float,
    no_echo: np.ndarray | None = None,
) -> np.ndarray:
    """Per pair of consecutive valid points: the gap that cuts a segment between them, m.

    ``break_distance_m`` plus 2 % of the range (``ranges``: the second point's, m), widened
    where beams without an echo lie between the two (``beams``: the valid points' beam
    indices, ascending) by ``range * increment / cos(BRIDGE_INCIDENCE_DEG)`` per missing
    beam, where they span at most ``BRIDGE_MAX_DEG`` (a wider gap is open space). A line
    the plane meets at grazing incidence (the floor, the ceiling) returns no echo on many
    beams; its points then lie several beam spacings apart, and the pieces between the
    dropouts are one line. ``no_echo``: per beam of the scan, it returned nothing within
    range (``+inf``); a gap with an invalid beam (``NaN``, ``-inf``) in it is not bridged
    (None: every missing beam counts as one without an echo).
    """
    cut = break_distance_m + 0.02 * ranges
    most = round(math.radians(BRIDGE_MAX_DEG) / abs(increment))
    steps = beams[1:] - beams[:-1]
    gaps = indices((steps > 1) & (steps <= most + 1))  # (few: most beams return)
    if gaps.size == 0:
        return cut
    missing = steps.take(gaps) - 1
    if no_echo is not None:  # every beam between returned nothing, or it is a gap
        # echoless beams up to each beam: a count per gap, not a (gaps, most) gather; a
        # gap with a beam that returned something adds nothing (0 missing beams)
        silent = np.add.accumulate(no_echo, dtype=np.intp)  # (np.cumsum: more Python layers)
        before = beams.take(gaps)
        missing *= silent.take(before + missing) - silent.take(before) == missing
    per_missing = abs(increment) / math.cos(math.radians(BRIDGE_INCIDENCE_DEG))
    cut[gaps] += ranges.take(gaps) * (per_missing * missing)
    return cut


def segment_scan(
    points: np.ndarray,
    beams: np.ndarray,
    increment: float,
    params: ImprovedParams,
    ring: bool = False,
    no_echo: np.ndarray | None = None,
) -> Segments:
    """Cut the valid points of a scan into segments (their lines are fitted on demand).

    Args:
        points: valid points in beam order, sensor frame, m, ``(m, 2)``.
        beams: their beam indices, ascending.
        increment: angle between beams, rad.
        params: ``chord_m``, ``line_angle_deg`` and ``break_distance_m`` are used.
        ring: the beams cover a full turn: the last point neighbours the first.
        no_echo: per beam of the scan, it returned nothing (:func:`break_distances`).
    """
    m = len(points)
    if m == 0:
        empty = np.zeros(0, dtype=np.intp)
        return Segments(beams, points, empty, np.zeros(0), np.zeros(0, bool), empty)
    ranges = row_norms(points)
    gap = row_norms(points[1:] - points[:-1])
    jumps = gap > break_distances(ranges[1:], beams, increment, params.break_distance_m, no_echo)
    half_widths = chord_half_widths(ranges, increment, params.chord_m)
    directions = _chord_directions(points, half_widths, jumps.nonzero()[0] + 1)
    across = single_flips_smoothed(across_travel(directions, params.line_angle_deg))
    cuts = (jumps | (across[1:] != across[:-1])).nonzero()[0] + 1
    seam_joined = False
    if ring and cuts.size > 0 and across[0] == across[-1]:  # the last point, then the first
        (x0, y0), (x1, y1) = points[0].tolist(), points[-1].tolist()  # (floats: no ufuncs)
        seam_m = math.hypot(x0 - x1, y0 - y1)
        seam_joined = seam_m <= params.break_distance_m + 0.02 * math.hypot(x0, y0)
    return segments_at(beams, points, directions, across, ranges, cuts, seam_joined)


def segments_at(
    beams: np.ndarray,
    points: np.ndarray,
    directions: np.ndarray,
    across: np.ndarray,
    ranges: np.ndarray,
    cuts: np.ndarray,
    seam_joined: bool,
) -> Segments:
    """The segments that start at the points ``cuts`` (ascending, none at 0).

    Args:
        beams, points, directions: as :class:`Segments` holds them, per valid point.
        across: per valid point, its local direction lies across the direction of travel
            (a segment takes its first point's).
        ranges: per valid point, its distance from the sensor, m.
        cuts: the first points of every segment but the first.
        seam_joined: see :class:`Segments`.
    """
    m = len(points)
    bounds = bounds_of(cuts, m)
    starts = bounds[:-1]
    sizes = bounds[1:] - starts
    labels = np.arange(sizes.size).repeat(sizes)  # (cheaper than a cumulative sum of cuts)
    segments = Segments(
        beams=beams,
        points=points,
        labels=labels,
        directions=directions,
        across=across.take(starts),
        sizes=sizes,
        seam_joined=seam_joined,
    )
    segments.memo["ranges"] = ranges  # worked out already: Segments.ranges
    segments.memo["bounds"] = bounds  # and Segments.bounds
    return segments
