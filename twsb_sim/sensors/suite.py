"""The robot's sensors fed from every physics step: IMU, attitude estimate, wheel odometry,
and the LiDAR site's pose history for the rotating scan.

The physics loop does one thing per step for all of them: it copies ``data.sensordata``
(19 numbers: gyro, accelerometer, the LiDAR site's pose, the wheel angles) into
:attr:`SensorSuite.rows`. After ``mj_step`` that row describes the state at the start of
the step, so row ``i`` is the state at ``t_first + i * dt``. Everything else happens in
:meth:`SensorSuite.sync`, called when a frame or an observation needs it: IMU and
odometry samples at their own rates (interpolated between steps), the IMU's errors, the
attitude filter and dead reckoning, all on whole batches.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from twsb_sim.kernel import kernel
from twsb_sim.robot import ENCODER_SENSORS, IMU_SENSORS, LIDAR_POSE_SENSORS, RobotHandles
from twsb_sim.sensors.attitude import AttitudeFilterConfig, ComplementaryFilter
from twsb_sim.sensors.imu import STANDARD_GRAVITY_MPS2, ImuConfig, ImuModel
from twsb_sim.sensors.odometry import EncoderOdometry, OdometryConfig
from twsb_sim.sensors.readings import ImuSamples, OdometrySamples, SensorReadings
from twsb_sim.sensors.sweep import PoseTrack

ROW_CAPACITY = 2048  # physics steps buffered before a sync is forced (4 s at 500 Hz)
LOOKUP_HISTORY_S = 1.0  # s of estimates and odometry kept for look-ups at past stamps
_EPS = 1e-9


def _columns(model: mujoco.MjModel, names: tuple[str, ...]) -> slice:
    """The sensordata columns of consecutive sensors, as a slice (cheap to gather)."""
    start = int(model.sensor(names[0]).adr[0])
    stop = int(model.sensor(names[-1]).adr[0] + model.sensor(names[-1]).dim[0])
    if stop - start != sum(int(model.sensor(n).dim[0]) for n in names):
        raise ValueError(f"sensors: expected {', '.join(names)} one after the other")
    return slice(start, stop)


class SensorSuite:
    """IMU, attitude filter, encoder odometry and LiDAR pose history of one simulation.

    Args:
        model: the compiled model (robot with its named sensors).
        handles: the robot's addresses in it.
        imu, attitude, odometry: the sensors' configurations.
        sweep_s: how much pose history the LiDAR needs (its scan time), s.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        handles: RobotHandles,
        imu: ImuConfig,
        attitude: AttitudeFilterConfig,
        odometry: OdometryConfig,
        sweep_s: float,
    ) -> None:
        self.imu_config, self.attitude_config, self.odometry_config = imu, attitude, odometry
        self.handles = handles
        self.dt_s = float(model.opt.timestep)
        self._imu_cols = _columns(model, IMU_SENSORS[:2])  # gyro, then accelerometer
        self._pos_cols, self._quat_cols = (_columns(model, (n,)) for n in LIDAR_POSE_SENSORS)
        self._wheel_cols = _columns(model, ENCODER_SENSORS)
        self.keep_rows = math.ceil(sweep_s / self.dt_s) + 2
        steps = (self.dt_s * imu.rate_hz, self.dt_s * odometry.rate_hz)  # steps per sample
        self._imu_on_steps, self._odom_on_steps = (abs(1 / x - round(1 / x)) < 1e-9 for x in steps)
        self.rows = np.zeros((max(ROW_CAPACITY, 2 * self.keep_rows), model.nsensordata))
        self.count = 0  # rows filled
        self.t_first = 0.0  # s, the time of row 0

    # -- the run ---------------------------------------------------------------------------

    def reset(self, data: mujoco.MjData, seed: np.random.SeedSequence) -> None:
        """Start over at ``data``'s state (kinematics current): new errors, odom at origin."""
        self.count, self.t_first, self.t0 = 0, float(data.time), float(data.time)
        self.imu = ImuModel(self.imu_config, np.random.default_rng(seed))
        self.filter = ComplementaryFilter(self.attitude_config, 1.0 / self.imu_config.rate_hz)
        h = self.handles
        self.odometry = EncoderOdometry(self.odometry_config, h.wheel_radius_m, h.track_width_m)
        self.odometry.reset(data.sensordata[self._wheel_cols])
        base = data.body(h.base_body_id)
        offset = base.xmat.reshape(3, 3).T @ (data.site_xpos[h.lidar_site_id] - base.xpos)
        self.lidar_offset_xy = offset[:2].copy()  # m, the LiDAR in base_footprint
        self._lidar_offset = tuple(self.lidar_offset_xy.tolist())
        self._next_imu = self._next_odom = 0  # sample numbers since the reset
        self._imu = [np.zeros((0, 10))]  # pending: arrival s, gyro, accel, roll pitch yaw
        self._odom = [np.zeros((0, 6))]  # pending: stamp s, x, y, yaw, v, w
        self._recent_imu = np.zeros((0, 10))  # look-ups: arrival s, gyro, accel, roll pitch yaw
        self._poses = np.zeros((0, 6))  # look-up history: stamp s, x, y, yaw, v, w

    def flush_full(self) -> None:
        """Called by the physics loop when :attr:`rows` is full: process, keep the tail."""
        self.sync()

    def row_times(self) -> np.ndarray:
        return self.t_first + np.arange(self.count) * self.dt_s

    def sync(self) -> None:
        """Turn the recorded steps into IMU and odometry samples; keep the sweep's tail."""
        if not self.count:
            return
        last = self.t_first + (self.count - 1) * self.dt_s
        imu_period, odom_period = 1.0 / self.imu_config.rate_hz, 1.0 / self.odometry_config.rate_hz
        n_imu = self._samples_due(self._next_imu, imu_period, last)
        if n_imu:
            imu_times, true = self._samples(
                self._next_imu, n_imu, imu_period, self._imu_cols, self._imu_on_steps
            )
            self._next_imu += n_imu
            readings = self.imu.measure(true)
            # arrival s, gyro, accel, roll pitch yaw
            block = _rows(
                imu_times, self.imu_config.latency_s, readings, self.filter.update(readings)
            )
            self._imu.append(block)
            self._recent_imu = np.concatenate((self._recent_imu, block))
        n_odom = self._samples_due(self._next_odom, odom_period, last)
        if n_odom:
            odom_times, wheels = self._samples(
                self._next_odom, n_odom, odom_period, self._wheel_cols, self._odom_on_steps
            )
            self._next_odom += n_odom
            poses, twists = self.odometry.update(wheels)
            block = _rows(odom_times, 0.0, poses, twists)  # stamp s, x, y, yaw, v, w
            self._odom.append(block)
            self._poses = np.concatenate((self._poses, block))
        drop = self.count - self.keep_rows
        if drop > 0:  # keep one revolution of poses (and the last row, for interpolation)
            self.rows[: self.keep_rows] = self.rows[drop : self.count]
            self.count = self.keep_rows
            self.t_first += drop * self.dt_s

    def _samples_due(self, next_index: int, period: float, last: float) -> int:
        """How many samples, from number ``next_index`` on, were taken by ``last``."""
        stop = math.floor((last - self.t0) / period + _EPS) + 1
        return max(stop, next_index) - next_index

    def _samples(
        self, first: int, n: int, period: float, columns: slice, on_steps: bool
    ) -> tuple[np.ndarray, np.ndarray]:
        """The times of samples ``first`` to ``first + n - 1`` and the recorded columns
        at them (within the recorded span), linearly interpolated; ``on_steps``: every
        sample falls on a physics step (the rate divides the physics'), whose row it takes."""
        return _samples(
            self.rows, self.count, self.t_first, self.dt_s, self.t0, period, first, n,
            columns.start, columns.stop, on_steps,
        )  # fmt: skip

    # -- what consumers get ----------------------------------------------------------------

    def pose_track(self, data: mujoco.MjData) -> PoseTrack:
        """The LiDAR site's poses: the recorded steps, then ``data``'s current state (its
        kinematics current), which follows the last recorded step by one step."""
        n, now = self.count, float(data.time)
        if n and abs(now - (self.t_first + n * self.dt_s)) > _EPS:  # not the next step
            samples = self.rows[:n]
        else:
            if n == len(self.rows):
                self.sync()
                n = self.count
            # the next step records this same state again: the free row holds it till then
            self.rows[n] = data.sensordata
            samples = self.rows[: n + 1]
        t_first = self.t_first if n else now
        return PoseTrack.from_quats(
            t_first, self.dt_s, samples[:, self._pos_cols], samples[:, self._quat_cols]
        )

    def readings(self, stamp_s: float, now_s: float) -> SensorReadings:
        """The streams that reached the robot by ``now_s`` since the last call, and the
        look-ups at ``stamp_s`` (call :meth:`sync` first)."""
        imu = np.concatenate(self._imu) if len(self._imu) > 1 else self._imu[0]
        n_arrived = int(np.searchsorted(imu[:, 0], now_s + _EPS, side="right"))
        self._imu = [imu[n_arrived:]]
        imu = imu[:n_arrived].copy()  # handed out read-only: the views below share it
        imu.flags.writeable = False
        odom = np.concatenate(self._odom) if len(self._odom) > 1 else self._odom[0].copy()
        odom.flags.writeable = False
        self._odom = [np.zeros((0, 6))]
        base = self.pose_at(stamp_s)
        x, y, yaw = base.tolist()  # floats: numpy scalars cost ~10x per operation
        c, s = math.cos(yaw), math.sin(yaw)
        dx, dy = self._lidar_offset
        lidar = np.array([x + c * dx - s * dy, y + s * dx + c * dy, yaw])
        attitude, twist = self.attitude_at(stamp_s), self.twist_at(stamp_s)
        for array in (base, lidar, attitude, twist):
            array.flags.writeable = False  # made for these readings: kept, not copied again
        readings = SensorReadings(
            imu=ImuSamples(
                stamps_s=imu[:, 0],
                gyro_rad_s=imu[:, 1:4],
                accel_mps2=imu[:, 4:7],
                rpy_rad=imu[:, 7:10],
            ),
            odometry=OdometrySamples(
                stamps_s=odom[:, 0], pose_odom=odom[:, 1:4], twist=odom[:, 4:6]
            ),
            attitude_rpy_rad=attitude,
            pose_base_in_odom=base,
            pose_lidar_in_odom=lidar,
            twist=twist,
        )
        old = min(stamp_s, now_s) - LOOKUP_HISTORY_S  # both are in time order
        self._recent_imu = self._recent_imu[np.searchsorted(self._recent_imu[:, 0], old) :]
        self._poses = self._poses[np.searchsorted(self._poses[:, 0], old) :]
        return readings

    def attitude_at(self, t_s: float) -> np.ndarray:
        """Roll, pitch, yaw (rad) the estimator had at ``t_s``: its output after the last
        sample that had arrived; level (zeros) before the first one."""
        arrived = np.searchsorted(self._recent_imu[:, 0], t_s + _EPS, side="right")
        return self._recent_imu[arrived - 1, 7:10].copy() if arrived else np.zeros(3)

    def pose_at(self, t_s: float) -> np.ndarray:
        """x, y, yaw of base_footprint in odom at ``t_s``, between odometry updates as
        ``tf`` interpolates them (the origin before the first update, the last after)."""
        poses = self._poses
        j = np.searchsorted(poses[:, 0], t_s + _EPS, side="right")
        if j == 0:
            return np.zeros(3)
        if j == len(poses) or abs(poses[j - 1, 0] - t_s) <= _EPS:
            return poses[j - 1, 1:4].copy()
        (t0, *p0), (t1, *p1) = poses[j - 1, :4].tolist(), poses[j, :4].tolist()
        a = (t_s - t0) / (t1 - t0)
        turn = math.remainder(p1[2] - p0[2], math.tau)
        return np.array(
            [p0[0] + a * (p1[0] - p0[0]), p0[1] + a * (p1[1] - p0[1]),
             math.remainder(p0[2] + a * turn, math.tau)]
        )  # fmt: skip

    def twist_at(self, t_s: float) -> np.ndarray:
        """Forward speed (m/s) and yaw rate (rad/s) of the last update at or before ``t_s``."""
        j = np.searchsorted(self._poses[:, 0], t_s + _EPS, side="right")
        return self._poses[j - 1, 4:6].copy() if j else np.zeros(2)

    def latest_imu(self, t_s: float) -> np.ndarray:
        """The last IMU reading (gyro, accel; ``(6,)``) that had arrived by ``t_s``; the
        state at reset (no rotation, 1 g up) before the first one."""
        arrived = np.searchsorted(self._recent_imu[:, 0], t_s + _EPS, side="right")
        if arrived:
            return self._recent_imu[arrived - 1, 1:7].copy()
        return np.array([0.0, 0.0, 0.0, 0.0, 0.0, STANDARD_GRAVITY_MPS2])


@kernel
def _samples(
    rows: np.ndarray,
    count: int,
    t_first: float,
    dt: float,
    t0: float,
    period: float,
    first: int,
    n: int,
    start: int,
    stop: int,
    on_steps: bool,
) -> tuple[np.ndarray, np.ndarray]:
    """Sample times ``t0 + (first + j) period`` and ``rows[:count, start:stop]`` at them
    (rows ``dt`` apart from ``t_first``), linearly interpolated, or the nearest row when
    every sample falls on a row (``on_steps``)."""
    times = np.empty(n)
    values = np.empty((n, stop - start))
    for j in range(n):
        times[j] = t0 + float(first + j) * period
        if count == 1:
            values[j] = rows[0, start:stop]
            continue
        position = (times[j] - t_first) / dt
        if on_steps:
            values[j] = rows[int(np.rint(position)), start:stop]
            continue
        i = min(max(int(np.floor(position + _EPS)), 0), count - 2)
        a = np.minimum(np.maximum(position - i, 0.0), 1.0)
        for c in range(stop - start):
            before = rows[i, start + c]
            values[j, c] = before + a * (rows[i + 1, start + c] - before)
    return times, values


@kernel
def _rows(times: np.ndarray, delay: float, first: np.ndarray, second: np.ndarray) -> np.ndarray:
    """``(k, 1 + a + b)`` rows: ``times + delay``, the ``(k, a)`` then the ``(k, b)`` values."""
    a, b = first.shape[1], second.shape[1]
    out = np.empty((len(times), 1 + a + b))
    for r in range(len(times)):
        out[r, 0] = times[r] + delay
        out[r, 1 : 1 + a] = first[r]
        out[r, 1 + a :] = second[r]
    return out
