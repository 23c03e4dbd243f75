"""The SLAM systems of the experiment, run over a recorded stream of scans.

``hector``: our Hector-style SLAM (:class:`scaneval.slam.HectorSlam`, default
parameters). ``kiss_icp``: KISS-ICP on the scans as 3D points at z = 0
(:class:`scaneval.slam.KissIcp2D`), when the ``kiss-icp`` package is installed.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Sequence
from typing import Any

import numpy as np

from twsb_sim.frame import Frame

SYSTEMS: tuple[str, ...] = ("hector", "kiss_icp")
SYSTEM_TITLES = {"hector": "Hector-style SLAM (ours)", "kiss_icp": "KISS-ICP"}


@dataclasses.dataclass(frozen=True, eq=False)
class SystemRun:
    """What one SLAM system made of one scan stream.

    Attributes:
        poses: ``(n, 3)`` sensor poses ``(x, y, theta)`` in the system's map frame (the
            first scan's sensor frame); rows after a crash are NaN.
        lost_at_scan: the scan at which the system reported losing track, or None.
        error: the exception that ended the run, "" when none.
        wall_s: wall time of the loop over the scans, s.
        slam: the system's object after the run (its maps), or None after a crash.
    """

    poses: np.ndarray
    lost_at_scan: int | None
    error: str
    wall_s: float
    slam: Any


def available_systems() -> tuple[str, ...]:
    """The systems that can run here (KISS-ICP is an optional extra)."""
    try:
        import kiss_icp  # noqa: F401
    except ImportError:
        return ("hector",)
    return SYSTEMS


def make_system(system: str, range_max_m: float) -> Any:
    """A fresh system: ``hector`` or ``kiss_icp``.

    Args:
        system: its name.
        range_max_m: the LiDAR's maximum range, m (KISS-ICP sizes its voxels from it).
    """
    from scaneval.slam import HectorSlam, KissIcp2D

    if system == "hector":
        return HectorSlam()
    if system == "kiss_icp":
        return KissIcp2D(max_range_m=range_max_m)
    raise ValueError(f"system: expected one of {', '.join(SYSTEMS)}, got {system!r}")


def run_system(system: str, frames: Sequence[Frame], removed: Sequence[np.ndarray]) -> SystemRun:
    """Run ``system`` over the frames' scans minus the ``removed`` beams.

    An exception inside the system ends the run as a tracking failure (its message is
    kept), never the experiment.
    """
    poses = np.full((len(frames), 3), np.nan)
    started = time.perf_counter()
    slam, error = None, ""
    try:
        slam = make_system(system, frames[0].scan.range_max if frames else 12.0)
        for k, (frame, mask) in enumerate(zip(frames, removed, strict=True)):
            slam.process_scan(frame.scan, mask)
            poses[k] = slam.pose  # both systems keep their latest pose here
    except Exception as exception:  # a crash of the system under test is a result
        error = f"{type(exception).__name__}: {exception}"
    wall_s = time.perf_counter() - started
    lost_at = getattr(slam, "lost_at_scan", None) if slam is not None else None
    return SystemRun(poses, lost_at, error, wall_s, slam)
