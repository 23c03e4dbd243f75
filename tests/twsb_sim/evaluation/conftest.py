"""Frames made by hand (pvfilter's synthetic ray caster) for the evaluation tests."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest

from pvfilter.synthetic import ray_cast, segment_scan
from twsb_sim.frame import Frame, RobotTruth
from twsb_sim.labels import BeamLabel

LIDAR_HEIGHT_M = 0.25


def truth_at(pose: tuple[float, float, float], stamp: float = 0.0) -> RobotTruth:
    """A level robot standing still with its sensor at ``pose`` (x m, y m, yaw rad)."""
    x, y, yaw = pose
    c, s = np.cos(yaw), np.sin(yaw)
    zero2, zero3 = np.zeros(2), np.zeros(3)
    return RobotTruth(
        stamp_s=stamp,
        position_base_in_world=np.array([x, y, 0.08]),
        quat_base_in_world=np.array([np.cos(yaw / 2), 0.0, 0.0, np.sin(yaw / 2)]),
        yaw_rad=yaw,
        pitch_rad=0.0,
        roll_rad=0.0,
        pitch_rate_rad_s=0.0,
        forward_velocity_mps=0.0,
        yaw_rate_rad_s=0.0,
        wheel_speeds_rad_s=zero2,
        wheel_torques_nm=zero2,
        command_velocity_mps=0.0,
        command_yaw_rate_rad_s=0.0,
        shove_active=False,
        position_sensor_in_world=np.array([x, y, LIDAR_HEIGHT_M]),
        rotation_sensor_to_world=np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]),
        imu_gyro_rad_s=zero3,
        imu_accel_mps2=np.array([0.0, 0.0, 9.81]),
        imu_quat=np.array([np.cos(yaw / 2), 0.0, 0.0, np.sin(yaw / 2)]),
    )


def frame_of(
    index: int,
    structure: np.ndarray,
    floor: np.ndarray | None = None,
    pose: tuple[float, float, float] = (0.0, 0.0, 0.0),
    structure_geom: int = 0,
) -> Frame:
    """A frame of sensor-frame segments: ``structure`` labelled STATIC (geom
    ``structure_geom``), ``floor`` labelled FLOOR (geom 1); stamp 0.1 s per index."""
    floor = np.zeros((0, 2, 2)) if floor is None else floor
    scan = segment_scan(np.concatenate((structure, floor)), stamp=0.1 * index)
    angles = scan.angles()
    on_floor = ray_cast(floor, angles) < ray_cast(structure, angles)
    finite = np.isfinite(scan.ranges)
    labels = np.where(finite, BeamLabel.STATIC, BeamLabel.NO_RETURN).astype(np.uint8)
    labels[finite & on_floor] = BeamLabel.FLOOR
    geom_ids = np.where(finite, np.where(on_floor, 1, structure_geom), -1)
    x, y, yaw = pose
    points = scan.points()
    c, s = np.cos(yaw), np.sin(yaw)
    world = np.column_stack(
        (x + c * points[:, 0] - s * points[:, 1], y + s * points[:, 0] + c * points[:, 1],
         np.full(len(scan), LIDAR_HEIGHT_M))
    )  # fmt: skip
    return Frame(
        index=index,
        scan=scan,
        labels=labels,
        hit_points_world=world,
        truth=truth_at(pose, scan.stamp),
        geom_ids=geom_ids,
    )


@pytest.fixture
def make_frame() -> Callable[..., Frame]:
    """Build a frame from segments (see :func:`frame_of`)."""
    return frame_of
