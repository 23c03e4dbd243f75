"""Segmentation that splits a floor or ceiling line from the structure it touches.

A tilted scan plane meets the floor along the straight line ``x = h / sin(pitch)`` in the
sensor frame, across the direction of travel, and meets the walls beside it in one
continuous curve: distance-based clustering joins the two (the paper's filter then sees a
cluster that is mostly wall). Here every point gets the direction of its neighbourhood in
scan order (not across a range jump), and a segment is a run of consecutive points that

- are at most ``break_distance_m`` (plus 2 % of the range) apart, and
- all lie on a line across the direction of travel (local direction within
  ``line_angle_deg`` of the sensor's y axis), or all do not.

So a floor line and the side wall it runs into fall into different segments at the
corner. Each segment then gets a total-least-squares line: its normal, its distance from
the sensor, and what tilt and roll of the scan plane would put the floor there.
"""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np

from pvfilter.improved.params import ImprovedParams


def local_directions(
    points: np.ndarray, half_width: int, runs: np.ndarray | None = None
) -> np.ndarray:
    """Direction of the line through each point's neighbourhood in scan order, rad.

    The chord from the point ``half_width`` before to the one ``half_width`` after (fewer
    at the ends of the scan or of a run): on a line of points with noise ``sigma`` spaced
    ``s`` apart, its angle errs by about ``sigma / (half_width * s)``, a few degrees, and it
    costs a few array operations.

    Args:
        points: valid points in beam order, sensor frame, m, shape ``(m, 2)``.
        half_width: neighbours on each side, points.
        runs: run id per point (ascending); a chord never reaches into another run
            (across a range jump). None: one run.

    Returns:
        Angle of each local line from the x axis, in ``(-pi/2, pi/2]``, shape ``(m,)``.
    """
    m = len(points)
    if m == 0:
        return np.zeros(0)
    at = np.arange(m)
    if runs is None:
        low, high = np.maximum(at - half_width, 0), np.minimum(at + half_width, m - 1)
    else:  # a run's first point is >= 0 and its last <= m - 1: they bound the scan too
        ends = (runs[1:] != runs[:-1]).nonzero()[0] + 1  # first point of each later run
        low = np.maximum(at - half_width, np.concatenate(([0], ends)).take(runs))
        high = np.minimum(at + half_width, np.concatenate((ends, [m])).take(runs) - 1)
    chord = points.take(high, axis=0)
    chord -= points.take(low, axis=0)
    angle = np.arctan2(chord[:, 1], chord[:, 0])
    # a line has no sense of direction: fold into (-pi/2, pi/2], in place
    np.subtract(angle, np.pi, out=angle, where=angle > 0.5 * np.pi)
    np.add(angle, np.pi, out=angle, where=angle <= -0.5 * np.pi)
    return angle


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
    """

    beams: np.ndarray
    points: np.ndarray
    labels: np.ndarray
    directions: np.ndarray
    across: np.ndarray
    sizes: np.ndarray

    def __len__(self) -> int:
        return int(self.sizes.size)

    @functools.cached_property
    def _fit(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Centroids, unit normals and distances from the sensor of the fitted lines."""
        k, labels, x, y = len(self), self.labels, self.points[:, 0], self.points[:, 1]
        mean_x = np.bincount(labels, x, k) / self.sizes
        mean_y = np.bincount(labels, y, k) / self.sizes
        # second moments about the mean, from raw sums (ranges are metres: no cancellation)
        cxx = np.bincount(labels, x * x, k) / self.sizes - mean_x * mean_x
        cyy = np.bincount(labels, y * y, k) / self.sizes - mean_y * mean_y
        cxy = np.bincount(labels, x * y, k) / self.sizes - mean_x * mean_y
        angle = 0.5 * np.arctan2(2.0 * cxy, cxx - cyy)  # of the line's direction
        normals = np.stack((-np.sin(angle), np.cos(angle)), axis=1)
        distances = np.abs(mean_x * normals[:, 0] + mean_y * normals[:, 1])
        return np.stack((mean_x, mean_y), axis=1), normals, distances

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

    def implied_tilt_roll(self, lidar_height_m: float) -> tuple[np.ndarray, np.ndarray]:
        """Tilt and roll of the scan plane that would put the floor on each line, rad.

        For pitch p and roll r the floor line is ``x sin p - y cos p sin r = h``: a line
        at ``h / sin(tilt)`` whose normal leans from the x axis by about ``r / tilt``.
        Lines nearer than ``h`` get a tilt of pi/2.
        """
        ratio = np.minimum(lidar_height_m / np.maximum(self.distances, 1e-9), 1.0)
        tilt = np.arcsin(ratio)
        roll = np.arcsin(np.minimum(np.sin(tilt) * np.abs(self.normals[:, 1]), 1.0))
        return tilt, roll


def segment_scan(points: np.ndarray, beams: np.ndarray, params: ImprovedParams) -> Segments:
    """Cut the valid points of a scan into segments (their lines are fitted on demand).

    Args:
        points: valid points in beam order, sensor frame, m, ``(m, 2)``.
        beams: their beam indices, ascending.
        params: ``local_fit_beams``, ``line_angle_deg`` and ``break_distance_m`` are used.
    """
    m = len(points)
    if m == 0:
        empty = np.zeros(0, dtype=np.intp)
        return Segments(beams, points, empty, np.zeros(0), np.zeros(0, bool), empty)
    step = points[1:] - points[:-1]
    gap = np.hypot(step[:, 0], step[:, 1])
    jumps = gap > params.break_distance_m + 0.02 * np.hypot(points[1:, 0], points[1:, 1])
    runs = np.zeros(m, dtype=np.intp)
    np.cumsum(jumps, out=runs[1:])
    directions = local_directions(points, params.local_fit_beams, runs)
    across = np.abs(np.sin(directions)) > math.cos(math.radians(params.line_angle_deg))
    cuts = (jumps | (across[1:] != across[:-1])).nonzero()[0] + 1
    labels = np.zeros(m, dtype=np.intp)
    labels[cuts] = 1
    labels = labels.cumsum()
    starts = np.concatenate(([0], cuts))
    return Segments(
        beams=beams,
        points=points,
        labels=labels,
        directions=directions,
        across=across[starts],
        sizes=np.concatenate((cuts, [m])) - starts,
    )
