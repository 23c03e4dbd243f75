"""A Rerun recording of one sequence's SLAM runs: the house, the truth, every system's
trajectory and map per filter, and the scans each filter let through.

Entity paths: ``world/house/...`` (as ``twsb run`` records it), ``world/truth``,
``world/slam/<system>/<filter>/{trajectory,pose,map}`` and, for the Hector-style SLAM,
``world/slam/hector/<filter>/scan`` (the scan used, placed at the estimate) with
``.../removed`` (what the filter took out). Everything is in the world frame after the
ATE's SE(2) alignment; per-scan entities are on the ``sim_time`` and ``frame`` timelines.
One top-down view per filter.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import rerun as rr
import rerun.blueprint as rrb

from scaneval.geometry import scan_points, transform_points
from twsb_sim.rerun_log.geometry import log_house
from twsb_sim.rerun_log.timelines import frame_times
from twsb_sim.slam.experiment import SequenceOutcome
from twsb_sim.slam.methods import METHOD_TITLES
from twsb_sim.slam.systems import SYSTEMS

TRUTH = "world/truth"
SLAM = "world/slam"
LINE_RADIUS_UI = -1.5  # negative radii are in UI points
POINT_RADIUS_UI = -0.75
POSE_RADIUS_UI = -4.0
MAP_OCCUPIED_PROBABILITY = 0.65  # grid cells drawn as map points from this probability
MAP_Z_M = 0.02  # m: maps and trajectories float just above the floor
# one view per filter, so colours tell the systems apart
SYSTEM_COLORS = {"hector": (90, 170, 255), "kiss_icp": (255, 150, 60)}
TRUTH_COLOR = (80, 220, 120)
SCAN_COLOR = (235, 235, 235)
REMOVED_COLOR = (255, 0, 255)


def _times(frames: list) -> list[rr.TimeColumn]:
    return frame_times([f.stamp_s for f in frames], [f.index for f in frames])


def _on_floor(xy: np.ndarray) -> np.ndarray:
    return np.column_stack((xy, np.full(len(xy), MAP_Z_M)))


def log_truth(rec: rr.RecordingStream, outcome: SequenceOutcome) -> None:
    """The sensor's true path, static."""
    rec.log(
        f"{TRUTH}/trajectory",
        rr.LineStrips3D(
            [_on_floor(outcome.truth[:, :2])], colors=(255, 255, 255), radii=LINE_RADIUS_UI
        ),
        static=True,
    )


def log_system(rec: rr.RecordingStream, outcome: SequenceOutcome, system: str, method: str) -> None:
    """One system's aligned trajectory (static), its pose per scan, and its map (static)."""
    run, result = outcome.runs[system, method], outcome.results[system, method]
    alignment = np.array(result.alignment)
    if not np.all(np.isfinite(alignment)):
        return
    path = f"{SLAM}/{system}/{method}"
    color = SYSTEM_COLORS[system]
    finite = np.all(np.isfinite(run.poses), axis=1)
    xy = transform_points(run.poses[finite, :2], alignment)
    rec.log(
        f"{path}/trajectory",
        rr.LineStrips3D([_on_floor(xy)], colors=color, radii=LINE_RADIUS_UI),
        static=True,
    )
    frames = [f for f, ok in zip(outcome.frames, finite, strict=True) if ok]
    rec.send_columns(
        f"{path}/pose",
        indexes=_times(frames),
        columns=rr.Points3D.columns(
            positions=_on_floor(xy),
            colors=np.tile(color, (len(xy), 1)),
            radii=np.full(len(xy), POSE_RADIUS_UI, np.float32),
        ),
    )
    rec.log(f"{path}/map", _map_points(outcome, system, method, alignment), static=True)


def _map_points(
    outcome: SequenceOutcome, system: str, method: str, alignment: np.ndarray
) -> rr.Points3D:
    run = outcome.runs[system, method]
    if system == "hector" and run.slam is not None:
        grid = run.slam.maps[0]
        cells = np.argwhere(grid.probability() >= MAP_OCCUPIED_PROBABILITY)
        xy = grid.origin_xy + (cells + 0.5) * grid.resolution_m
    else:  # a point map: every other scan at its estimated pose, thinned to a 5 cm raster
        chunks = [
            transform_points(
                scan_points(outcome.frames[k].scan, outcome.removed[method][k]), run.poses[k]
            )
            for k in range(0, len(outcome.frames), 2)
            if np.all(np.isfinite(run.poses[k]))
        ]
        xy = np.concatenate(chunks) if chunks else np.zeros((0, 2))
        xy = np.unique(np.round(xy / 0.05), axis=0) * 0.05
    xy = transform_points(xy, alignment)
    return rr.Points3D(_on_floor(xy), colors=SYSTEM_COLORS[system], radii=POINT_RADIUS_UI)


def log_scans(rec: rr.RecordingStream, outcome: SequenceOutcome, method: str) -> None:
    """The scans the Hector-style SLAM used, and the beams the filter removed, per scan."""
    run, result = outcome.runs["hector", method], outcome.results["hector", method]
    alignment = np.array(result.alignment)
    if not np.all(np.isfinite(alignment)):
        return
    kept, removed, kept_n, removed_n, frames = [], [], [], [], []
    for frame, pose, mask in zip(outcome.frames, run.poses, outcome.removed[method], strict=True):
        if not np.all(np.isfinite(pose)):
            continue
        placed = lambda points, pose=pose: transform_points(  # noqa: E731
            transform_points(points, pose), alignment
        )
        kept.append(placed(scan_points(frame.scan, mask)))
        removed.append(placed(frame.scan.points()[mask & frame.scan.valid_mask()]))
        kept_n.append(len(kept[-1]))
        removed_n.append(len(removed[-1]))
        frames.append(frame)
    if not frames:
        return
    times = _times(frames)
    for name, chunks, lengths, color in (
        ("scan", kept, kept_n, SCAN_COLOR),
        ("removed", removed, removed_n, REMOVED_COLOR),
    ):
        points = _on_floor(np.concatenate(chunks))
        rec.send_columns(
            f"{SLAM}/hector/{method}/{name}",
            indexes=times,
            columns=rr.Points3D.columns(
                positions=points,
                colors=np.tile(color, (len(points), 1)),
                radii=np.full(len(points), POINT_RADIUS_UI, np.float32),
            ).partition(lengths),
        )


def blueprint(
    methods: list[str], house_extent_m: tuple[float, float, float, float]
) -> rrb.Blueprint:
    """One top-down 3D view per filter: the walls, the truth, and both systems with that
    filter; the time cursor follows the end of the recording (the finished maps)."""
    x_min, y_min, x_max, y_max = house_extent_m
    centre = (0.5 * (x_min + x_max), 0.5 * (y_min + y_max))
    height = 1.4 * max(x_max - x_min, y_max - y_min)
    eye = rrb.EyeControls3D(
        kind=rrb.Eye3DKind.Orbital,
        position=(centre[0], centre[1] - 0.05 * height, height),  # nearly straight down
        look_target=(centre[0], centre[1], 0.0),
        eye_up=(0.0, 0.0, 1.0),
    )
    views = [
        rrb.Spatial3DView(
            name=METHOD_TITLES[method],
            origin="world",
            contents=[
                "+ world/house/walls",
                f"+ {TRUTH}/**",
                *(f"+ {SLAM}/{system}/{method}/**" for system in SYSTEMS),
            ],
            background=(30, 30, 34),
            line_grid=rrb.LineGrid3D(visible=False),
            eye_controls=eye,
        )
        for method in methods
    ]
    return rrb.Blueprint(
        rrb.Grid(*views),
        rrb.TimePanel(timeline="frame", play_state="following"),
        collapse_panels=True,
    )


def record_sequence(outcome: SequenceOutcome, path: Path) -> None:
    """Write the recording of one sequence's runs to ``path`` (``.rrd``)."""
    methods = list(dict.fromkeys(m for _, m in outcome.runs))
    rec = rr.RecordingStream("twsb_slam", recording_id=f"{outcome.sequence.name}-{outcome.seed}")
    rec.save(path, default_blueprint=blueprint(methods, outcome.sequence.house.extent_m))
    log_house(rec, outcome.sequence.house)
    log_truth(rec, outcome)
    for system, method in outcome.runs:
        log_system(rec, outcome, system, method)
    if any(system == "hector" for system, _ in outcome.runs):
        for method in methods:
            log_scans(rec, outcome, method)
    rec.flush()
    rec.disconnect()
