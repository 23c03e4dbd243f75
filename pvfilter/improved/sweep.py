"""A rotating LiDAR's timing and a tilted plane's stretch, undone before scans are compared.

A rotating LiDAR measures beam ``i`` at ``stamp + i * time_increment``: while the sensor
turns and drives, the beams of one scan are seen from different poses (a turn of 1 rad/s
puts the two ends of a 10 Hz scan 0.1 rad apart). :func:`deskew` moves a scan's points to
the frame of the sensor at mid-scan, :func:`skew` back to where a scan's beams see them,
and :func:`move_scan` carries one scan's points into the next scan's beams in one pass.

A plane pitched by ``p`` meets a wall ``d`` ahead or behind at ``d / cos p`` along its x
axis: :func:`unstretch` scales x by ``cos p`` so that vertical structure is where a level
plane sees it.
"""

from __future__ import annotations

import math

import numpy as np

from pvfilter.improved.beams import BeamLayout
from pvfilter.improved.motion import Motion

SKEW_REACH_M = 10.0  # m: a far return, for how far a turn during a scan moves it
NEGLIGIBLE_SKEW_M = 0.002  # m: less motion than this in half a scan is not deskewed


def deskew(
    points: np.ndarray, layout: BeamLayout, time_increment: float, velocity: Motion
) -> np.ndarray:
    """Points of a rotating scan moved to the frame of the sensor at mid-scan, m.

    Beam ``i`` is measured ``(i - (n - 1) / 2) * time_increment`` after mid-scan; with the
    sensor moving at ``velocity`` (the motion over one second), a point seen then is
    moved back into the mid-scan frame. All beams at one instant (``time_increment = 0``)
    or a sensor that hardly moves during a scan leave the points as they are.
    """
    if _unskewed(layout, time_increment, velocity):
        return points
    return _turn_and_shift(points, layout.mid_scan_times(time_increment), velocity, -1.0)


def skew(
    points: np.ndarray, layout: BeamLayout, time_increment: float, velocity: Motion
) -> np.ndarray:
    """Mid-scan points moved to where a rotating scan moving at ``velocity`` sees them, m.

    The inverse of :func:`deskew`: a point is measured when the beam at its bearing is,
    and by then the sensor has moved on (the bearing's own shift is second order).
    """
    if _unskewed(layout, time_increment, velocity):
        return points
    bearing = np.arctan2(points[:, 1], points[:, 0])
    bearing -= layout.angle_min
    if layout.ring:
        bearing %= 2.0 * np.pi
    beam = np.clip(bearing / layout.increment, 0.0, layout.count - 1.0, out=bearing)
    tau = (beam - 0.5 * (layout.count - 1)) * time_increment  # s
    return _turn_and_shift(points, tau, velocity, 1.0)


def _unskewed(layout: BeamLayout, time_increment: float, velocity: Motion) -> bool:
    """The sensor moves less than ``NEGLIGIBLE_SKEW_M`` during half a scan (at
    ``SKEW_REACH_M``), or all beams are measured at one instant."""
    half_scan = 0.5 * layout.count * abs(time_increment)  # s
    reach = abs(velocity.theta_rad) * SKEW_REACH_M + velocity.translation_m
    return half_scan * reach < NEGLIGIBLE_SKEW_M


def _turn_and_shift(
    points: np.ndarray, tau: np.ndarray, velocity: Motion, sign: float
) -> np.ndarray:
    """Each point turned by ``sign * theta * tau`` and shifted by ``sign * t * tau``: shift
    then turn for ``sign = -1`` (deskew), turn then shift for ``+1`` (skew).

    The turn is at most a few degrees (a turn rate times half a scan): second-order
    cosine and first-order sine err by under 1e-4 of the range there, for a third of
    the cost of the trigonometry.
    """
    angle = (sign * velocity.theta_rad) * tau
    cosine = 1.0 - 0.5 * angle * angle
    x, y = points[:, 0], points[:, 1]
    if sign < 0.0:
        x = x - velocity.tx_m * tau
        y = y - velocity.ty_m * tau
    moved = np.empty_like(points)
    np.subtract(cosine * x, angle * y, out=moved[:, 0])
    np.add(angle * x, cosine * y, out=moved[:, 1])
    if sign > 0.0:
        moved[:, 0] += velocity.tx_m * tau
        moved[:, 1] += velocity.ty_m * tau
    return moved


def move_scan(
    points: np.ndarray,
    beams: np.ndarray,
    layout: BeamLayout,
    motion: Motion,
    before: tuple[float, Motion],
    after: tuple[float, Motion],
) -> np.ndarray:
    """The points of one rotating scan where the next scan's beams see them, m.

    :func:`deskew` with the earlier scan's timing, ``motion`` between the mid-scan frames,
    then :func:`skew` with the later scan's, in one pass: the three turns add up, so each
    point turns once, by ``theta + w_after tau_after - w_before tau_before``. The turn of
    the translation during the later scan's skew is left out (under 1 cm at 1 m/s and
    2 rad/s).

    Args:
        points: the earlier scan's points, its sensor frame, m, ``(k, 2)``.
        beams: the beam each of them was measured on.
        layout: the beams of both scans.
        motion: the motion between the two mid-scan frames.
        before: the earlier scan's time increment (s) and velocity (motion per second).
        after: the later scan's.
    """
    moved = np.empty_like(points)
    moved[:, 0], moved[:, 1] = move_xy(
        points[:, 0], points[:, 1], beams, layout, motion, before, after
    )
    return moved


def move_xy(
    x: np.ndarray,
    y: np.ndarray,
    beams: np.ndarray,
    layout: BeamLayout,
    motion: Motion,
    before: tuple[float, Motion],
    after: tuple[float, Motion],
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`move_scan` of the points ``(x, y)``, m: the moved x and y, each contiguous
    (the level view takes bearings and ranges of them, which cost less on contiguous
    arrays than on the columns of one).

    The same operations as written out in :func:`move_scan`'s formula, in place where a
    temporary would be thrown away (``a + b`` and ``b + a`` are the same float).
    """
    (increment_before, velocity_before), (increment_after, velocity_after) = before, after
    every = beams is layout.every_beam()  # (the level view moves every beam)
    if every:
        tau = layout.mid_scan_times(increment_before)  # s
    else:
        tau = layout.mid_scan_offsets().take(beams)
        tau *= increment_before  # s
    # the point lands about theta / increment beams away from where it was seen (on a ring,
    # past the seam it is seen a scan period earlier or later)
    turn_beams = motion.theta_rad / layout.increment
    landing = (layout.beam_numbers() if every else beams) + turn_beams
    if layout.ring:
        _wrap_once(landing, turn_beams, layout.count, every)
    else:
        np.clip(landing, 0.0, layout.count - 1.0, out=landing)
    landing -= 0.5 * (layout.count - 1)
    tau_after = np.multiply(landing, increment_after, out=landing)  # s
    # each point turns by theta plus a few degrees at most (the turn rates times half a
    # scan): second order in that small part, as in _turn_and_shift
    small = velocity_after.theta_rad * tau_after
    small -= velocity_before.theta_rad * tau
    x = x - velocity_before.tx_m * tau
    y = y - velocity_before.ty_m * tau
    c, s = math.cos(motion.theta_rad), math.sin(motion.theta_rad)
    near_one = 0.5 * small  # 1 - small^2 / 2
    near_one *= small
    np.subtract(1.0, near_one, out=near_one)
    cosine = c * near_one
    cosine -= s * small
    sine = np.multiply(s, near_one, out=near_one)
    sine += c * small
    moved_x = cosine * x
    moved_x -= sine * y
    shift = velocity_after.tx_m * tau_after
    shift += motion.tx_m
    moved_x += shift
    moved_y = np.multiply(sine, x, out=x)
    moved_y += cosine * y
    shift = np.multiply(velocity_after.ty_m, tau_after, out=shift)
    shift += motion.ty_m
    moved_y += shift
    return moved_x, moved_y


def _wrap_once(landing: np.ndarray, turn_beams: float, count: int, ascending: bool = False) -> None:
    """``landing %= count`` in place, for beams ``0 .. count - 1`` turned by ``turn_beams``.

    A turn of less than half a scan moves a beam at most once past the seam, on the side
    the turn goes: one conditional add or subtract then gives the float remainder's very
    values (``fmod`` is exact, and a negative value gains ``count`` just as the remainder
    adds it), at a third of its cost. Larger turns take the remainder itself.
    ``ascending``: ``landing`` ascends (every beam, in order), so the beams past the seam
    are a run at one end, found by a binary search and changed as a slice (the same
    add or subtract, without a mask over every beam).
    """
    if not abs(turn_beams) < 0.5 * count:
        np.remainder(landing, count, out=landing)
    elif turn_beams >= 0.0:
        if ascending:
            landing[landing.searchsorted(count) :] -= count  # the first at or past count on
        else:
            np.subtract(landing, count, out=landing, where=landing >= count)
    elif ascending:
        landing[: landing.searchsorted(0.0)] += count  # those below 0
    else:
        np.add(landing, count, out=landing, where=landing < 0.0)


def unstretch(points: np.ndarray, tilt_rad: float) -> np.ndarray:
    """Points of a plane tilted by ``tilt_rad`` as a level plane sees vertical structure.

    A plane pitched by ``p`` meets a wall ``d`` ahead (or behind) at ``d / cos p`` along its
    x axis: walls ahead and behind look farther, and a scan match reads a drive that did
    not happen. Scaling x by ``cos p`` undoes it for vertical structure (roll's share,
    along y, is second order).
    """
    if tilt_rad == 0.0 or math.isnan(tilt_rad):
        return points
    level = points.copy()
    level[:, 0] *= math.cos(tilt_rad)
    return level
