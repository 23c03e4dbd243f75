"""Writes a run's frames to a folder that numpy alone can read.

``twsb run ... --out DIR`` leaves:

- ``DIR/frames.npz``: one array per quantity, frames stacked along axis 0 (see
  :data:`FRAME_ARRAYS`), plus the LaserScan intrinsics as scalars; the same layout the
  ``pvfilter`` command reads, so a run can be re-filtered offline.
- ``DIR/summary.json``: the run summary (:class:`~twsb_sim.summary.RunSummary`).
- ``DIR/scenario.toml``: a copy of the scenario file that was run.

Files appear atomically (written to a temporary name, then renamed), and they are also
written when the run ends early (a fall, Ctrl-C), so no simulated frame is lost.
"""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path
from typing import Any

import numpy as np

from pvfilter import ROBOT_INPUTS
from pvfilter.io import PER_SCAN_KEYS
from twsb_sim.frame import Frame, truth_arrays
from twsb_sim.robot_inputs import robot_inputs
from twsb_sim.summary import RunSummary

FRAME_ARRAYS = {
    "stamps": "float64[K], s, stamp of each scan",
    "ranges": "float64[K, n], m, REP-117 (+inf no return, -inf closer than range_min)",
    "labels": "uint8[K, n], ground-truth BeamLabel per beam",
    "hit_points_world": "float32[K, n, 3], m, noise-free hit points, NaN where no return",
    "removed": "bool[K, n], beams the filter in the loop removed (only when a filter ran)",
    "truth_<field>": "one array per RobotTruth field, e.g. truth_pitch_rad float64[K]",
    "sensor_<field>": "the robot's sensors at each stamp: sensor_attitude_rpy_rad [K, 3], "
    "sensor_pose_base_in_odom [K, 3], sensor_pose_lidar_in_odom [K, 3], sensor_twist [K, 2]",
    "pitch_rad, roll_rad, pose_sensor_in_odom": "the robot inputs a filter receives, under the "
    "names the pvfilter command reads: float64[K] attitude estimate (rad), float64[K, 3] LiDAR "
    "pose from the wheel odometry (x m, y m, yaw rad)",
    "imu_samples": "float64[N, 10]: arrival s, gyro xyz rad/s, accel xyz m/s², estimate rpy rad",
    "odometry_samples": "float64[M, 6]: stamp s, x m, y m, yaw rad (odom), v m/s, w rad/s",
    "imu_samples_per_frame, odometry_samples_per_frame": "int64[K]: how many arrived per frame",
    "angle_min, angle_increment, range_min, range_max, time_increment, scan_time": "scalars; "
    "beam i of a scan was measured at stamps + i * time_increment",
    "lidar_height_m, axle_height_m, lidar_ahead_m": "scalars, m: the scenario robot's geometry, "
    "as filters take it (the pvfilter command tells them it)",
}
_SENSOR_FIELDS = ("attitude_rpy_rad", "pose_base_in_odom", "pose_lidar_in_odom", "twist")


def _atomic_write(path: Path, write: Any) -> None:
    temporary = path.with_name(f".{path.name}.partial")
    write(temporary)
    os.replace(temporary, path)


class FrameWriter:
    """A sink that keeps every frame and writes the run folder when the run ends."""

    def __init__(
        self,
        out_dir: str | Path,
        scenario_file: str | Path | None = None,
        robot_geometry: dict[str, float] | None = None,
    ) -> None:
        self.out_dir = Path(out_dir)
        self.scenario_file = Path(scenario_file) if scenario_file else None
        self.robot_geometry = dict(robot_geometry or {})  # written beside the scans, m
        self._frames: list[Frame] = []
        self._removed: list[np.ndarray] = []

    def on_frame(self, frame: Frame, filter_result: Any | None) -> None:
        self._frames.append(frame)
        if filter_result is not None:
            self._removed.append(np.asarray(filter_result.removed, dtype=bool))

    def on_event(self, t_s: float, text: str) -> None:
        pass

    def close(self, summary: RunSummary) -> None:
        self.out_dir.mkdir(parents=True, exist_ok=True)
        arrays = self.arrays()
        _atomic_write(self.out_dir / "frames.npz", lambda p: _save_npz(p, arrays))
        text = json.dumps(summary.to_dict(), indent=2, default=float)
        _atomic_write(self.out_dir / "summary.json", lambda p: p.write_text(text + "\n"))
        if self.scenario_file and self.scenario_file.is_file():
            _atomic_write(
                self.out_dir / "scenario.toml", lambda p: shutil.copyfile(self.scenario_file, p)
            )

    def arrays(self) -> dict[str, np.ndarray]:
        """The frames so far, stacked as they are written to ``frames.npz``."""
        if not self._frames:
            return {}
        scan = self._frames[0].scan
        arrays: dict[str, np.ndarray] = {
            "stamps": np.array([f.scan.stamp for f in self._frames]),
            "ranges": np.stack([f.scan.ranges for f in self._frames]),
            "labels": np.stack([f.labels for f in self._frames]),
            "hit_points_world": np.stack([f.hit_points_world for f in self._frames]).astype(
                np.float32
            ),
            "phases": np.array([f.phase for f in self._frames]),
        }
        for name in PER_SCAN_KEYS:  # the LaserScan intrinsics, as the pvfilter command reads them
            arrays[name] = np.float64(getattr(scan, name))
        for name, value in self.robot_geometry.items():  # so offline runs see the same robot
            arrays[name] = np.float64(value)
        if self._removed:
            arrays["removed"] = np.stack(self._removed)
        for name, values in truth_arrays([f.truth for f in self._frames]).items():
            arrays[f"truth_{name}"] = values
        with_sensors = [f.sensors for f in self._frames if f.sensors is not None]
        if len(with_sensors) == len(self._frames):
            for name in _SENSOR_FIELDS:
                arrays[f"sensor_{name}"] = np.stack([getattr(r, name) for r in with_sensors])
            imu = [np.column_stack((r.imu.stamps_s, r.imu.gyro_rad_s, r.imu.accel_mps2,
                                    r.imu.rpy_rad)) for r in with_sensors]  # fmt: skip
            odom = [np.column_stack((r.odometry.stamps_s, r.odometry.pose_odom,
                                     r.odometry.twist)) for r in with_sensors]  # fmt: skip
            inputs = [robot_inputs(f, ROBOT_INPUTS) for f in self._frames]
            for name in ROBOT_INPUTS:  # so `pvfilter frames.npz` runs any filter on them
                arrays[name] = np.array([i[name] for i in inputs], dtype=np.float64)
            arrays["imu_samples"] = np.vstack(imu)
            arrays["imu_samples_per_frame"] = np.array([len(b) for b in imu])
            arrays["odometry_samples"] = np.vstack(odom)
            arrays["odometry_samples_per_frame"] = np.array([len(b) for b in odom])
        return arrays


def _save_npz(path: Path, arrays: dict[str, np.ndarray]) -> None:
    with open(path, "wb") as file:
        np.savez_compressed(file, **arrays)
