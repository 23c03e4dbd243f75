"""Synthetic scans ray-cast against line segments: for tests, benchmarks and demos.

Everything is in the sensor frame (x forward, y left). A pitch-variation line is a
segment across the direction of travel: a scan plane tilted by ``phi`` about y at height
``h`` meets the floor along ``x = h / tan(phi)`` ahead (nose down) or behind (nose up).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from pvfilter.scan import Scan

BEAMS_PER_TURN = 720  # the paper's LiDAR: 2 beams per degree
BLOCKED_SECTOR = (-math.radians(150.0), -math.radians(30.0))  # rad, the robot's leg


def ray_cast(segments: np.ndarray, angles: np.ndarray) -> np.ndarray:
    """Range from the origin along each beam to the nearest segment.

    Args:
        segments: endpoints ``((x0, y0), (x1, y1))`` per segment, m, shape ``(s, 2, 2)``.
        angles: beam angles, rad, shape ``(n,)``.

    Returns:
        Range per beam, m; ``+inf`` where the beam hits no segment.
    """
    segments = np.asarray(segments, dtype=np.float64).reshape(-1, 2, 2)
    start, along = segments[:, 0], segments[:, 1] - segments[:, 0]  # (s, 2)
    cos, sin = np.cos(angles)[:, None], np.sin(angles)[:, None]  # (n, 1)
    # the beam t * (cos, sin) meets start + u * along where both cross products agree
    denominator = cos * along[:, 1] - sin * along[:, 0]  # (n, s)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (start[:, 0] * along[:, 1] - start[:, 1] * along[:, 0]) / denominator
        u = (start[:, 0] * sin - start[:, 1] * cos) / denominator
        hit = (t > 0.0) & (u >= 0.0) & (u <= 1.0)
    return np.where(hit, t, np.inf).min(axis=1, initial=np.inf)


def room_segments(front: float, back: float, left: float, right: float) -> np.ndarray:
    """The four walls of a rectangular room around the sensor, distances in m."""
    corners = np.array([[front, left], [-back, left], [-back, -right], [front, -right]])
    return np.stack((corners, np.roll(corners, -1, axis=0)), axis=1)


def cross_line(x: float, half_width: float) -> np.ndarray:
    """A segment across the direction of travel at ``x`` m, ``half_width`` m each side."""
    return np.array([[[x, -half_width], [x, half_width]]])


def segment_scan(
    segments: np.ndarray,
    *,
    stamp: float = 0.0,
    beams: int = BEAMS_PER_TURN,
    noise_m: float = 0.0,
    rng: np.random.Generator | None = None,
    blocked: tuple[float, float] | None = None,
) -> Scan:
    """A full-turn scan (beam 0 at -pi) of the given segments.

    Args:
        segments: the geometry, sensor frame, m, shape ``(s, 2, 2)``.
        stamp: scan time, s.
        beams: beams per turn.
        noise_m: standard deviation of Gaussian range noise, m (needs ``rng``).
        rng: random generator for the noise.
        blocked: (start, end) angles, rad, of a sector whose beams are NaN.
    """
    increment = 2.0 * math.pi / beams
    angles = -math.pi + increment * np.arange(beams)
    ranges = ray_cast(segments, angles)
    if noise_m > 0.0:
        ranges = ranges + rng.normal(0.0, noise_m, beams)
    if blocked is not None:
        ranges[(angles >= blocked[0]) & (angles <= blocked[1])] = np.nan
    ranges[ranges > 12.0] = np.inf  # REP-117: no return within range_max
    return Scan(
        ranges=ranges,
        angle_min=-math.pi,
        angle_increment=increment,
        range_min=0.05,
        range_max=12.0,
        stamp=stamp,
        scan_time=0.1,
        time_increment=0.1 / beams,
    )


@dataclasses.dataclass(frozen=True)
class RoomSequence:
    """Scans of a sensor moving back and forth in a room, with floor lines now and then.

    Attributes:
        scans: the scans, 10 Hz.
        truth: bool per beam per scan: True where the beam hit a floor line.
    """

    scans: list[Scan]
    truth: list[np.ndarray]


def room_sequence(count: int, seed: int = 0, event_every: int = 20) -> RoomSequence:
    """A 720-beam 10 Hz sequence in an 8.5 m x 4 m room with 1 cm range noise.

    The sensor oscillates along x (up to 0.5 m). In the middle of every ``event_every``
    scans a pitch event puts a floor line 1.0, 1.2 and 1.4 m ahead (or behind, every other
    event) in three consecutive scans. The 120 degree sector on the right is blocked.

    Args:
        count: number of scans.
        seed: seed of the noise generator.
        event_every: scans between the starts of two pitch events.
    """
    rng = np.random.default_rng(seed)
    scans, truth = [], []
    for k in range(count):
        offset = 0.5 * math.sin(2.0 * math.pi * k / 100.0)  # m, along x
        walls = room_segments(4.5 - offset, 4.0 + offset, 2.0, 2.0)
        phase, event = k % event_every - event_every // 2, k // event_every
        floor = np.zeros((0, 2, 2))
        if 0 <= phase < 3:
            side = 1.0 if event % 2 == 0 else -1.0
            floor = cross_line(side * (1.0 + 0.2 * phase), 1.5)
        scan = segment_scan(
            np.concatenate((walls, floor)),
            stamp=0.1 * k,
            noise_m=0.01,
            rng=rng,
            blocked=BLOCKED_SECTOR,
        )
        floor_ranges = ray_cast(floor, scan.angles())
        scans.append(scan)
        truth.append(scan.valid_mask() & (floor_ranges < ray_cast(walls, scan.angles())))
    return RoomSequence(scans, truth)
