"""The robot's own sensors against the truth: attitude estimate, encoder odometry.

The estimate is plotted at every IMU sample (its arrival time: lag and latency show),
beside the true pitch and roll of :mod:`~twsb_sim.rerun_log.plots`. Odometry is drawn in
the 3D world (its ``odom`` frame placed at the robot's start pose, where it began) and
plotted as its error against the truth: distance (m) and heading (deg).
"""

from __future__ import annotations

import math

import numpy as np
import rerun as rr

from twsb_sim.rerun_log import paths
from twsb_sim.rerun_log.batch import FrameBatch
from twsb_sim.rerun_log.timelines import sim_times

ODOMETRY_COLOR = (255, 200, 40)
ODOMETRY_RADIUS_UI = -2.0
ODOMETRY_HEIGHT_M = 0.01  # the odometry path is drawn just above the truth's

SENSOR_SERIES_STYLES = {
    paths.PLOT_PITCH_ESTIMATE: (["IMU estimate [deg]"], [(120, 120, 255)]),
    paths.PLOT_ROLL: (["roll [deg] (+ = left side up)"], [(200, 120, 255)]),
    paths.PLOT_ROLL_ESTIMATE: (["IMU estimate [deg]"], [(120, 200, 255)]),
    paths.PLOT_VELOCITY_ODOMETRY: (["encoder odometry [m/s]"], [(255, 200, 40)]),
    paths.PLOT_ODOMETRY_ERROR: (
        ["position error [m]", "heading error [deg]"],
        [(255, 200, 40), (255, 120, 40)],
    ),
}


def log_sensor_styles(rec: rr.RecordingStream) -> None:
    """Names and colours of the sensor series, and the odometry path's look (static)."""
    for path, (names, colors) in SENSOR_SERIES_STYLES.items():
        rec.log(path, rr.SeriesLines(names=names, colors=colors), static=True)
    rec.log(
        paths.ODOMETRY,
        rr.Points3D.from_fields(colors=[ODOMETRY_COLOR], radii=ODOMETRY_RADIUS_UI),
        static=True,
    )


def odom_in_world(start_xy_yaw: np.ndarray, poses_odom: np.ndarray) -> np.ndarray:
    """``(k, 3)`` odom-frame poses (x, y, yaw) placed in the world at the start pose."""
    x0, y0, yaw0 = start_xy_yaw
    c, s = math.cos(yaw0), math.sin(yaw0)
    x, y, yaw = poses_odom.T
    return np.column_stack((x0 + c * x - s * y, y0 + s * x + c * y, yaw0 + yaw))


def log_sensor_series(
    rec: rr.RecordingStream, batch: FrameBatch, t0_s: float, start_xy_yaw: np.ndarray
) -> None:
    """Attitude estimate, odometry path and error, true roll for the frames of ``batch``.

    Args:
        rec: the recording.
        batch: consecutive frames (those without sensor readings are skipped).
        t0_s: where this run's time 0 sits on ``sim_time`` (s).
        start_xy_yaw: the robot's start pose in the world (x m, y m, yaw rad): the odom
            frame's origin.
    """
    frames = [f for f in batch.frames if f.sensors is not None]
    if not frames:
        return
    imu = [f.sensors.imu for f in frames]
    stamps = np.concatenate([s.stamps_s for s in imu])
    if len(stamps):
        rpy = np.degrees(np.vstack([s.rpy_rad for s in imu]))
        times = sim_times(t0_s + stamps)
        for path, column in ((paths.PLOT_PITCH_ESTIMATE, 1), (paths.PLOT_ROLL_ESTIMATE, 0)):
            scalars = rr.Scalars.columns(scalars=rpy[:, column : column + 1])
            rec.send_columns(path, indexes=times, columns=scalars)
    keep = [i for i, f in enumerate(batch.frames) if f.sensors is not None]
    times = batch.subset(keep).times
    roll = np.degrees([[f.truth.roll_rad] for f in frames])
    rec.send_columns(paths.PLOT_ROLL, indexes=times, columns=rr.Scalars.columns(scalars=roll))
    twist = np.array([[f.sensors.twist[0]] for f in frames])
    rec.send_columns(
        paths.PLOT_VELOCITY_ODOMETRY, indexes=times, columns=rr.Scalars.columns(scalars=twist)
    )
    odom = odom_in_world(start_xy_yaw, np.array([f.sensors.pose_base_in_odom for f in frames]))
    true_xy = np.array([f.truth.position_base_in_world[:2] for f in frames])
    true_yaw = np.array([f.truth.yaw_rad for f in frames])
    heading_error = np.degrees(np.angle(np.exp(1j * (odom[:, 2] - true_yaw))))
    errors = np.column_stack((np.linalg.norm(odom[:, :2] - true_xy, axis=1), heading_error))
    rec.send_columns(
        paths.PLOT_ODOMETRY_ERROR, indexes=times, columns=rr.Scalars.columns(scalars=errors)
    )
    positions = np.column_stack((odom[:, :2], np.full(len(odom), ODOMETRY_HEIGHT_M)))
    rec.send_columns(
        paths.ODOMETRY, indexes=times, columns=rr.Points3D.columns(positions=positions)
    )
