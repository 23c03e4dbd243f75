"""Pictures of single frames for the miss diagnosis: what the filter kept, removed, missed.

A :class:`FrameSnapshot` holds just what a picture needs (a frame's points, truth,
mask, per-beam miss stage and cluster records), so the diagnosis can keep its best
examples after the frames themselves are gone. :func:`render_snapshot` draws one in the
sensor frame: beams coloured by outcome, clusters annotated with ``v_C`` and
``P(C_pv)``, the tracking radial band dashed.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np

from pvfilter import FilterParams, FilterResult
from twsb_sim.frame import Frame
from twsb_sim.labels import is_pitch_variation

OUTCOME_COLOURS = {  # matplotlib colours
    "kept (not pitch variation)": "#b0b0b0",
    "removed, pitch variation (TP)": "#1a9850",
    "removed, not pitch variation (FP)": "#d73027",
    "missed pitch variation (FN)": "#fc8d59",
}
VIEW_M = 6.0  # m, the least half-width of a picture


@dataclasses.dataclass(frozen=True, eq=False)
class FrameSnapshot:
    """One frame with the filter's decision, for a picture.

    Attributes:
        run_id: ``sequence/house/seed``.
        frame_index: the frame's number in the run.
        stamp_s: its time, s.
        pitch_deg: the robot's true pitch, deg (positive = nose down).
        phase: the scenario phase in force.
        reason: why this frame was chosen (shown in the title).
        points: sensor-frame end points, m, ``(n, 2)``, NaN where invalid.
        positive, removed, finite: bool per beam (truth, decision, finite input range).
        clusters: per cluster: centroid, v_c, p_pv, detected, tracked, size, pv_share.
    """

    run_id: str
    frame_index: int
    stamp_s: float
    pitch_deg: float
    phase: str
    reason: str
    points: np.ndarray
    positive: np.ndarray
    removed: np.ndarray
    finite: np.ndarray
    clusters: tuple[dict, ...]


def snapshot(frame: Frame, result: FilterResult, run_id: str, reason: str) -> FrameSnapshot:
    """A picture-ready copy of a frame and the filter's result for it."""
    positive = is_pitch_variation(frame.labels)
    members = result.detection.clusters.labels
    clusters = []
    for c, record in enumerate(result.clusters):
        share = float(positive[members == c].mean()) if record.size else 0.0
        clusters.append(
            {
                "centroid": record.centroid,
                "v_c": record.v_c,
                "p_pv": record.p_pv,
                "detected": record.detected,
                "tracked": record.tracked,
                "size": record.size,
                "pv_share": share,
            }
        )
    return FrameSnapshot(
        run_id=run_id,
        frame_index=frame.index,
        stamp_s=frame.stamp_s,
        pitch_deg=math.degrees(frame.truth.pitch_rad),
        phase=frame.phase,
        reason=reason,
        points=frame.scan.points(),
        positive=positive,
        removed=np.asarray(result.removed, dtype=bool),
        finite=np.isfinite(frame.scan.ranges),
        clusters=tuple(clusters),
    )


def outcome_masks(shot: FrameSnapshot) -> dict[str, np.ndarray]:
    """Beams per outcome (the keys of :data:`OUTCOME_COLOURS`)."""
    pos, rem, fin = shot.positive & shot.finite, shot.removed & shot.finite, shot.finite
    masks = (fin & ~rem & ~pos, rem & pos, rem & ~pos, pos & ~rem)
    return dict(zip(OUTCOME_COLOURS, masks, strict=True))


def render_snapshot(shot: FrameSnapshot, path: Path, params: FilterParams | None = None) -> None:
    """Draw a snapshot in the sensor frame (x forward, up the page) and save it as PNG."""
    import matplotlib

    matplotlib.use("Agg")  # files only, no display
    import matplotlib.pyplot as plt

    params = params or FilterParams()
    fig, ax = plt.subplots(figsize=(7.0, 7.0))
    # sensor x (forward) up the page, y (left) to the left: plot (-y, x)
    for name, mask in outcome_masks(shot).items():
        p = shot.points[mask]
        size = 4 if name.startswith("kept") else 9
        ax.scatter(
            -p[:, 1], p[:, 0], s=size, c=OUTCOME_COLOURS[name], label=f"{name}: {mask.sum()}"
        )
    for radius in (params.d_min, params.d_max):
        ax.add_patch(plt.Circle((0, 0), radius, fill=False, ls="--", lw=0.7, color="#4575b4"))
    ax.annotate("", xy=(0, 0.5), xytext=(0, 0), arrowprops={"arrowstyle": "->", "color": "k"})
    for c, cluster in enumerate(shot.clusters):
        if cluster["v_c"] < params.v_th and not cluster["pv_share"]:
            continue  # gated structure: unlabelled, to keep the picture readable
        x, y = cluster["centroid"]
        state = "D" if cluster["detected"] else ("T" if cluster["tracked"] else "-")
        p_pv = "gated" if math.isnan(cluster["p_pv"]) else f"{cluster['p_pv']:.2f}"
        text = f"c{c} {state} vC={cluster['v_c']:.2f} P={p_pv} pv={cluster['pv_share']:.0%}"
        ax.plot(-y, x, "k+", ms=7)
        ax.annotate(text, (-y, x), fontsize=6.5, xytext=(3, 3), textcoords="offset points")
    ax.set_aspect("equal")
    # show every removed or pitch-variation point, and the rest out to a few metres
    notable = shot.points[shot.finite & (shot.removed | shot.positive)]
    reach = max([VIEW_M, *(np.abs(notable).max(axis=0) + 0.5 if len(notable) else [])])
    ax.set_xlim(-reach, reach)
    ax.set_ylim(-reach, reach)
    ax.set_xlabel("-y (m, left of the robot is left)")
    ax.set_ylabel("x (m, forward)")
    ax.set_title(
        f"{shot.run_id} frame {shot.frame_index} (t={shot.stamp_s:.1f} s, "
        f"pitch {shot.pitch_deg:+.1f}°, {shot.phase})\n{shot.reason}",
        fontsize=8.5,
    )
    ax.legend(
        loc="lower left",
        fontsize=7,
        title="D detected, T tracked; dashed: d_min, d_max",
        title_fontsize=7,
    )
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
