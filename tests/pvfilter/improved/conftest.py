"""Scans of a room from a moving, pitching sensor, ray-cast by pvfilter.synthetic."""

from __future__ import annotations

import math

import numpy as np

from pvfilter.improved import ImprovedParams
from pvfilter.improved import segment_scan as segment_points
from pvfilter.improved.scoring import SegmentScores, score_segments
from pvfilter.improved.segmentation import Segments
from pvfilter.scan import Scan
from pvfilter.synthetic import (
    BEAMS_PER_TURN,
    BLOCKED_SECTOR,
    ray_cast,
    room_segments,
    segment_scan,
)

HEIGHT_M = 0.25  # the scan plane's height above the floor, m
ROOM = room_segments(4.0, 4.0, 2.5, 2.5)  # world frame, m: 8 m x 5 m around the origin
PARAMS = ImprovedParams(lidar_height_m=HEIGHT_M, axle_height_m=HEIGHT_M)
INCREMENT = math.radians(0.5)  # rad: between the points of the lists that scored() takes


def line(x0: float, y0: float, x1: float, y1: float, count: int = 40) -> np.ndarray:
    """``count`` points from (x0, y0) to (x1, y1), sensor frame, m."""
    return np.column_stack((np.linspace(x0, x1, count), np.linspace(y0, y1, count)))


def scored(
    *parts: np.ndarray,
    new: np.ndarray | None = None,
    params: ImprovedParams = PARAMS,
    attitude=None,
    static=None,
    through: np.ndarray | None = None,
) -> tuple[Segments, SegmentScores]:
    """The segments of ``parts`` (point lists in beam order) and their scores; every
    point new unless ``new`` says otherwise."""
    points = np.concatenate(parts)
    segments = segment_points(points, np.arange(len(points)), INCREMENT, params)
    new = np.ones(len(points), bool) if new is None else new
    return segments, score_segments(segments, new, 0.0, attitude, params, static, through)


def to_sensor(segments: np.ndarray, pose: tuple[float, float, float]) -> np.ndarray:
    """World segments in the frame of a sensor at ``pose`` (x m, y m, yaw rad)."""
    x, y, yaw = pose
    c, s = math.cos(yaw), math.sin(yaw)
    shifted = segments - np.array([x, y])
    return shifted @ np.array([[c, -s], [s, c]])


def floor_line(pitch_rad: float, half_width: float = 10.0) -> np.ndarray:
    """Where a plane pitched by ``pitch_rad`` (nose down > 0) meets the floor: a segment
    across the sensor's x axis at ``h / sin(pitch)``, ahead or behind."""
    x = HEIGHT_M / math.sin(pitch_rad)
    return np.array([[[x, -half_width], [x, half_width]]])


def room_scan(
    pose=(0.0, 0.0, 0.0),
    pitch_rad: float = 0.0,
    stamp: float = 0.0,
    noise_m: float = 0.01,
    seed: int = 0,
    extra: np.ndarray | None = None,
    beams: int = BEAMS_PER_TURN,
):
    """A scan of the room from ``pose`` (``beams`` per turn); with a pitch, the floor line
    too.

    Returns:
        The scan, and per beam whether it hit the floor line.
    """
    structure = to_sensor(ROOM, pose)
    if extra is not None:
        structure = np.concatenate((structure, to_sensor(extra, pose)))
    floor = np.zeros((0, 2, 2)) if abs(pitch_rad) < 1e-6 else floor_line(pitch_rad)
    rng = np.random.default_rng(seed)
    scan = segment_scan(
        np.concatenate((structure, floor)),
        stamp=stamp,
        noise_m=noise_m,
        rng=rng,
        blocked=BLOCKED_SECTOR,
        beams=beams,
    )
    angles = scan.angles()
    on_floor = np.isfinite(scan.ranges) & (ray_cast(floor, angles) < ray_cast(structure, angles))
    return scan, on_floor


def pitch_event(start: int, length: int, peak_deg: float):
    """Pitch per frame, rad: 0, then a smooth rise to ``peak_deg`` and back over ``length``
    frames from frame ``start``."""

    def pitch(k: int) -> float:
        phase = (k - start) / max(length - 1, 1)
        if not 0.0 <= phase <= 1.0:
            return 0.0
        return math.radians(peak_deg) * math.sin(math.pi * phase)

    return pitch


def tilted_scan(
    pose=(0.0, 0.0, 0.0),
    pitch_rad: float = 0.0,
    roll_rad: float = 0.0,
    height_m: float = HEIGHT_M,
    ceiling_m: float | None = None,
    walls: np.ndarray = ROOM,
    stamp: float = 0.0,
    beams: int = 720,
    range_max_m: float = 12.0,
):
    """A scan cast in 3D: the plane ``height_m`` above the floor, pitched (nose down > 0)
    and rolled (left side up > 0), in a room of vertical walls with a floor at z = 0 and,
    if given, a ceiling at ``ceiling_m``, by a scanner reaching ``range_max_m``. No noise;
    the blocked sector is -inf.

    Returns:
        The scan, and per beam what it hit: 0 nothing, 1 a wall, 2 the floor, 3 the ceiling.
    """
    increment = 2.0 * math.pi / beams
    angles = -math.pi + increment * np.arange(beams)
    cp, sp, cr, sr = (
        math.cos(pitch_rad),
        math.sin(pitch_rad),
        math.cos(roll_rad),
        math.sin(roll_rad),
    )
    # the beam (cos a, sin a, 0) of the sensor frame in the level frame: Ry(pitch) Rx(roll)
    x, y = np.cos(angles), np.sin(angles)
    dx, dy, dz = cp * x + sp * sr * y, cr * y, -sp * x + cp * sr * y
    horizontal = np.hypot(dx, dy)
    with np.errstate(divide="ignore", invalid="ignore"):
        t_wall = ray_cast(to_sensor(walls, pose), np.arctan2(dy, dx)) / horizontal
        t_floor = np.where(dz < 0.0, -height_m / dz, np.inf)
        t_ceiling = np.full(beams, np.inf)
        if ceiling_m is not None:
            t_ceiling = np.where(dz > 0.0, (ceiling_m - height_m) / dz, np.inf)
    hits = np.stack((np.full(beams, np.inf), t_wall, t_floor, t_ceiling))
    labels = np.argmin(hits, axis=0)
    ranges = hits.min(axis=0)
    ranges[ranges > range_max_m] = np.inf
    labels[~np.isfinite(ranges)] = 0
    blocked = (angles >= BLOCKED_SECTOR[0]) & (angles <= BLOCKED_SECTOR[1])
    ranges[blocked] = -np.inf
    labels[blocked] = 0
    scan = Scan(ranges=ranges, angle_min=-math.pi, angle_increment=increment, range_min=0.05,
                range_max=range_max_m, stamp=stamp, scan_time=0.1)  # fmt: skip
    return scan, labels


def prepared(scan: Scan):
    """The beams of ``scan``, its points per beam (NaN rows: invalid) and each point's local
    line direction (NaN: none), as the improved filter's scan match takes them."""
    from pvfilter.improved import BeamLayout, ImprovedParams, segment_scan

    layout = BeamLayout.of(scan)
    valid = scan.valid_mask()
    points = layout.points(np.where(valid, scan.ranges, np.nan))
    beams = np.flatnonzero(valid)
    directions = np.full(len(scan), np.nan)
    directions[beams] = segment_scan(
        points[beams], beams, layout.increment, ImprovedParams()
    ).directions
    return layout, points, directions
