"""One LiDAR frame of a run: the scan, a ground-truth label per beam, and the robot's truth.

A frame is what every consumer of the simulator receives: the filter in the loop, scan
matchers, the Rerun logger, data-set writers, the Gymnasium env. Arrays are read-only so
a frame can be handed to several consumers (and threads) without copies.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from pvfilter import Scan
from twsb_sim.sensors.readings import Attitude, SensorReadings


def _frozen(array: np.ndarray, dtype: type) -> np.ndarray:
    """A read-only array of ``dtype``: ``array`` itself when nothing can change it any more
    (read-only, and so is the array it views: the simulator's own frame arrays), else a
    read-only copy."""
    if (
        isinstance(array, np.ndarray)
        and array.dtype == dtype
        and not array.flags.writeable
        and (
            array.base is None
            or (isinstance(array.base, np.ndarray) and not array.base.flags.writeable)
        )
    ):
        return array
    array = np.array(array, dtype=dtype)
    array.flags.writeable = False
    return array


@dataclass(frozen=True, eq=False, kw_only=True)
class RobotTruth:
    """The robot's true state at the scan's stamp (world frame: REP-103, z up).

    The base frame's origin is the wheel-axle centre. Positive pitch is nose down. The
    ``imu_*`` fields are the exact readings (no sensor errors); what the robot's IMU and
    estimator reported is in :attr:`Frame.sensors`.
    """

    stamp_s: float  # s, simulated time
    position_base_in_world: np.ndarray  # m, (3,)
    quat_base_in_world: np.ndarray  # (w, x, y, z)
    yaw_rad: float
    pitch_rad: float  # positive = nose down
    roll_rad: float
    pitch_rate_rad_s: float
    forward_velocity_mps: float  # along the heading, horizontal
    yaw_rate_rad_s: float
    wheel_speeds_rad_s: np.ndarray  # (left, right)
    wheel_torques_nm: np.ndarray  # (left, right), as applied (saturated)
    command_velocity_mps: float
    command_yaw_rate_rad_s: float
    shove_active: bool
    position_sensor_in_world: np.ndarray  # m, (3,), the LiDAR's origin
    rotation_sensor_to_world: np.ndarray  # (3, 3)
    imu_gyro_rad_s: np.ndarray  # (3,), IMU frame
    imu_accel_mps2: np.ndarray  # (3,), IMU frame, specific force (gravity included)
    imu_quat: np.ndarray  # (w, x, y, z), IMU frame orientation in the world

    def __post_init__(self) -> None:
        for name in _TRUTH_ARRAYS:  # a frame's worth of truths is built every scan
            value = getattr(self, name)
            if isinstance(value, np.ndarray):
                object.__setattr__(self, name, _frozen(value, np.float64))


_TRUTH_ARRAYS = tuple(f.name for f in dataclasses.fields(RobotTruth) if "ndarray" in str(f.type))


@dataclass(frozen=True, eq=False, kw_only=True)
class Frame:
    """One scan with its ground truth.

    Attributes:
        index: frame number in the run, from 0.
        scan: the simulated scan (REP-117 ranges, LaserScan fields, stamp in s).
        labels: ``uint8[n]`` :class:`~twsb_sim.labels.BeamLabel` per beam.
        hit_points_world: ``float64[n, 3]`` where each beam really hit (m, world frame),
            NaN where it hit nothing within range; noise-free.
        truth: the robot's state.
        phase: the scenario phase in force ("hard stop", ...), "" when none.
        geom_ids: ``int32[n]``, the MuJoCo geom each beam hit, -1 where none (ids of the
            run's compiled model; ``mujoco.mj_id2name`` names them); None when unknown.
        sensors: what the robot's IMU, attitude filter and wheel odometry reported (see
            :class:`~twsb_sim.sensors.SensorReadings`); None for frames made without them.

    Beam ``i`` was measured at ``scan.stamp + i * scan.time_increment``.
    """

    index: int
    scan: Scan
    labels: np.ndarray
    hit_points_world: np.ndarray
    truth: RobotTruth
    phase: str = ""
    geom_ids: np.ndarray | None = None
    sensors: SensorReadings | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "labels", _frozen(self.labels, np.uint8))
        if self.geom_ids is not None:
            object.__setattr__(self, "geom_ids", _frozen(self.geom_ids, np.int32))
        object.__setattr__(self, "hit_points_world", _frozen(self.hit_points_world, np.float64))
        if self.labels.shape != self.scan.ranges.shape:
            raise ValueError(
                f"labels: need one per beam ({len(self.scan)}), got {self.labels.shape}"
            )

    @property
    def stamp_s(self) -> float:
        return self.scan.stamp

    @property
    def received_s(self) -> float:
        """When the scan was complete and handed out, s: the end of its revolution
        (``stamp + scan_time`` for a counter-clockwise scanner, whose beam 0 comes first;
        the stamp itself for a clockwise or an instant one)."""
        return self.scan.stamp + max(0.0, len(self.scan) * self.scan.time_increment)

    @property
    def beam_times_s(self) -> np.ndarray:
        """When each beam was measured, s: ``stamp + i * time_increment``."""
        return self.scan.stamp + np.arange(len(self.scan)) * self.scan.time_increment

    @property
    def attitude_estimate(self) -> Attitude:
        """Pitch and roll (rad; + nose down, + left side up) as the robot's own attitude
        filter had them at the scan's stamp, from its noisy IMU, lag included: what an
        IMU-using filter receives (``method.process(frame.scan, *frame.attitude_estimate)``).

        Raises:
            ValueError: the frame was made without the sensor models.
        """
        return self._require_sensors("attitude_estimate").attitude

    @property
    def lidar_pose_in_odom(self) -> np.ndarray:
        """The LiDAR's pose in the ``odom`` frame at the stamp from wheel odometry:
        ``(x m, y m, yaw rad)``, the filters' odometry input.

        Raises:
            ValueError: the frame was made without the sensor models.
        """
        return self._require_sensors("lidar_pose_in_odom").pose_lidar_in_odom

    def _require_sensors(self, what: str) -> SensorReadings:
        if self.sensors is None:
            raise ValueError(
                f"{what}: this frame carries no sensor readings (made without the sensor models)"
            )
        return self.sensors


def truth_arrays(truths: list[RobotTruth]) -> dict[str, np.ndarray]:
    """Stack the truth of many frames into one array per field (for files and tables)."""
    if not truths:
        return {}
    return {
        f.name: np.stack([np.asarray(getattr(t, f.name)) for t in truths])
        for f in dataclasses.fields(RobotTruth)
    }
