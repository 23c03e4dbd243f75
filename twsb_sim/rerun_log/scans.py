"""Per-frame scan data: world hit points, the sensor view's labels, decisions and clusters.

Each ``log_<thing>`` takes a :class:`~twsb_sim.rerun_log.batch.FrameBatch` and sends
one column per entity (``send_columns``): a batch of frames costs little more than one
frame would. Every frame gets a row, empty when it has nothing to show, so nothing stale
lingers in the viewer.
"""

from __future__ import annotations

import numpy as np
import rerun as rr

from twsb_sim.rerun_log import paths
from twsb_sim.rerun_log.annotations import (
    DETECTED_COLOR,
    TRACKED_COLOR,
    beam_decisions,
    packed_colors,
)
from twsb_sim.rerun_log.batch import FrameBatch

POINT_RADIUS_UI = -3.0  # negative radii are in UI points: the same size at any zoom
HIT_RADIUS_UI = -2.5
REMOVED_RADIUS_UI = -4.5
REMOVED_HALO_COLOR = (255, 255, 255, 110)
HALO_DRAW_ORDER = 30.0  # 2D draw order: halos under the scan's dots, labels on top
DOT_DRAW_ORDER = 40.0
LABEL_DRAW_ORDER = 50.0
LEVEL_VIEW_RADIUS_UI = -1.5
LEVEL_VIEW_COLOR = (80, 190, 255, 200)  # light blue: apart from the decisions
LEVEL_VIEW_DRAW_ORDER = 20.0  # under the halos and the scan's dots
CLUSTER_BOX_PAD_M = 0.05
BOX_LINE_RADIUS_UI = -1.0
CENTROID_RADIUS_UI = -1.5
_STATE_COLORS = packed_colors(np.array([DETECTED_COLOR, TRACKED_COLOR]))


def _send(
    rec: rr.RecordingStream,
    path: str,
    batch: FrameBatch,
    archetype: type,
    lengths: np.ndarray,
    **fields: np.ndarray,
) -> None:
    """One row per frame of ``batch``: frame i holds the next ``lengths[i]`` instances."""
    rec.send_columns(
        path, indexes=batch.times, columns=archetype.columns(**fields).partition(lengths)
    )


def _send_scan_points(
    rec: rr.RecordingStream, path: str, batch: FrameBatch, mask: np.ndarray, **fields: np.ndarray
) -> None:
    """The sensor-frame points of the beams in ``mask`` (``(K, n)``), one row per frame."""
    _send(rec, path, batch, rr.Points2D, mask.sum(axis=1), positions=batch.points[mask], **fields)


def log_scan_styles(rec: rr.RecordingStream) -> None:
    """Point sizes and fixed colours of the per-frame entities, once (static).

    A static component holds for every row of its entity, so the per-frame columns carry
    only what changes; a column less per entity is a good part of a batch's cost.
    """
    styles = {
        paths.LIDAR_HITS: rr.Points3D.from_fields(radii=HIT_RADIUS_UI),
        paths.SENSOR_LABELS: rr.Points2D.from_fields(
            radii=POINT_RADIUS_UI, draw_order=DOT_DRAW_ORDER
        ),
        paths.SENSOR_DECISION: rr.Points2D.from_fields(
            radii=POINT_RADIUS_UI, draw_order=DOT_DRAW_ORDER
        ),
        paths.SENSOR_REMOVED: rr.Points2D.from_fields(
            radii=REMOVED_RADIUS_UI, colors=[REMOVED_HALO_COLOR], draw_order=HALO_DRAW_ORDER
        ),
        paths.SENSOR_CLUSTERS: rr.Points2D.from_fields(
            radii=POINT_RADIUS_UI, draw_order=DOT_DRAW_ORDER
        ),
        paths.SENSOR_CLUSTER_BOXES: rr.Boxes2D.from_fields(radii=BOX_LINE_RADIUS_UI),
        paths.SENSOR_LEVEL_VIEW: rr.Points2D.from_fields(
            radii=LEVEL_VIEW_RADIUS_UI, colors=[LEVEL_VIEW_COLOR], draw_order=LEVEL_VIEW_DRAW_ORDER
        ),
        paths.SENSOR_CLUSTER_IDS: rr.Points2D.from_fields(
            radii=CENTROID_RADIUS_UI, draw_order=LABEL_DRAW_ORDER
        ),
    }
    for path, style in styles.items():
        rec.log(path, style, static=True)


def log_lidar_hits(rec: rr.RecordingStream, batch: FrameBatch) -> None:
    """Where each beam really hit, in the world frame, class id = ground-truth label."""
    hits = np.stack([frame.hit_points_world for frame in batch.frames], dtype=np.float32)
    hit = np.isfinite(hits[:, :, 0])
    _send(
        rec,
        paths.LIDAR_HITS,
        batch,
        rr.Points3D,
        hit.sum(axis=1),
        positions=hits[hit],
        class_ids=batch.labels[hit],
    )


def log_sensor_labels(rec: rr.RecordingStream, batch: FrameBatch) -> None:
    """The scan in the sensor frame, class id = ground-truth label of each beam."""
    valid = batch.valid
    _send_scan_points(rec, paths.SENSOR_LABELS, batch, valid, class_ids=batch.labels[valid])


def log_filter_decisions(rec: rr.RecordingStream, batch: FrameBatch) -> None:
    """Per valid beam, the filter's decision against ground truth; and the removed beams.

    Args:
        rec: the recording.
        batch: frames with a filter result (see :meth:`FrameBatch.with_results`).
    """
    valid = batch.valid
    removed = batch.stack("removed", bool)
    decisions = beam_decisions(batch.labels[valid], removed[valid])
    _send_scan_points(rec, paths.SENSOR_DECISION, batch, valid, class_ids=decisions)
    _send_scan_points(rec, paths.SENSOR_REMOVED, batch, valid & removed)


def log_level_view(rec: rr.RecordingStream, batch: FrameBatch) -> None:
    """Where the improved filter's level view lies along each beam (``level_view_m``): the
    structure the remembered level scans put there. A return in front of it by more than
    the free-space margin is new; beams where the view is unknown, or saw nothing within
    range, show nothing.

    Args:
        rec: the recording.
        batch: frames whose result has a level view (``batch.with_results("level_view_m")``).
    """
    view = batch.stack("level_view_m", np.float64)  # (K, n), m
    shown = np.isfinite(view)
    xy = batch.directions() * view[:, :, None]
    _send(rec, paths.SENSOR_LEVEL_VIEW, batch, rr.Points2D, shown.sum(axis=1),
          positions=xy[shown].astype(np.float32))  # fmt: skip


def _removed_cluster_labels(ids: np.ndarray, p_pv: np.ndarray, detected: np.ndarray) -> list[str]:
    """``#id P=<score> detected|tracked`` for each removed cluster (the paper's P(C_pv))."""
    return [
        f"#{k} P={'-' if np.isnan(p) else f'{p:.2f}'} {'detected' if d else 'tracked'}"
        for k, p, d in zip(ids.tolist(), p_pv.tolist(), detected.tolist(), strict=True)
    ]


def log_clusters(rec: rr.RecordingStream, batch: FrameBatch) -> None:
    """Clustered points, class id = cluster id; a box and a label per removed cluster.

    Each cluster's points take its id's colour (and ``cluster #id`` on hover) from the
    annotation context of :data:`paths.SENSOR_CLUSTERS`. The clusters the filter removed
    get a box, red when detected in this scan and orange when tracked from the last one,
    and a label at the centroid (``#id P=P(C_pv) detected|tracked``; box labels would be
    misplaced by the sensor view's turned frame). Cluster ``k`` of a frame is
    ``result.cluster_view()``'s cluster ``k``, whichever filter it was; this reads the
    views' per-cluster arrays, all frames at once.

    Args:
        rec: the recording.
        batch: frames whose result has clusters (see :meth:`FrameBatch.with_results`).
    """
    views = [result.cluster_view() for result in batch.results]
    ids = np.stack([d.clusters.labels for d in views])  # (K, n), -1: no cluster
    clustered = ids >= 0
    _send_scan_points(rec, paths.SENSOR_CLUSTERS, batch, clustered, class_ids=ids[clustered])
    # the removed clusters of the batch, numbered across frames
    counts = np.array([len(d.scores) for d in views])
    detected = np.concatenate([d.detected for d in views]).astype(bool)
    tracked = np.concatenate([d.tracked for d in views]).astype(bool)
    removed = np.flatnonzero(detected | tracked)
    first = np.concatenate(([0], np.cumsum(counts)[:-1]))
    frame_of = np.searchsorted(first, removed, side="right") - 1
    per_frame = np.bincount(frame_of, minlength=len(batch))
    # their bounds: the points of removed clusters, grouped by cluster
    is_removed = np.zeros(counts.sum() + 1, dtype=bool)  # the last entry: "no cluster"
    is_removed[removed] = True
    batch_ids = np.where(clustered, ids + first[:, None], -1)
    in_removed = is_removed[batch_ids]
    xy, owner = batch.points[in_removed], batch_ids[in_removed]
    order = np.argsort(owner, kind="stable")
    starts = np.flatnonzero(np.diff(owner[order], prepend=-1))
    low = np.minimum.reduceat(xy[order], starts, axis=0) if len(xy) else np.empty((0, 2))
    high = np.maximum.reduceat(xy[order], starts, axis=0) if len(xy) else np.empty((0, 2))
    colors = np.where(detected[removed], _STATE_COLORS[0], _STATE_COLORS[1])
    _send(
        rec,
        paths.SENSOR_CLUSTER_BOXES,
        batch,
        rr.Boxes2D,
        per_frame,
        centers=(low + high) / 2,
        half_sizes=(high - low) / 2 + CLUSTER_BOX_PAD_M,
        colors=colors,
    )
    centroids = np.concatenate([d.clusters.centroids for d in views]).reshape(-1, 2)
    scores = np.concatenate([d.scores for d in views])
    _send(
        rec,
        paths.SENSOR_CLUSTER_IDS,
        batch,
        rr.Points2D,
        per_frame,
        positions=centroids[removed],
        colors=colors,
        labels=_removed_cluster_labels(
            removed - first[frame_of], scores[removed], detected[removed]
        ),
    )
