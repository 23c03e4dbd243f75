"""The columns of a data-set shard: one row per scan, plain Arrow types.

Every column is a scalar or a list of scalars, so pandas, polars, DuckDB and
Hugging Face ``datasets`` read the shards as they are. The robot's pose and rates are
the simulator's ground truth (:class:`~twsb_sim.frame.RobotTruth`, REP-103 world frame,
z up, positive pitch = nose down); the base frame's origin is the wheel-axle centre.

This module needs pyarrow and numpy only (no simulator), like the loader.
"""

from __future__ import annotations

import pyarrow as pa

from twsb_sim.labels import PITCH_VARIATION_LABELS, BeamLabel

FORMAT_VERSION = 1  # bumped when the columns or the layout change

# (name, Arrow type, meaning) in the order of the table
COLUMNS: tuple[tuple[str, pa.DataType, str], ...] = (
    ("episode", pa.int32(), "episode number k (its seed derives from the data set's seed and k)"),
    ("frame", pa.int32(), "scan number in the episode, from 0"),
    ("stamp_s", pa.float64(), "s, simulated time of the scan since the episode began"),
    ("ranges", pa.list_(pa.float32()), "m, one per beam, REP-117 (+inf no return, -inf blocked)"),
    ("labels", pa.list_(pa.uint8()), "ground-truth BeamLabel code per beam"),
    ("base_x_m", pa.float64(), "m, axle centre in the world"),
    ("base_y_m", pa.float64(), "m"),
    ("base_z_m", pa.float64(), "m"),
    ("base_qw", pa.float64(), "base orientation in the world, unit quaternion (w, x, y, z)"),
    ("base_qx", pa.float64(), ""),
    ("base_qy", pa.float64(), ""),
    ("base_qz", pa.float64(), ""),
    ("yaw_rad", pa.float64(), "rad, heading, counter-clockwise from world x"),
    ("pitch_rad", pa.float64(), "rad, positive = nose down"),
    ("roll_rad", pa.float64(), "rad, positive = left side up"),
    ("pitch_rate_rad_s", pa.float64(), "rad/s"),
    ("forward_velocity_mps", pa.float64(), "m/s, axle velocity along the heading"),
    ("yaw_rate_rad_s", pa.float64(), "rad/s"),
    ("wheel_speed_left_rad_s", pa.float64(), "rad/s, relative to the body, + rolls forward"),
    ("wheel_speed_right_rad_s", pa.float64(), "rad/s"),
    ("wheel_torque_left_nm", pa.float64(), "N·m, as applied (saturated)"),
    ("wheel_torque_right_nm", pa.float64(), "N·m"),
    ("command_velocity_mps", pa.float64(), "m/s, forward-velocity command in force"),
    ("command_yaw_rate_rad_s", pa.float64(), "rad/s, yaw-rate command in force"),
    ("shove_active", pa.bool_(), "a shove is pushing the robot at this instant"),
    ("phase", pa.string(), "maneuver in force: accelerate, cruise, hard stop, brake, turn, ..."),
    ("sensor_x_m", pa.float64(), "m, LiDAR origin in the world"),
    ("sensor_y_m", pa.float64(), "m"),
    ("sensor_z_m", pa.float64(), "m"),
    ("sensor_qw", pa.float64(), "LiDAR orientation in the world (w, x, y, z)"),
    ("sensor_qx", pa.float64(), ""),
    ("sensor_qy", pa.float64(), ""),
    ("sensor_qz", pa.float64(), ""),
    ("imu_gyro_x_rad_s", pa.float64(), "rad/s, IMU frame"),
    ("imu_gyro_y_rad_s", pa.float64(), ""),
    ("imu_gyro_z_rad_s", pa.float64(), ""),
    ("imu_accel_x_mps2", pa.float64(), "m/s², IMU frame, specific force (gravity included)"),
    ("imu_accel_y_mps2", pa.float64(), ""),
    ("imu_accel_z_mps2", pa.float64(), ""),
    ("imu_qw", pa.float64(), "IMU orientation in the world (w, x, y, z)"),
    ("imu_qx", pa.float64(), ""),
    ("imu_qy", pa.float64(), ""),
    ("imu_qz", pa.float64(), ""),
    *(
        (f"n_{label.name.lower()}", pa.int16(), f"beams labeled {label.name} in this scan")
        for label in BeamLabel
    ),
    ("n_pitch_variation", pa.int16(), "beams labeled FLOOR, CEILING or HORIZONTAL"),
)

SCHEMA = pa.schema([pa.field(name, dtype, nullable=False) for name, dtype, _ in COLUMNS])

# the per-label count column of each label name, and of the pitch-variation union
COUNT_COLUMNS: dict[str, str] = {
    **{label.name: f"n_{label.name.lower()}" for label in BeamLabel},
    "PITCH_VARIATION": "n_pitch_variation",
}

PITCH_VARIATION_CODES = tuple(int(label) for label in PITCH_VARIATION_LABELS)
EPISODE_METADATA_KEY = b"twsb.episode"  # Parquet key-value metadata: the episode summary (JSON)
