"""The columns of a data-set shard: one row per scan, plain Arrow types.

Every column is a scalar or a list of scalars, so pandas, polars, DuckDB and
Hugging Face ``datasets`` read the shards as they are. The robot's pose and rates are
the simulator's ground truth (:class:`~twsb_sim.frame.RobotTruth`, REP-103 world frame,
z up, positive pitch = nose down); the base frame's origin is the wheel-axle centre.
What the robot's own sensors reported (format 2 on) sits beside it: the encoder
odometry and the attitude estimate at the scan's stamp, and the IMU samples and
odometry updates that arrived since the previous scan (list columns, their own rates).

Format history (``FORMAT_VERSION``; the loader reads every one):

- 1: scans cast at one instant (``time_increment`` 0); ground truth only.
- 2: rotating scans (beam ``i`` at ``stamp_s + i * time_increment``, the stamp being
  beam 0's time); the robot's sensors (:data:`SENSOR_COLUMNS`).

This module needs pyarrow and numpy only (no simulator), like the loader.
"""

from __future__ import annotations

import pyarrow as pa

from twsb_sim.labels import PITCH_VARIATION_LABELS, BeamLabel

FORMAT_VERSION = 2  # bumped when the columns or the layout change

_F64_LIST = pa.list_(pa.float64())
_F32_LIST = pa.list_(pa.float32())

# what the robot's own sensors reported (format 2 on)
SENSOR_COLUMNS: tuple[tuple[str, pa.DataType, str], ...] = (
    ("odom_x_m", pa.float64(), "m, base_footprint in odom at the stamp, from the encoders"),
    ("odom_y_m", pa.float64(), "m"),
    ("odom_yaw_rad", pa.float64(), "rad"),
    ("odom_forward_velocity_mps", pa.float64(), "m/s, encoder odometry's twist"),
    ("odom_yaw_rate_rad_s", pa.float64(), "rad/s"),
    ("lidar_odom_x_m", pa.float64(), "m, the LiDAR in odom at the stamp (encoder odometry)"),
    ("lidar_odom_y_m", pa.float64(), "m"),
    ("lidar_odom_yaw_rad", pa.float64(), "rad"),
    ("est_roll_rad", pa.float64(), "rad, the robot's attitude estimate at the stamp"),
    ("est_pitch_rad", pa.float64(), "rad, positive = nose down (noisy IMU, filter lag)"),
    ("est_yaw_rad", pa.float64(), "rad, from the gyro alone, 0 at the start"),
    ("imu_samples_stamp_s", _F64_LIST, "s, IMU samples since the previous scan: arrival"),
    ("imu_samples_gyro_x_rad_s", _F32_LIST, "rad/s, IMU frame, as measured"),
    ("imu_samples_gyro_y_rad_s", _F32_LIST, ""),
    ("imu_samples_gyro_z_rad_s", _F32_LIST, ""),
    ("imu_samples_accel_x_mps2", _F32_LIST, "m/s², IMU frame, as measured"),
    ("imu_samples_accel_y_mps2", _F32_LIST, ""),
    ("imu_samples_accel_z_mps2", _F32_LIST, ""),
    ("imu_samples_roll_rad", _F32_LIST, "rad, the attitude estimate after each sample"),
    ("imu_samples_pitch_rad", _F32_LIST, ""),
    ("imu_samples_yaw_rad", _F32_LIST, ""),
    ("odom_samples_stamp_s", _F64_LIST, "s, odometry updates since the previous scan"),
    ("odom_samples_x_m", _F64_LIST, "m, base_footprint in odom"),
    ("odom_samples_y_m", _F64_LIST, "m"),
    ("odom_samples_yaw_rad", _F64_LIST, "rad"),
    ("odom_samples_forward_velocity_mps", _F32_LIST, "m/s"),
    ("odom_samples_yaw_rate_rad_s", _F32_LIST, "rad/s"),
)

# (name, Arrow type, meaning) in the order of the table
COLUMNS: tuple[tuple[str, pa.DataType, str], ...] = (
    ("episode", pa.int32(), "episode number k (its seed derives from the data set's seed and k)"),
    ("frame", pa.int32(), "scan number in the episode, from 0"),
    ("stamp_s", pa.float64(), "s, time of the scan's beam 0 since the episode began"),
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
    ("imu_gyro_x_rad_s", pa.float64(), "rad/s, IMU frame, exact (no sensor errors)"),
    ("imu_gyro_y_rad_s", pa.float64(), ""),
    ("imu_gyro_z_rad_s", pa.float64(), ""),
    ("imu_accel_x_mps2", pa.float64(), "m/s², IMU frame, specific force, exact"),
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
    *SENSOR_COLUMNS,
)

# the format a column first appeared in (the others were there from format 1)
COLUMN_SINCE: dict[str, int] = {name: 2 for name, _, _ in SENSOR_COLUMNS}
FORMAT_CHANGES = {  # format: what it added, for the message an older data set gets
    2: "rotating scans and the robot's sensors (encoder odometry, attitude estimate, "
    "IMU samples); its scans were cast at one instant (time_increment 0)",
}

SCHEMA = pa.schema([pa.field(name, dtype, nullable=False) for name, dtype, _ in COLUMNS])

# the per-label count column of each label name, and of the pitch-variation union
COUNT_COLUMNS: dict[str, str] = {
    **{label.name: f"n_{label.name.lower()}" for label in BeamLabel},
    "PITCH_VARIATION": "n_pitch_variation",
}

PITCH_VARIATION_CODES = tuple(int(label) for label in PITCH_VARIATION_LABELS)
EPISODE_METADATA_KEY = b"twsb.episode"  # Parquet key-value metadata: the episode summary (JSON)
