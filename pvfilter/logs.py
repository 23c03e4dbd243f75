"""False alarms on real logs: what a filter removes from scans that never pitched.

Real 2D LiDAR logs of robots that drive level (wheeled rovers, hand-held and flying
scanners) hold no pitch-variation point, so every beam a filter removes from them is a
false alarm. :func:`evaluate_log` runs a filter over one scan file (layout in
:mod:`pvfilter.io`) and counts them: the share of valid beams removed over the whole log,
and the worst scan. The log's wheel odometry, where it has it, can be given to the filter
as ``pose_sensor_in_odom``: the scan file's own ``pose_sensor_in_odom`` array, or its
``odom_poses`` (base in the odom frame) composed with its ``laser_offset`` (the LiDAR in
the base frame).
"""

from __future__ import annotations

import dataclasses
import time
import warnings
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from pvfilter.contract import ScanFilter
from pvfilter.io import read_arrays, scans_from_arrays

WORST_SCAN_LIMIT = 0.05  # a scan that loses more than this share of its beams is counted


@dataclasses.dataclass(frozen=True)
class LogReport:
    """One filter over one log.

    Attributes:
        log: the log's file name without extension.
        filter: the filter's name.
        scans: scans in the log.
        valid_beams: beams with a valid range, over the log.
        removed_beams: of those, removed.
        worst_scan: index of the scan that lost the largest share of its valid beams (-1:
            none lost any).
        worst_scan_share: that share.
        scans_over_limit: scans that lost more than ``WORST_SCAN_LIMIT`` of their beams.
        odometry: the filter was given the log's odometry.
        scans_per_s: the filter's rate on this log.
    """

    log: str
    filter: str
    scans: int
    valid_beams: int
    removed_beams: int
    worst_scan: int
    worst_scan_share: float
    scans_over_limit: int
    odometry: bool
    scans_per_s: float

    @property
    def removed_share(self) -> float:
        """Share of the valid beams removed over the log."""
        return self.removed_beams / self.valid_beams if self.valid_beams else 0.0


NO_VALID_BEAM = "no beam lies within [range_min, range_max]: are the ranges in metres?"
# (what the commands note for a file without a valid beam: a share of 0 % of nothing
# would read as a clean result, and ranges in millimetres read as metres lie beyond
# every range_max)


def odometry_inputs(arrays: dict[str, np.ndarray], count: int) -> list[dict] | None:
    """Per scan, ``{"pose_sensor_in_odom": (x, y, yaw)}`` from a log's odometry (None: the
    log has none).

    Raises:
        ValueError: ``"<key>: ..."`` for odometry of the wrong shape.
    """
    if "pose_sensor_in_odom" in arrays:
        poses = np.asarray(arrays["pose_sensor_in_odom"], dtype=np.float64)
    elif "odom_poses" in arrays:
        base = np.asarray(arrays["odom_poses"], dtype=np.float64)
        if base.shape != (count, 3):
            raise ValueError(f"odom_poses: must have shape ({count}, 3), got {base.shape}")
        offset = np.asarray(arrays.get("laser_offset", np.zeros(3)), dtype=np.float64)
        if offset.shape != (3,):
            raise ValueError(f"laser_offset: must be (x, y, yaw), got shape {offset.shape}")
        c, s = np.cos(base[:, 2]), np.sin(base[:, 2])
        poses = np.stack(
            (
                base[:, 0] + c * offset[0] - s * offset[1],
                base[:, 1] + s * offset[0] + c * offset[1],
                base[:, 2] + offset[2],
            ),
            axis=1,
        )
    else:
        return None
    if poses.shape != (count, 3):
        raise ValueError(f"pose_sensor_in_odom: must have shape ({count}, 3), got {poses.shape}")
    return [{"pose_sensor_in_odom": pose} for pose in poses]


def evaluate_log(
    path: str | Path, name: str, make_filter: Callable[[], ScanFilter], odometry: bool = False
) -> LogReport | None:
    """Run a fresh filter over a scan file and count what it removes.

    Args:
        path: the scan file (.npz).
        name: the filter's name, for the report.
        make_filter: builds the filter.
        odometry: give the filter the log's odometry, where it has one.

    Returns:
        The report; None when the file holds no scans (a file of relations only).

    Raises:
        ValueError: ``"<path>: ..."`` for a malformed file.
    """
    path = Path(path)
    arrays = read_arrays(path)
    if "ranges" not in arrays:
        return None
    scans = scans_from_arrays(arrays, source=str(path))
    inputs = None
    if odometry:
        try:
            inputs = odometry_inputs(arrays, len(scans))
        except ValueError as error:
            raise ValueError(f"{path}: {error}") from None
    inputs = inputs or [{}] * len(scans)
    scan_filter = make_filter()
    valid = removed = over = 0
    worst, worst_share = -1, 0.0
    start = time.perf_counter()
    with warnings.catch_warnings():  # some logs' stamps go back: the filters say so, once
        warnings.simplefilter("ignore")
        for k, (scan, extra) in enumerate(zip(scans, inputs, strict=True)):
            mask = scan.valid_mask()
            lost = int(np.count_nonzero(scan_filter.process(scan, **extra).removed & mask))
            count = int(np.count_nonzero(mask))
            valid, removed = valid + count, removed + lost
            share = lost / count if count else 0.0
            over += share > WORST_SCAN_LIMIT
            if share > worst_share:
                worst, worst_share = k, share
    seconds = time.perf_counter() - start
    rate = len(scans) / seconds if seconds > 0.0 else float("inf")
    used = odometry and inputs[0] != {} if inputs else False
    return LogReport(path.stem, name, len(scans), valid, removed, worst, worst_share, over,
                     bool(used), rate)  # fmt: skip


def markdown(reports: Sequence[LogReport]) -> str:
    """The reports as a Markdown table, one row per log and filter."""
    lines = [
        "| log | filter | scans | removed of valid beams | worst scan | scans > "
        f"{WORST_SCAN_LIMIT:.0%} | odometry | scans/s |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in reports:
        worst = f"{r.worst_scan_share:.2%} (scan {r.worst_scan})" if r.worst_scan >= 0 else "–"
        lines.append(
            f"| {r.log} | {r.filter} | {r.scans} | {r.removed_share:.3%} ({r.removed_beams} of "
            f"{r.valid_beams}) | {worst} | {r.scans_over_limit} | "
            f"{'yes' if r.odometry else 'no'} | {r.scans_per_s:.0f} |"
        )
    return "\n".join(lines) + "\n"
