"""SLAM on recorded logs with and without a filter: what a filter's removals cost the map.

Real logs of robots that drive level hold no pitch-variation point, so a filter can only
take real structure out of them (:mod:`pvfilter.logs` counts what it removes). This module
asks what that costs a SLAM front end: each log is run through a SLAM system with no
filter and with each filter, and every run is scored

- against the log's reference poses (``ref_poses``, a SLAM-corrected trajectory) where it
  has them, else against its wheel odometry (``odom_poses``: drifts, so only a rough
  reference), else not at all: the ATE after a rotation and translation (``se2``);
- against the run without a filter: the RMSE between the two trajectories after the same
  alignment (``shift_m``). A filter that removes nothing leaves it at 0.

A run is a tracking failure as :func:`scaneval.slam.score_trajectory` says: the system
lost track, a pose is not finite, or it strays more than ``FAILURE_DISTANCE_M`` from the
reference poses (not from odometry, which drifts by itself).
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path

import numpy as np

from pvfilter.contract import ScanFilter
from pvfilter.io import read_arrays, scans_from_arrays
from pvfilter.scan import Scan
from scaneval.slam.hector import HectorParams, HectorSlam
from scaneval.slam.kiss import KissIcp2D
from scaneval.slam.scoring import FAILURE_DISTANCE_M, score_trajectory
from scaneval.trajectory import ate

REFERENCES = ("ref_poses", "odom_poses")  # what a log's trajectory is scored against, in order
NO_FILTER = "none"


@dataclasses.dataclass(frozen=True)
class LogSlamRun:
    """One SLAM system over one log, with one filter (or none).

    Attributes:
        log: the log's file name without extension.
        system: ``hector`` or ``kiss_icp``.
        filter: the filter's name; ``none`` for the run without a filter.
        scans: scans in the log.
        removed_share: share of the valid beams the filter removed.
        reference: what the trajectory is scored against: ``ref_poses``, ``odom_poses``,
            or "" (nothing).
        ate_m: ATE RMSE against the reference after ``se2`` alignment, m (NaN: none).
        failed: a tracking failure (see the module docstring).
        failure: why, in words ("" when it did not fail).
        shift_m: RMSE between this trajectory and the run without a filter, after ``se2``
            alignment, m (0 for that run itself).
    """

    log: str
    system: str
    filter: str
    scans: int
    removed_share: float
    reference: str
    ate_m: float
    failed: bool
    failure: str
    shift_m: float


def make_system(system: str, scan: Scan) -> HectorSlam | KissIcp2D:
    """A fresh SLAM system sized for the log's scanner.

    Raises:
        ValueError: an unknown system name.
        ImportError: ``kiss_icp`` without the KISS-ICP package.
    """
    if system == "hector":
        reach = min(float(scan.range_max), 30.0)
        return HectorSlam(HectorParams(range_min_m=float(scan.range_min), range_max_m=reach))
    if system == "kiss_icp":
        return KissIcp2D(max_range_m=float(scan.range_max), min_range_m=float(scan.range_min))
    raise ValueError(f"SLAM system: expected hector or kiss_icp, got {system!r}")


def trajectory(system: str, scans: Sequence[Scan], removed: Sequence[np.ndarray]) -> tuple:
    """The system's poses over the scans, without the ``removed`` beams; and the scan at
    which it reported losing track (None if it did not) and an error message ("")."""
    slam = make_system(system, scans[0])
    poses = np.full((len(scans), 3), np.nan)
    try:
        for k, (scan, mask) in enumerate(zip(scans, removed, strict=True)):
            update = slam.process_scan(scan, mask)
            poses[k] = update.pose if system == "hector" else update
    except (ValueError, FloatingPointError, np.linalg.LinAlgError) as error:
        return poses, getattr(slam, "lost_at_scan", None), str(error)
    return poses, slam.lost_at_scan, ""


def removed_masks(scan_filter: ScanFilter | None, scans: Sequence[Scan]) -> list[np.ndarray]:
    """Per scan, the beams the filter removes (none without a filter)."""
    if scan_filter is None:
        return [np.zeros(len(scan), dtype=bool) for scan in scans]
    with warnings.catch_warnings():  # some logs' stamps go back: the filters say so, once
        warnings.simplefilter("ignore")
        return [np.asarray(scan_filter.process(scan).removed, dtype=bool) for scan in scans]


def slam_on_log(
    path: str | Path,
    filters: Mapping[str, Callable[[], ScanFilter]],
    systems: Sequence[str] = ("hector",),
) -> list[LogSlamRun]:
    """Run every system over a scan file with no filter and with each of ``filters``.

    Args:
        path: the scan file (.npz, the layout of :mod:`pvfilter.io`).
        filters: filter name -> a function that builds a fresh one.
        systems: SLAM systems to run (``hector``, ``kiss_icp``).

    Returns:
        One run per system and filter, the run without a filter first; empty for a file
        without scans (relations only).
    """
    path = Path(path)
    arrays = read_arrays(path)
    if "ranges" not in arrays:
        return []
    scans = scans_from_arrays(arrays, source=str(path))
    reference_key = next((key for key in REFERENCES if key in arrays), "")
    reference = np.asarray(arrays[reference_key], float) if reference_key else None
    masks = {NO_FILTER: removed_masks(None, scans)}
    masks.update({name: removed_masks(build(), scans) for name, build in filters.items()})
    valid = sum(int(np.count_nonzero(scan.valid_mask())) for scan in scans)
    runs = []
    for system in systems:
        baseline = None
        for name, removed in masks.items():
            poses, lost_at, error = trajectory(system, scans, removed)
            baseline = poses if baseline is None else baseline
            lost = sum(
                int(np.count_nonzero(m & s.valid_mask()))
                for m, s in zip(removed, scans, strict=True)
            )
            ate_m, failed, failure = math.nan, bool(error or lost_at is not None), error
            if reference is not None:
                known = np.isfinite(reference).all(axis=1)  # a reference may skip scans
                # odometry drifts: straying from it is no tracking failure
                far = FAILURE_DISTANCE_M if reference_key == "ref_poses" else math.inf
                score = score_trajectory(poses[known], reference[known], lost_at_scan=lost_at,
                                         error=error, failure_distance_m=far)  # fmt: skip
                ate_m, failed, failure = score.rmse_m, score.failed, score.failure
            elif lost_at is not None:
                failure = failure or f"lost track at scan {lost_at} (reported by the system)"
            runs.append(
                LogSlamRun(path.stem, system, name, len(scans), lost / valid if valid else 0.0,
                           reference_key, ate_m, failed, failure, _shift(poses, baseline))
            )  # fmt: skip
    return runs


def _shift(poses: np.ndarray, baseline: np.ndarray) -> float:
    """RMSE between two trajectories of the same scans, se2-aligned (NaN if either has
    fewer than two finite poses in common)."""
    both = np.isfinite(poses).all(axis=1) & np.isfinite(baseline).all(axis=1)
    if both.sum() < 2:
        return math.nan
    return float(ate(poses[both], baseline[both], align="se2").rmse)


def markdown(runs: Sequence[LogSlamRun]) -> str:
    """The runs as a Markdown table, one row per log, system and filter."""
    lines = [
        "| log | system | filter | removed | scored against | ATE (m) | shift from no filter (m) "
        "| tracking |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in runs:
        ate_text = "–" if math.isnan(r.ate_m) else f"{r.ate_m:.3f}"
        shift = "–" if math.isnan(r.shift_m) else f"{r.shift_m:.3f}"
        tracking = f"failed: {r.failure}" if r.failed else "ok"
        lines.append(
            f"| {r.log} | {r.system} | {r.filter} | {100 * r.removed_share:.3f} % | "
            f"{r.reference or 'nothing'} | {ate_text} | {shift} | {tracking} |"
        )
    return "\n".join(lines) + "\n"
