"""The default layout of a recording: 3D world, sensor views, plots and the event log."""

from __future__ import annotations

import math

import rerun.blueprint as rrb
from rerun.blueprint.encodings import TextLogColumn, TextLogColumnKind, TimelineColumn

from twsb_sim.rerun_log import paths

SENSOR_VIEW_HALF_WIDTH_M = 10.0  # the sensor views open on +-10 m around the LiDAR
# the 3D camera starts above, behind and to the right of the robot, steep enough to look
# over the walls, and follows it
EYE_BEHIND_M = 1.5
EYE_RIGHT_M = 1.5
EYE_HEIGHT_M = 6.5
EYE_AHEAD_M = 2.5  # ... looking at the floor this far ahead of it

_UP_TO_CURSOR = rrb.VisibleTimeRanges(
    [
        rrb.VisibleTimeRange(
            timeline,
            start=rrb.TimeRangeBoundary.infinite(),
            end=rrb.TimeRangeBoundary.cursor_relative(),
        )
        for timeline in ("sim_time", "frame")
    ]
)


def _world_view(start: tuple[float, float, float] | None) -> rrb.Spatial3DView:
    eye = None
    if start is not None:  # follow the robot from behind its start pose
        x, y, yaw = start
        c, s = math.cos(yaw), math.sin(yaw)
        eye = rrb.EyeControls3D(
            kind=rrb.Eye3DKind.Orbital,
            position=(
                x - EYE_BEHIND_M * c + EYE_RIGHT_M * s,
                y - EYE_BEHIND_M * s - EYE_RIGHT_M * c,
                EYE_HEIGHT_M,
            ),
            look_target=(x + EYE_AHEAD_M * c, y + EYE_AHEAD_M * s, 0.0),
            eye_up=(0.0, 0.0, 1.0),
            tracking_entity=paths.ROBOT,
        )
    return rrb.Spatial3DView(
        name="3D world: hit points by ground-truth label",
        origin=paths.WORLD,
        overrides={
            paths.TRAJECTORY: _UP_TO_CURSOR,  # the whole path so far, not the last segment
            paths.ODOMETRY: _UP_TO_CURSOR,
            paths.HOUSE_CEILING: rrb.EntityBehavior(visible=False),  # it would hide the rest
        },
        background=(30, 30, 34),
        line_grid=rrb.LineGrid3D(visible=False),
        eye_controls=eye,
    )


def _sensor_view(name: str, *layers: str) -> rrb.Spatial2DView:
    half = SENSOR_VIEW_HALF_WIDTH_M
    return rrb.Spatial2DView(
        name=name,
        origin=paths.SENSOR,
        contents=[paths.SENSOR_FRAME, paths.SENSOR_RINGS, paths.SENSOR_ROBOT, *layers],
        visual_bounds=rrb.VisualBounds2D(x_range=[-half, half], y_range=[-half, half]),
        background=(18, 18, 20),
    )


def _plot(name: str, path: str) -> rrb.TimeSeriesView:
    return rrb.TimeSeriesView(name=name, origin=path, plot_legend=rrb.PlotLegend(visible=True))


def _events_view() -> rrb.TextLogView:
    return rrb.TextLogView(
        name="Events",
        origin=paths.EVENTS,
        columns=rrb.TextLogColumns(
            timeline_columns=[
                TimelineColumn("sim_time"),
                TimelineColumn("frame", visible=False),
                TimelineColumn("log_time", visible=False),
            ],
            text_log_columns=[
                TextLogColumn(TextLogColumnKind.EntityPath, visible=False),
                TextLogColumn(TextLogColumnKind.LogLevel),
                TextLogColumn(TextLogColumnKind.Body),
            ],
        ),
    )


def default_blueprint(start: tuple[float, float, float] | None = None) -> rrb.Blueprint:
    """The layout a recording opens with.

    Top: the 3D world, the sensor view of the filter's decisions (of the ground-truth
    labels in runs without a filter) and the sensor view of the clusters. Bottom: the
    time series and the event log. The time panel starts on ``sim_time``.

    Args:
        start: the robot's start (x m, y m, yaw rad); the 3D camera then starts behind
            it and follows it. None: the viewer's default camera.
    """
    decisions = _sensor_view(
        "Sensor frame: filter decision per beam",
        paths.SENSOR_REMOVED,
        paths.SENSOR_DECISION,
        paths.SENSOR_LABELS,  # runs without a filter: the labels instead
        paths.SENSOR_CLUSTER_BOXES,
        paths.SENSOR_LEVEL_VIEW,  # the improved filter's
    )
    clusters = _sensor_view(
        "Sensor frame: clusters",
        paths.SENSOR_CLUSTERS,
        paths.SENSOR_CLUSTER_BOXES,
        paths.SENSOR_CLUSTER_IDS,
    )
    plots = rrb.Grid(
        _plot("Pitch: truth and IMU estimate", paths.PLOT_PITCH),
        _plot("Roll: truth and IMU estimate", paths.PLOT_ROLL),
        _plot("Pitch rate", paths.PLOT_PITCH_RATE),
        _plot("Velocity: command, truth, encoders", paths.PLOT_VELOCITY),
        _plot("Encoder odometry error", paths.PLOT_ODOMETRY_ERROR),
        _plot("Yaw rate", paths.PLOT_YAW_RATE),
        _plot("Wheel torques", paths.PLOT_WHEEL_TORQUE),
        _plot("Pitch-variation beams", paths.PLOT_BEAMS),
        _plot("Precision / recall per frame", paths.PLOT_PRECISION_RECALL),
        _plot("Beam score", paths.PLOT_P_PV),
        grid_columns=5,
    )
    return rrb.Blueprint(
        rrb.Vertical(
            rrb.Horizontal(
                _world_view(start),
                decisions,
                clusters,
                column_shares=[4, 3, 3],
            ),
            rrb.Horizontal(
                plots,
                rrb.Vertical(
                    rrb.TextDocumentView(name="Legend", origin=paths.LEGEND), _events_view()
                ),
                column_shares=[3, 1],
            ),
            row_shares=[3, 2],
        ),
        rrb.TimePanel(timeline="sim_time", state="collapsed"),
        rrb.SelectionPanel(state="collapsed"),
        rrb.BlueprintPanel(state="collapsed"),
    )
