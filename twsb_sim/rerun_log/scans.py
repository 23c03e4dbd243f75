"""Per-frame scan data: world hit points, the sensor view's labels, decisions and clusters.

Each ``log_<thing>`` takes a batch of consecutive frames and sends one column per
entity (``send_columns``): logging a batch costs about what logging one frame would,
which keeps a recording's cost within a few percent of the simulation's. Every frame
gets a row, empty when it has nothing to show, so nothing stale lingers in the viewer.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import rerun as rr

from twsb_sim.frame import Frame
from twsb_sim.rerun_log import paths
from twsb_sim.rerun_log.annotations import (
    CLUSTER_PALETTE,
    DETECTED_COLOR,
    KEPT_CLUSTER_COLOR,
    TRACKED_COLOR,
    beam_decisions,
)
from twsb_sim.rerun_log.timelines import Times

POINT_RADIUS_UI = -2.5
HIT_RADIUS_UI = -2.5  # negative radii are in UI points: the same size at any zoom
REMOVED_RADIUS_UI = -4.5
CLUSTER_BOX_PAD_M = 0.05
BOX_LINE_RADIUS_UI = -1.0
CENTROID_RADIUS_UI = -1.5
REMOVED_HALO_COLOR = np.array([255, 255, 255, 90], dtype=np.uint8)  # under the decision dots


def _send_points(
    rec: rr.RecordingStream,
    path: str,
    times: Times,
    points: list[np.ndarray],
    radius_ui: float,
    archetype: type = rr.Points2D,
    **fields: list[np.ndarray],
) -> None:
    """One row per frame: ``points[i]`` and the ``fields[name][i]`` of each point of frame i."""
    lengths = [len(p) for p in points]
    width = 3 if archetype is rr.Points3D else 2
    rec.send_columns(
        path,
        indexes=times,
        columns=archetype.columns(
            positions=np.concatenate(points).reshape(-1, width),
            radii=np.full(sum(lengths), radius_ui, dtype=np.float32),
            **{name: np.concatenate(values) for name, values in fields.items()},
        ).partition(lengths),
    )


def valid_points(frame: Frame) -> tuple[np.ndarray, np.ndarray]:
    """The scan's valid beam indices and their sensor-frame points (m), as the filter sees them."""
    valid = np.flatnonzero(frame.scan.valid_mask())
    return valid, frame.scan.points()[valid]


def log_lidar_hits(rec: rr.RecordingStream, times: Times, frames: Sequence[Frame]) -> None:
    """Where each beam really hit, in the world frame, class id = ground-truth label."""
    hits = [np.isfinite(frame.hit_points_world[:, 0]) for frame in frames]
    _send_points(
        rec,
        paths.LIDAR_HITS,
        times,
        [frame.hit_points_world[hit] for frame, hit in zip(frames, hits, strict=True)],
        HIT_RADIUS_UI,
        rr.Points3D,
        class_ids=[frame.labels[hit] for frame, hit in zip(frames, hits, strict=True)],
    )


def log_sensor_labels(rec: rr.RecordingStream, times: Times, frames: Sequence[Frame]) -> None:
    """The scan in the sensor frame, class id = ground-truth label of each beam."""
    valid = [valid_points(frame) for frame in frames]
    _send_points(
        rec,
        paths.SENSOR_LABELS,
        times,
        [xy for _, xy in valid],
        POINT_RADIUS_UI,
        class_ids=[frame.labels[i] for frame, (i, _) in zip(frames, valid, strict=True)],
    )


def log_filter_decisions(
    rec: rr.RecordingStream, times: Times, frames: Sequence[Frame], results: Sequence[Any]
) -> None:
    """Per valid beam, the filter's decision against ground truth; and the removed beams.

    Args:
        rec: the recording.
        times: one row per frame (see :func:`~twsb_sim.rerun_log.timelines.frame_times`).
        frames: consecutive frames.
        results: the filter's result for each frame (with a boolean ``removed`` mask).
    """
    points, decisions, removed_points = [], [], []
    for frame, result in zip(frames, results, strict=True):
        valid, xy = valid_points(frame)
        removed = np.asarray(result.removed, dtype=bool)[valid]
        points.append(xy)
        decisions.append(beam_decisions(frame.labels[valid], removed))
        removed_points.append(xy[removed])
    _send_points(rec, paths.SENSOR_DECISION, times, points, POINT_RADIUS_UI, class_ids=decisions)
    _send_points(
        rec,
        paths.SENSOR_REMOVED,
        times,
        removed_points,
        REMOVED_RADIUS_UI,
        colors=[np.tile(REMOVED_HALO_COLOR, (len(xy), 1)) for xy in removed_points],
    )


def _box_color(record: Any) -> tuple[int, int, int]:
    if record.detected:
        return DETECTED_COLOR
    return TRACKED_COLOR if record.tracked else KEPT_CLUSTER_COLOR


def _cluster_label(k: int, record: Any) -> str:
    """``#id``, and for a removed cluster its P(C_pv) and whether detected or tracked."""
    if not record.removed:
        return f"#{k}"
    p_pv = "-" if np.isnan(record.p_pv) else f"{record.p_pv:.2f}"
    return f"#{k} P={p_pv} {'detected' if record.detected else 'tracked'}"


def log_clusters(
    rec: rr.RecordingStream, times: Times, frames: Sequence[Frame], results: Sequence[Any]
) -> None:
    """Clustered points, one colour per cluster id; a box and a label per cluster.

    Boxes are red for clusters detected in this scan, orange for tracked ones, grey for
    kept ones. Labels sit at the centroids (``#id``, plus ``P(C_pv)`` and the state of
    removed clusters); box labels would be misplaced by the view's turned frame.
    """
    points, colors, bounds, box_colors, centroids, labels = [], [], [], [], [], []
    for frame, result in zip(frames, results, strict=True):
        xy_all = frame.scan.points()
        clusters = [xy_all[record.indices] for record in result.clusters]
        points.append(_concat(clusters, 2, np.float64))
        colors.append(
            _concat(
                [np.repeat(CLUSTER_PALETTE[[k % len(CLUSTER_PALETTE)]], len(xy), axis=0)
                 for k, xy in enumerate(clusters)],
                3,
                np.uint8,
            )
        )  # fmt: skip
        low = np.array([xy.min(axis=0) for xy in clusters]).reshape(-1, 2) - CLUSTER_BOX_PAD_M
        high = np.array([xy.max(axis=0) for xy in clusters]).reshape(-1, 2) + CLUSTER_BOX_PAD_M
        bounds.append((low, high))
        box_colors.append(
            np.array([_box_color(r) for r in result.clusters], np.uint8).reshape(-1, 3)
        )
        centroids.append(np.array([r.centroid for r in result.clusters]).reshape(-1, 2))
        labels.append([_cluster_label(k, r) for k, r in enumerate(result.clusters)])
    _send_points(rec, paths.SENSOR_CLUSTERS, times, points, POINT_RADIUS_UI, colors=colors)
    counts = [len(c) for c in centroids]
    all_colors = np.concatenate(box_colors)
    rec.send_columns(
        paths.SENSOR_CLUSTER_BOXES,
        indexes=times,
        columns=rr.Boxes2D.columns(
            centers=np.concatenate([(low + high) / 2 for low, high in bounds]),
            half_sizes=np.concatenate([(high - low) / 2 for low, high in bounds]),
            colors=all_colors,
            radii=np.full(len(all_colors), BOX_LINE_RADIUS_UI, dtype=np.float32),
        ).partition(counts),
    )
    _send_points(
        rec,
        paths.SENSOR_CLUSTER_IDS,
        times,
        centroids,
        CENTROID_RADIUS_UI,
        colors=box_colors,
        labels=[np.array(row, dtype=str) for row in labels],
    )


def _concat(parts: list[np.ndarray], width: int, dtype: type) -> np.ndarray:
    """Rows of all parts stacked, ``(0, width)`` when there are none."""
    return np.concatenate(parts).astype(dtype) if parts else np.empty((0, width), dtype)
