"""Fig. 8-style pictures: maps side by side per filter, and trajectories against the truth.

Everything is drawn in the world frame: each system's map and trajectory are moved by the
same SE(2) alignment the ATE uses, over the house's true walls (thin grey outlines), so a
duplicated or bent wall shows as map ink off the outlines.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure  # no pyplot: files only, no display, no global state
from matplotlib.patches import Rectangle
from matplotlib.transforms import Affine2D

from scaneval.geometry import scan_points, transform_points
from scaneval.slam import FAILURE_DISTANCE_M
from twsb_sim.house import House
from twsb_sim.slam.experiment import SequenceOutcome
from twsb_sim.slam.methods import METHOD_TITLES
from twsb_sim.slam.systems import SYSTEM_TITLES

METHOD_COLORS = {
    "none": "tab:red",
    "pvf": "tab:blue",
    "pvf_p04": "tab:purple",
    "improved": "tab:cyan",
    "imu_gate": "tab:orange",
    "truth_labels": "tab:green",
}
POINT_MAP_EVERY = 2  # frames: a KISS-ICP point map draws every other scan
UNKNOWN_SHADE = 0.85  # grey level of never-observed cells
DPI = 90


def draw_house(ax: Axes, house: House) -> None:
    """The footprints of the walls and door frames, thin grey outlines."""
    for part in house.walls:
        if part.shape != "box" or part.z_min_m > 0.3:  # door headers are above the scan
            continue
        (x, y, _), (hx, hy, _) = part.pos, part.size
        patch = Rectangle((-hx, -hy), 2 * hx, 2 * hy, fill=False, lw=0.4, ec="0.6")
        patch.set_transform(Affine2D().rotate(part.yaw_rad).translate(x, y) + ax.transData)
        ax.add_patch(patch)


def _alignment(outcome: SequenceOutcome, system: str, method: str) -> np.ndarray | None:
    alignment = np.array(outcome.results[system, method].alignment)
    return alignment if np.all(np.isfinite(alignment)) else None


def _draw_grid_map(ax: Axes, slam: object, alignment: np.ndarray) -> np.ndarray | None:
    """The finest map (black occupied, white free, light grey unknown); its world bounds."""
    grid = slam.maps[0]
    touched = np.argwhere(grid.log_odds != 0.0)
    if touched.size == 0:
        return None
    (i0, j0), (i1, j1) = touched.min(axis=0), touched.max(axis=0) + 1
    shade = 1.0 - grid.probability()[i0:i1, j0:j1]
    shade[grid.log_odds[i0:i1, j0:j1] == 0.0] = UNKNOWN_SHADE
    x0, y0 = grid.origin_xy + np.array([i0, j0]) * grid.resolution_m
    x1, y1 = x0 + (i1 - i0) * grid.resolution_m, y0 + (j1 - j0) * grid.resolution_m
    image = ax.imshow(
        shade.T,
        origin="lower",
        extent=(x0, x1, y0, y1),
        cmap="gray",
        vmin=0.0,
        vmax=1.0,
        interpolation="nearest",
    )
    x, y, theta = alignment
    image.set_transform(Affine2D().rotate(theta).translate(x, y) + ax.transData)
    corners = np.array([[x0, y0], [x1, y0], [x0, y1], [x1, y1]])
    return transform_points(corners, alignment)


def _draw_point_map(
    ax: Axes, outcome: SequenceOutcome, system: str, method: str, alignment: np.ndarray
) -> np.ndarray | None:
    """The scans placed at the estimated poses (KISS-ICP keeps no global map); the points."""
    run, removed = outcome.runs[system, method], outcome.removed[method]
    chunks = []
    for k in range(0, len(outcome.frames), POINT_MAP_EVERY):
        if np.all(np.isfinite(run.poses[k])):
            points = scan_points(outcome.frames[k].scan, removed[k])
            chunks.append(transform_points(points, run.poses[k]))
    if not chunks:
        return None
    world = transform_points(np.concatenate(chunks), alignment)
    ax.scatter(world[:, 0], world[:, 1], s=0.05, c="k", alpha=0.25, lw=0, rasterized=True)
    return world


def _panel_title(outcome: SequenceOutcome, system: str, method: str) -> str:
    result = outcome.results[system, method]
    ate = "tracking failure" if result.failed else f"ATE {result.ate_m:.3f} m"
    return f"{SYSTEM_TITLES[system]}\n{METHOD_TITLES[method]}: {ate}"


def draw_maps(outcome: SequenceOutcome, path: Path, methods: tuple[str, ...] | None = None) -> None:
    """One map per system (rows) and filter (columns), the truth and estimate over it.

    Hector's map is its finest occupancy grid (black = occupied, white = free, grey =
    unknown); KISS-ICP keeps no global map, so its map is the scans placed at its poses.
    """
    systems = sorted({s for s, _ in outcome.runs}, key=list(SYSTEM_TITLES).index)
    methods = methods or tuple(dict.fromkeys(m for _, m in outcome.runs))
    fig = Figure(figsize=(4.8 * len(methods), 4.4 * len(systems)), layout="constrained")
    axes = fig.subplots(len(systems), len(methods), squeeze=False)
    x_min, y_min, x_max, y_max = outcome.sequence.house.extent_m
    for row, system in enumerate(systems):
        for col, method in enumerate(methods):
            ax = axes[row, col]
            alignment = _alignment(outcome, system, method)
            drawn = None
            if alignment is not None:
                if system == "hector" and outcome.runs[system, method].slam is not None:
                    drawn = _draw_grid_map(ax, outcome.runs[system, method].slam, alignment)
                else:
                    drawn = _draw_point_map(ax, outcome, system, method, alignment)
            draw_house(ax, outcome.sequence.house)
            _draw_trajectories(ax, outcome, system, (method,))
            ax.set_title(_panel_title(outcome, system, method), fontsize=9)
            # what was mapped, within the house (a lost map may spread far beyond it)
            seen = outcome.truth[:, :2]
            seen = seen if drawn is None else np.vstack((drawn, seen))
            low = np.maximum(seen.min(axis=0), (x_min, y_min)) - 0.5
            high = np.minimum(seen.max(axis=0), (x_max, y_max)) + 0.5
            ax.set_xlim(low[0], high[0])
            ax.set_ylim(low[1], high[1])
            ax.set_aspect("equal")
            ax.tick_params(labelsize=7)
    fig.suptitle(f"{outcome.sequence.name}, seed {outcome.seed}", fontsize=10)
    fig.savefig(path, dpi=DPI, bbox_inches="tight")


def _draw_trajectories(
    ax: Axes, outcome: SequenceOutcome, system: str, methods: tuple[str, ...]
) -> None:
    ax.plot(*outcome.truth[:, :2].T, color="k", lw=1.0, ls="--", label="truth (sensor)")
    for method in methods:
        run, result = outcome.runs[system, method], outcome.results[system, method]
        alignment = _alignment(outcome, system, method)
        if alignment is None:
            continue
        aligned = transform_points(run.poses[:, :2], alignment)
        ate = "–" if result.failed else f"{result.ate_m:.3f} m"
        label = f"{METHOD_TITLES[method]}: {ate}"
        ax.plot(*aligned.T, color=METHOD_COLORS[method], lw=0.9, label=label)


def draw_trajectories(outcome: SequenceOutcome, path: Path) -> None:
    """Every filter's trajectory against the truth, one panel per system (Fig. 8 (i), (j)),
    and below it the position error over time (the dotted line is the failure threshold)."""
    systems = sorted({s for s, _ in outcome.runs}, key=list(SYSTEM_TITLES).index)
    methods = tuple(dict.fromkeys(m for _, m in outcome.runs))
    fig = Figure(figsize=(5.2 * len(systems), 6.6), layout="constrained")
    axes = fig.subplots(2, len(systems), squeeze=False, height_ratios=(2.2, 1.0))
    stamps = np.array([f.stamp_s for f in outcome.frames])
    for ax, system in zip(axes[1], systems, strict=True):
        for method in methods:
            run, alignment = outcome.runs[system, method], _alignment(outcome, system, method)
            if alignment is not None:
                aligned = transform_points(run.poses[:, :2], alignment)
                error = np.hypot(*(aligned - outcome.truth[:, :2]).T)
                ax.plot(stamps, error, color=METHOD_COLORS[method], lw=0.9)
        ax.axhline(FAILURE_DISTANCE_M, color="k", lw=0.6, ls=":")
        ax.set_xlabel("time (s)", fontsize=7)
        ax.set_ylabel("position error after alignment (m)", fontsize=7)
        ax.tick_params(labelsize=7)
    for ax, system in zip(axes[0], systems, strict=True):
        draw_house(ax, outcome.sequence.house)
        _draw_trajectories(ax, outcome, system, methods)
        ax.set_title(f"{SYSTEM_TITLES[system]} (legend: ATE, – = tracking failure)", fontsize=8)
        ax.set_aspect("equal")
        ax.legend(fontsize=7, loc="best")
        ax.tick_params(labelsize=7)
        _zoom_to(ax, outcome.truth[:, :2], margin_m=1.5)
    fig.suptitle(
        f"{outcome.sequence.name}, seed {outcome.seed}: trajectories after the "
        "ATE's SE(2) alignment",
        fontsize=9,
    )
    fig.savefig(path, dpi=DPI * 1.3, bbox_inches="tight")


def _zoom_to(ax: Axes, points: np.ndarray, margin_m: float) -> None:
    low, high = points.min(axis=0) - margin_m, points.max(axis=0) + margin_m
    half = 0.5 * max(high - low)
    centre = 0.5 * (low + high)
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
