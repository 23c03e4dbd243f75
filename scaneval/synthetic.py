"""Synthetic scenes for testing and benchmarking matchers and baselines without data.

A room with clutter given as line segments in a world frame, and 720-beam scans of it
ray-cast from any sensor pose (:func:`pvfilter.synthetic.segment_scan`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from pvfilter.scan import Scan
from pvfilter.synthetic import BLOCKED_SECTOR, room_segments, segment_scan
from scaneval.geometry import invert, transform_points


def box_segments(center_xy: ArrayLike, half_x: float, half_y: float) -> np.ndarray:
    """The four sides of an axis-aligned box, m, shape ``(4, 2, 2)``."""
    cx, cy = np.asarray(center_xy, dtype=np.float64)
    return room_segments(cx + half_x, half_x - cx, cy + half_y, half_y - cy)


def cluttered_room() -> np.ndarray:
    """An 8 m x 5 m room around the origin with a box, a column and a slanted cabinet.

    Returns:
        Segments in the world frame, m, shape ``(s, 2, 2)``.
    """
    walls = room_segments(5.0, 3.0, 2.0, 3.0)
    cabinet = np.array([[[-2.5, 1.9], [-1.5, 1.2]], [[-1.5, 1.2], [-1.2, 1.6]]])
    return np.concatenate(
        (walls, box_segments((2.5, -1.5), 0.4, 0.3), box_segments((1.0, 1.2), 0.1, 0.1), cabinet)
    )


def scan_from_pose(
    segments_world: np.ndarray,
    pose_sensor_in_world: ArrayLike,
    *,
    stamp: float = 0.0,
    noise_m: float = 0.01,
    rng: np.random.Generator | None = None,
    blocked: tuple[float, float] | None = BLOCKED_SECTOR,
) -> Scan:
    """A 720-beam scan of world segments from a sensor pose.

    Args:
        segments_world: the scene, m, shape ``(s, 2, 2)``.
        pose_sensor_in_world: ``(x, y, theta)`` of the sensor, m, m, rad.
        stamp: scan time, s.
        noise_m: standard deviation of Gaussian range noise, m.
        rng: random generator for the noise (a fixed seed when omitted).
        blocked: sensor-frame sector (start, end), rad, whose beams are NaN; the robot's
            leg on the right by default, ``None`` for a full turn.
    """
    world_to_sensor = invert(pose_sensor_in_world)
    segments = transform_points(np.asarray(segments_world).reshape(-1, 2), world_to_sensor)
    return segment_scan(
        segments.reshape(-1, 2, 2),
        stamp=stamp,
        noise_m=noise_m,
        rng=rng if rng is not None else np.random.default_rng(0),
        blocked=blocked,
    )
