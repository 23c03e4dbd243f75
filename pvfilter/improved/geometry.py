"""The geometry of a tilted scan plane: where it meets the floor and the ceiling.

A scanner at height ``h_s`` whose plane is pitched by ``p`` (positive nose down) and
rolled by ``r`` meets the floor along the line ``x sin p - y cos p sin r = h_s`` of its
own frame: a straight line across the direction of travel at ``h_s / sin p`` (ahead when
nose down, behind when nose up), whose normal leans from the x axis by ``atan(sin r /
tan p)``. It meets a ceiling at height ``H`` on the other side, at ``(H - h_s) / sin p``,
along a parallel line. ``h_s`` itself falls with the tilt as the robot tilts about its
wheel axle: ``h_s = axle + (h - axle) cos p``.

A scanner mounted ``a`` ahead of the axle (``lidar_ahead_m``) sits ``a`` along the
plane's own x axis from the plane's point over the axle, whatever the pitch: nose down
lowers it by ``a sin p``, and every line of the plane lies ``a`` nearer on the side
ahead and ``a`` farther behind. The formulas hold for distances from that point
(:func:`axle_distances`).

With a rotating LiDAR the beams of one scan are measured over its whole sweep, and the
pitch changes meanwhile: a return measured ``dt`` from a line's middle may come from a
plane up to ``pitch_rate * dt`` flatter, whose floor line lies farther out, without bound
as the plane nears level.

And a plane tilted into the floor meets it along a whole line: every beam on that side
ends at that line or nearer. A return beyond it shows the line is not the floor.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from pvfilter.improved.beams import indices
from pvfilter.improved.params import ImprovedParams
from pvfilter.improved.segmentation import Segments

HORIZON_M = 0.1  # m: how far beyond a floor line a return must be to show it is none
HORIZON_POINTS = 5  # points: so many returns beyond it are not noise
LEAN_SIGMAS = 3.0  # the lean of a fitted line may exceed the physical bound by this many
# standard deviations of its fit


def axle_distances(segments: Segments, params: ImprovedParams) -> np.ndarray:
    """Distance of each segment's line from the scan plane's point over the axle, m.

    That point lies ``lidar_ahead_m`` behind the sensor, at ``(-a, 0)`` in its frame; the
    distance of the line ``x . n = c . n`` from it is ``|c . n + a n_x|``: the sensor's
    distance plus ``a`` for a line ahead, minus ``a`` for one behind.
    """
    if params.lidar_ahead_m == 0.0:
        return segments.distances
    return np.abs(segments.offsets + params.lidar_ahead_m * segments.normals[:, 0])


def implied_tilt(distance_m: np.ndarray, params: ImprovedParams) -> np.ndarray:
    """The tilt that puts the floor at ``distance_m`` from the plane's point over the axle
    (:func:`axle_distances`), rad (pi/2 nearer).

    Solves ``d sin p = axle + (h - axle) cos p`` in closed form: with
    ``R = hypot(d, h - axle)`` and ``phi = atan2(h - axle, d)``, ``p = phi + asin(axle / R)``.
    """
    arm = params.lidar_height_m - params.axle_height_m
    reach = np.hypot(distance_m, arm)  # (at least |arm|)
    if abs(arm) < 1e-9:
        reach = np.maximum(reach, 1e-9)
    ratio = np.minimum(params.axle_height_m / reach, 1.0)
    tilt = np.arctan2(arm, distance_m) + np.arcsin(ratio)
    return np.minimum(tilt, 0.5 * np.pi)


def floor_distance(tilt_rad: np.ndarray | float, params: ImprovedParams) -> np.ndarray:
    """Distance of the floor line of a plane tilted by ``tilt_rad`` from the plane's point
    over the axle, m (from the sensor for a scanner over the axle)."""
    tilt = np.maximum(np.abs(tilt_rad), 1e-6)
    return params.scanner_height_m(tilt) / np.sin(tilt)


def floor_shift(
    tilt_rad: np.ndarray | float, change_rad: np.ndarray | float, params: ImprovedParams
) -> np.ndarray:
    """How far the floor line of a plane tilted by ``tilt_rad`` moves when the tilt changes
    by ``change_rad``, m (to first order).

    With ``d = h_s / sin p`` and ``h_s = axle + (h - axle) cos p``,
    ``|dd/dp| = (h - axle) + h_s cos p / sin^2 p``: a shallow line moves metres for a
    degree (1.7 m at 3 deg and h = 0.25 m), a steep one centimetres.
    """
    tilt = np.maximum(np.abs(tilt_rad), 1e-3)
    arm = params.lidar_height_m - params.axle_height_m
    slope = arm + params.scanner_height_m(tilt) * np.cos(tilt) / np.sin(tilt) ** 2
    return slope * np.abs(change_rad)


def ceiling_min_distance(tilt_rad: np.ndarray | float, params: ImprovedParams) -> np.ndarray:
    """Nearest a ceiling (at least ``min_ceiling_m`` high) can be at that tilt, m, from the
    plane's point over the axle."""
    tilt = np.maximum(np.abs(tilt_rad), 1e-6)
    return (params.min_ceiling_m - params.scanner_height_m(tilt)) / np.sin(tilt)


def lean_ok(
    sin_lean: np.ndarray,
    tilt: np.ndarray,
    distance: np.ndarray,
    spread_along: np.ndarray,
    spread_across: np.ndarray,
    sizes: np.ndarray,
    time_span_s: np.ndarray,
    params: ImprovedParams,
) -> np.ndarray:
    """Per line: its normal leans from the x axis no more than physics allows.

    The bound is the roll's lean, ``atan(sin(max_roll) / tan(tilt))``, plus the bend of a
    rotating scan (the pitch changing by up to ``max_pitch_rate`` over the line's
    ``time_span_s``, over its length), plus ``LEAN_SIGMAS`` standard deviations of the
    fitted normal (``sqrt(across / (n * along))`` for ``n`` points).

    Args:
        sin_lean: sine of each line's lean from the x axis (``|n_y|``).
        tilt: the tilt each line implies, rad.
        distance: each line's distance from the sensor, m.
        spread_along: variance of its points along it, m^2.
        spread_across: variance of its points across it, m^2.
        sizes: its points.
        time_span_s: time between its first and last beam, s.
        params: ``max_roll_deg`` and ``max_pitch_rate_rad_s``.
    """
    tan_tilt = np.tan(np.maximum(tilt, 1e-6))
    roll_term = math.sin(math.radians(params.max_roll_deg)) / tan_tilt  # as np.sin, np.radians
    along_m2 = np.maximum(spread_along, 1e-12)  # (no zero to divide by)
    length = np.sqrt(12.0 * along_m2)
    bend = distance / tan_tilt * params.max_pitch_rate_rad_s * time_span_s / length
    bound = np.arctan(roll_term + bend)
    sigma = np.sqrt(spread_across / (np.maximum(sizes, 1) * along_m2))
    return np.arcsin(np.minimum(sin_lean, 1.0)) <= bound + LEAN_SIGMAS * sigma


def seen_beyond(
    segments: Segments,
    scored: np.ndarray,
    tilt: np.ndarray,
    time_increment: float,
    params: ImprovedParams,
) -> np.ndarray:
    """Per scored segment: returns on its side lie beyond it, which a floor (or ceiling)
    line would have hidden.

    A plane tilted into the floor meets it along a whole line across the direction of
    travel: every beam on that side ends at that line or nearer. So at least
    ``HORIZON_POINTS`` returns farther out along x than the segment (by ``HORIZON_M`` plus
    2 % of the range, plus the lean a roll of ``max_roll_deg`` gives the line at the
    return's y) prove the segment is not where the plane meets the floor: a wall, or
    furniture, seen beside open space. With a rotating LiDAR a return measured ``dt``
    from the line's middle proves it only if it also lies beyond the floor line of the
    flattest plane the pitch can reach meanwhile (``max_pitch_rate_rad_s * dt`` less
    tilt): where a scan's sweep starts and ends straight ahead, the two halves of a floor
    line are measured a whole sweep apart, and the later half of a levelling plane lies
    metres farther out.
    """
    seen = np.zeros(len(segments), dtype=bool)
    lines = indices(scored)
    if lines.size == 0:
        return seen
    x, y = segments.points[:, 0], segments.points[:, 1]
    ranges = segments.ranges
    centroids = segments.centroids.take(lines, axis=0)  # (cheaper than indexing rows)
    line_x = centroids[:, 0]  # m
    side = np.sign(line_x)  # (c,)
    depth = np.abs(line_x)  # the line's x, m
    line_tilt = np.maximum(tilt.take(lines), 1e-3)
    lean = math.sin(math.radians(params.max_roll_deg)) / np.tan(line_tilt)
    beyond = side[:, None] * x - depth[:, None]  # (c, m)
    beyond -= HORIZON_M + 0.02 * ranges
    beyond -= np.abs(y - centroids[:, 1:2]) * lean[:, None]
    past = beyond > 0.0  # returns beyond the line itself (few)
    if np.count_nonzero(past) < HORIZON_POINTS:  # (most scans: cheaper than a 2-D nonzero)
        return seen
    line, point = np.nonzero(past)
    # time between each such return's beam and its line's middle beam, s
    middle = (
        np.bincount(segments.labels, segments.beams, len(segments))[lines] / segments.sizes[lines]
    )
    apart = np.abs(segments.beams.take(point) - middle.take(line)) * abs(time_increment)
    flattest = np.maximum(line_tilt.take(line) - params.max_pitch_rate_rad_s * apart, 1e-6)
    bend = floor_distance(flattest, params) - floor_distance(line_tilt, params).take(line)
    proof = beyond[line, point] > bend
    seen[lines] = np.bincount(line[proof], minlength=lines.size) >= HORIZON_POINTS
    return seen


TURN_TOLERANCE = math.radians(3.0)  # rad: how far a line's direction in the sensor frame
# may be from where it is expected (turned with the world, or kept with the sensor) and
# still be that line (the fitted direction's error and the roll's change over 0.3 s)


def line_lean(normal_y: ArrayLike, normal_x: ArrayLike) -> np.ndarray:
    """The direction of a line's normal from the sensor's x axis, rad, in ``[-pi/2,
    pi/2)`` (a normal and its opposite are one line): per element, as ``np.arctan2``."""
    return folded(np.arctan2(normal_y, normal_x))


def folded(angle_rad: ArrayLike) -> np.ndarray:
    """An angle between line directions, rad, folded into ``[-pi/2, pi/2)``."""
    return (angle_rad + 0.5 * math.pi) % math.pi - 0.5 * math.pi
