"""A frame sink that keeps an episode's scans, truth and sensor readings as one table."""

from __future__ import annotations

from typing import Any

import numpy as np
import pyarrow as pa
from scipy.spatial.transform import Rotation

from twsb_sim.dataset.schema import COUNT_COLUMNS, PITCH_VARIATION_CODES, SCHEMA, SENSOR_COLUMNS
from twsb_sim.frame import Frame
from twsb_sim.labels import BeamLabel
from twsb_sim.sinks import NullSink

SCAN_FIELDS = (  # the LaserScan intrinsics of every scan, kept once per episode
    "angle_min",
    "angle_max",
    "angle_increment",
    "range_min",
    "range_max",
    "time_increment",
    "scan_time",
)

_TRUTH_SCALARS = {  # column: RobotTruth field
    "yaw_rad": "yaw_rad",
    "pitch_rad": "pitch_rad",
    "roll_rad": "roll_rad",
    "pitch_rate_rad_s": "pitch_rate_rad_s",
    "forward_velocity_mps": "forward_velocity_mps",
    "yaw_rate_rad_s": "yaw_rate_rad_s",
    "command_velocity_mps": "command_velocity_mps",
    "command_yaw_rate_rad_s": "command_yaw_rate_rad_s",
}
_TRUTH_VECTORS = {  # RobotTruth field: its columns
    "position_base_in_world": ("base_x_m", "base_y_m", "base_z_m"),
    "quat_base_in_world": ("base_qw", "base_qx", "base_qy", "base_qz"),
    "wheel_speeds_rad_s": ("wheel_speed_left_rad_s", "wheel_speed_right_rad_s"),
    "wheel_torques_nm": ("wheel_torque_left_nm", "wheel_torque_right_nm"),
    "position_sensor_in_world": ("sensor_x_m", "sensor_y_m", "sensor_z_m"),
    "imu_gyro_rad_s": ("imu_gyro_x_rad_s", "imu_gyro_y_rad_s", "imu_gyro_z_rad_s"),
    "imu_accel_mps2": ("imu_accel_x_mps2", "imu_accel_y_mps2", "imu_accel_z_mps2"),
    "imu_quat": ("imu_qw", "imu_qx", "imu_qy", "imu_qz"),
}


_SENSOR_SCALARS = {  # SensorReadings field: its columns
    "pose_base_in_odom": ("odom_x_m", "odom_y_m", "odom_yaw_rad"),
    "twist": ("odom_forward_velocity_mps", "odom_yaw_rate_rad_s"),
    "pose_lidar_in_odom": ("lidar_odom_x_m", "lidar_odom_y_m", "lidar_odom_yaw_rad"),
    "attitude_rpy_rad": ("est_roll_rad", "est_pitch_rad", "est_yaw_rad"),
}
_IMU_SAMPLES = ("imu_samples_stamp_s",
                *(f"imu_samples_gyro_{c}_rad_s" for c in "xyz"),
                *(f"imu_samples_accel_{c}_mps2" for c in "xyz"),
                "imu_samples_roll_rad", "imu_samples_pitch_rad", "imu_samples_yaw_rad")  # fmt: skip
_ODOM_SAMPLES = ("odom_samples_stamp_s", "odom_samples_x_m", "odom_samples_y_m",
                 "odom_samples_yaw_rad", "odom_samples_forward_velocity_mps",
                 "odom_samples_yaw_rate_rad_s")  # fmt: skip


class EpisodeRecorder(NullSink):
    """Keeps what the data set stores of every frame of one run."""

    def __init__(self) -> None:
        self.ranges: list[np.ndarray] = []
        self.labels: list[np.ndarray] = []
        self.stamps: list[float] = []
        self.phases: list[str] = []
        self.shove_active: list[bool] = []
        self.scalars: dict[str, list[float]] = {c: [] for c in _TRUTH_SCALARS}
        self.vectors: dict[str, list[np.ndarray]] = {f: [] for f in _TRUTH_VECTORS}
        self.sensor_rotations: list[np.ndarray] = []
        self.sensor_scalars: list[np.ndarray] = []  # per frame: the _SENSOR_SCALARS columns
        self.imu_samples: list[np.ndarray] = []  # per frame: (k, 10), the _IMU_SAMPLES
        self.odom_samples: list[np.ndarray] = []  # per frame: (k, 6), the _ODOM_SAMPLES
        self.intrinsics: dict[str, float | int] | None = None  # LaserScan fields, first frame

    def __len__(self) -> int:
        return len(self.stamps)

    def on_frame(self, frame: Frame, filter_result: Any | None) -> None:
        truth = frame.truth
        if self.intrinsics is None:
            scan = frame.scan
            self.intrinsics = {name: float(getattr(scan, name)) for name in SCAN_FIELDS}
            self.intrinsics["beams"] = len(scan)
        self.ranges.append(frame.scan.ranges.astype(np.float32))
        self.labels.append(frame.labels)
        self.stamps.append(frame.stamp_s)
        self.phases.append(frame.phase)
        self.shove_active.append(truth.shove_active)
        for column, name in _TRUTH_SCALARS.items():
            self.scalars[column].append(getattr(truth, name))
        for name in _TRUTH_VECTORS:
            self.vectors[name].append(getattr(truth, name))
        self.sensor_rotations.append(truth.rotation_sensor_to_world)
        sensors = frame.sensors
        self.sensor_scalars.append(np.concatenate([getattr(sensors, f) for f in _SENSOR_SCALARS]))
        imu, odom = sensors.imu, sensors.odometry
        self.imu_samples.append(
            np.column_stack((imu.stamps_s, imu.gyro_rad_s, imu.accel_mps2, imu.rpy_rad))
        )
        self.odom_samples.append(np.column_stack((odom.stamps_s, odom.pose_odom, odom.twist)))

    def truncate(self, n_frames: int) -> None:
        """Keep only the first ``n_frames`` frames."""
        lists = [self.ranges, self.labels, self.stamps, self.phases, self.shove_active]
        lists += [self.sensor_rotations, *self.scalars.values(), *self.vectors.values()]
        lists += [self.sensor_scalars, self.imu_samples, self.odom_samples]
        for values in lists:
            del values[n_frames:]

    def to_table(self, episode: int) -> pa.Table:
        """The episode's rows in the data-set schema (:data:`~twsb_sim.dataset.schema.SCHEMA`)."""
        n = len(self)
        ranges = np.stack(self.ranges) if n else np.zeros((0, 0), np.float32)
        labels = np.stack(self.labels) if n else np.zeros((0, 0), np.uint8)
        columns: dict[str, Any] = {
            "episode": np.full(n, episode, np.int32),
            "frame": np.arange(n, dtype=np.int32),
            "stamp_s": np.array(self.stamps, np.float64),
            "ranges": _list_array(ranges, pa.float32()),
            "labels": _list_array(labels, pa.uint8()),
            "shove_active": np.array(self.shove_active, bool),
            "phase": pa.array(self.phases, pa.string()),
        }
        for column, values in self.scalars.items():
            columns[column] = np.array(values, np.float64)
        for name, names in _TRUTH_VECTORS.items():
            stacked = np.array(self.vectors[name], np.float64).reshape(n, len(names))
            columns.update({c: stacked[:, i] for i, c in enumerate(names)})
        quats = _quaternions_wxyz(self.sensor_rotations)
        columns.update({f"sensor_{c}": quats[:, i] for i, c in enumerate(("qw", "qx", "qy", "qz"))})
        for label in BeamLabel:
            counts = np.count_nonzero(labels == label, axis=1)
            columns[COUNT_COLUMNS[label.name]] = counts.astype(np.int16)
        columns["n_pitch_variation"] = np.isin(labels, PITCH_VARIATION_CODES).sum(1, np.int16)
        names = [c for cs in _SENSOR_SCALARS.values() for c in cs]
        scalars = np.array(self.sensor_scalars, np.float64).reshape(n, len(names))
        columns.update({c: scalars[:, i] for i, c in enumerate(names)})
        types = {name: dtype for name, dtype, _ in SENSOR_COLUMNS}
        for names, samples in (
            (_IMU_SAMPLES, self.imu_samples),
            (_ODOM_SAMPLES, self.odom_samples),
        ):
            columns.update(_ragged_columns(names, samples, types))
        return pa.table({f.name: columns[f.name] for f in SCHEMA}, schema=SCHEMA)


def _ragged_columns(
    names: tuple[str, ...], per_row: list[np.ndarray], types: dict[str, pa.DataType]
) -> dict[str, pa.ListArray]:
    """List columns from one ``(k_row, len(names))`` block per row (k_row may vary)."""
    lengths = np.array([len(block) for block in per_row], dtype=np.int32)
    offsets = pa.array(np.concatenate(([0], np.cumsum(lengths))).astype(np.int32), pa.int32())
    stacked = np.vstack(per_row) if per_row else np.zeros((0, len(names)))
    return {
        name: pa.ListArray.from_arrays(offsets, pa.array(stacked[:, i], types[name].value_type))
        for i, name in enumerate(names)
    }


def _list_array(rows: np.ndarray, value_type: pa.DataType) -> pa.ListArray:
    """One list per row of a 2-D array, without a Python loop."""
    n, width = rows.shape
    offsets = pa.array(np.arange(n + 1, dtype=np.int32) * width, pa.int32())
    return pa.ListArray.from_arrays(offsets, pa.array(rows.reshape(-1), value_type))


def _quaternions_wxyz(rotations: list[np.ndarray]) -> np.ndarray:
    """Unit quaternions (w, x, y, z), w >= 0, of a list of rotation matrices."""
    if not rotations:
        return np.zeros((0, 4))
    xyzw = Rotation.from_matrix(np.stack(rotations)).as_quat()
    wxyz = np.roll(xyzw, 1, axis=1)
    return np.where(wxyz[:, :1] < 0, -wxyz, wxyz)
