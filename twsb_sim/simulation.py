"""One robot in one house: physics, balance control and the sensors, step by step.

:class:`Simulation` knows nothing of scenario files: it is the engine that the scenario
runner, the Gymnasium env and the data-set generator all drive. Each physics step runs
the LQR balance controller (or applies raw wheel torques) and records the sensors' raw
state (:class:`~twsb_sim.sensors.SensorSuite`); :meth:`Simulation.frame` hands out the
LiDAR revolution that has just ended, cast beam by beam from the sensor's poses during
it, with the robot's truth at the scan's stamp and what its IMU and encoders reported.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import mujoco
import numpy as np

from pvfilter import Scan
from twsb_sim.collision_region import CollisionRegion, RegionGuard, confine_collisions
from twsb_sim.control.balance import BalanceConfig, bound_control, make_balance_controller
from twsb_sim.control.lqr import LqrConfig
from twsb_sim.frame import Frame, RobotTruth
from twsb_sim.house import House, SpawnPose, add_house_to_spec
from twsb_sim.kernel import kernel
from twsb_sim.level_view import LevelView
from twsb_sim.lidar import Lidar, LidarConfig
from twsb_sim.movers import MoverSet
from twsb_sim.robot import (
    LIDAR_POSE_SENSORS,
    RobotConfig,
    RobotHandles,
    load_robot_spec,
    set_pose,
)
from twsb_sim.sensors import (
    AttitudeFilterConfig,
    ImuConfig,
    OdometryConfig,
    SensorSuite,
)

# MuJoCo's answer to a diverging simulation: it warns, then resets the state (time 0, the
# model's origin), and stepping goes on as if nothing happened
DIVERGENCE_WARNINGS = ("BADQACC", "BADQVEL", "BADQPOS")
_DIVERGENCE_INDICES = sorted(  # in MuJoCo's order, as mujoco_warnings() lists them
    ((name, int(getattr(mujoco.mjtWarning, f"mjWARN_{name}"))) for name in DIVERGENCE_WARNINGS),
    key=lambda item: item[1],
)


@dataclass(frozen=True)
class Shove:
    """A force acting now: world-frame force at a point fixed in the body frame."""

    force_world_n: np.ndarray  # N, (3,)
    point_body_m: np.ndarray  # m, (3,), body frame (origin at the axle)


@kernel
def _all_finite(first: np.ndarray, second: np.ndarray) -> bool:
    """Whether every value of both arrays is finite."""
    for value in first:
        if not math.isfinite(value):
            return False
    for value in second:
        if not math.isfinite(value):
            return False
    return True


def build_model(
    house: House,
    robot: RobotConfig,
    movers: MoverSet | None = None,
    collision_region: CollisionRegion | None = None,
) -> mujoco.MjModel:
    """Compile the robot into the house, with the movers (people, doors, ...) if any.

    With a ``collision_region``, the house's geoms the robot cannot reach from it are
    compiled without contacts (:func:`~twsb_sim.collision_region.confine_collisions`).
    """
    return _build(house, robot, movers, collision_region)[0]


def _build(
    house: House,
    robot: RobotConfig,
    movers: MoverSet | None,
    collision_region: CollisionRegion | None,
) -> tuple[mujoco.MjModel, list[str]]:
    """The compiled model, and the geoms taken out of collision for the region."""
    spec = load_robot_spec(robot)
    add_house_to_spec(spec, house)
    if movers:
        movers.add_to_spec(spec)
    skip_static_geom_poses(spec)
    confined = confine_collisions(spec, collision_region) if collision_region else []
    return spec.compile(), confined


def skip_static_geom_poses(spec: mujoco.MjSpec) -> None:
    """Let ``mj_step`` skip the world poses of geoms that never move, and nothing else.

    MuJoCo recomputes every geom's world pose at each step, the house's hundred-odd
    static ones included. With sleeping enabled, the geoms of static bodies are posed
    when the data is made or reset (``mj_resetData``) and the kinematics leaves them as
    they are; every body that can move is told never to sleep, so each of them is
    simulated as before and the trajectories are the same to the bit. Measured on
    generated episodes: about 1.4 us less per step (the kinematics stage from about 2.2
    to 0.8 us). A static geom moved in the model afterwards needs ``mj_resetData``.
    """
    spec.option.enableflags |= mujoco.mjtEnableBit.mjENBL_SLEEP
    for body in spec.worldbody.bodies:  # the roots of the trees: the robot, free furniture
        if body.joints:  # mocap bodies (people, doors) have none and take no sleep policy
            body.sleep = mujoco.mjtSleepPolicy.mjSLEEP_NEVER


class Simulation:
    """A TWSB robot balancing in a house, with a LiDAR.

    Args:
        house: the house to build.
        robot, lidar, controller: parameters of each subsystem.
        fall_pitch_deg: |pitch| beyond which the robot counts as fallen.
        seed: seeds the sensors' errors (``SeedSequence`` children: the LiDAR's, then the
            IMU's); the physics itself is deterministic.
        imu, attitude, odometry: the IMU, the robot's attitude filter, its wheel odometry.
        movers: people, pets, doors and light furniture in the house (none by default);
            the kinematic ones are posed whenever the LiDAR casts.
        balance: the balance controller (the LQR by default) and its stop brake.
        start: where the robot starts, a spawn pose or ``(x_m, y_m, yaw_rad)`` (default:
            the house's first spawn pose).
        collision_region: where the LiDAR origin will stay for the whole run: the house's
            geoms the robot cannot reach from there are compiled without contacts, a
            cheaper physics step with the same trajectory (:mod:`twsb_sim.collision_region`);
            every step then checks that the robot is still inside, and raises
            :class:`~twsb_sim.collision_region.LeftCollisionRegion` when it is not (the
            run must be done again without a region). Ignored when a body other than
            the robot moves and collides (free furniture).
    """

    def __init__(
        self,
        house: House,
        robot: RobotConfig = RobotConfig(),  # noqa: B008
        lidar: LidarConfig = LidarConfig(),  # noqa: B008
        controller: LqrConfig = LqrConfig(),  # noqa: B008
        fall_pitch_deg: float = 45.0,
        seed: int = 0,
        imu: ImuConfig = ImuConfig(),  # noqa: B008
        attitude: AttitudeFilterConfig = AttitudeFilterConfig(),  # noqa: B008
        odometry: OdometryConfig = OdometryConfig(),  # noqa: B008
        movers: MoverSet | None = None,
        balance: BalanceConfig | None = None,
        start: SpawnPose | tuple[float, float, float] | None = None,
        collision_region: CollisionRegion | None = None,
    ) -> None:
        self.house = house
        self.robot_config = robot
        self.movers = movers if movers is not None else MoverSet()
        self.model, confined = _build(house, robot, self.movers, collision_region)
        # the geoms out of collision hold only while the robot stays in the region
        self.region_guard = RegionGuard(collision_region) if confined else None
        self.movers.bind(self.model)
        self.data = mujoco.MjData(self.model)
        # views into data, made once (reset keeps its buffers): checked at every breakpoint
        self._warning_counts = self.data.warning.number
        self._qpos, self._qvel = self.data.qpos, self.data.qvel
        self.handles = RobotHandles(self.model)
        self.lidar = Lidar(self.model, lidar)
        self.sensors = SensorSuite(
            self.model, self.handles, imu, attitude, odometry, self.lidar.scan_time
        )
        adr = int(self.model.sensor(LIDAR_POSE_SENSORS[0]).adr[0])
        self._lidar_position_cols = slice(adr, adr + 3)  # of the sensor rows
        self.level_view = LevelView(self.model, self.lidar)  # labels on ramps and slopes
        self.controller = make_balance_controller(self.model, robot, controller, balance)
        self.fall_pitch_rad = math.radians(fall_pitch_deg)
        self.dt_s = float(self.model.opt.timestep)
        self._seed = seed
        if start is None:  # the spawn search runs only here, when no start is given
            start = house.spawn_poses[0] if house.spawn_poses else (0.0, 0.0, 0.0)
        self.reset(start, seed)

    # -- state ---------------------------------------------------------------------------

    def reset(self, pose: SpawnPose | tuple[float, float, float], seed: int | None = None) -> None:
        """Put the robot upright and still at ``pose`` (x m, y m, yaw rad); time 0.

        Args:
            pose: a spawn pose of the house, or ``(x_m, y_m, yaw_rad)``.
            seed: a new seed for the sensors' errors (default: the last one).
        """
        if seed is not None:
            self._seed = seed
        x, y, yaw = (pose.x_m, pose.y_m, pose.yaw_rad) if isinstance(pose, SpawnPose) else pose
        mujoco.mj_resetData(self.model, self.data)
        self.movers.pose(self.data, 0.0)
        set_pose(self.model, self.data, x, y, yaw)
        self.controller.reset()
        lidar_seed, sensors_seed = np.random.SeedSequence(self._seed).spawn(2)
        self.noise_rng = np.random.default_rng(lidar_seed)
        self.sensors.reset(self.data, sensors_seed)
        if self.region_guard is not None:
            self.region_guard.check(self.data.site_xpos[self.handles.lidar_site_id][None, :])
        self.command = (0.0, 0.0)
        self.max_abs_pitch_rad = 0.0  # over every physics step since reset
        self._shove: Shove | None = None
        # the truth at the start of the revolution in progress; before the reset the
        # robot stood still where it is now
        self._sweep_start_truth = self.truth()
        self._sweep_start_is_reset = True

    @property
    def time_s(self) -> float:
        return float(self.data.time)

    def pitch_rad(self) -> float:
        """Current pitch (positive = nose down)."""
        return self.handles.read_balance_state(self.data).pitch_rad

    def mujoco_warnings(self) -> dict[str, int]:
        """MuJoCo's warnings since the last reset, by name (empty when all is well)."""
        counts = self._warning_counts  # one array read: the per-item loop costs 0.2 ms
        return {
            mujoco.mjtWarning(i).name.removeprefix("mjWARN_"): int(counts[i])
            for i in np.flatnonzero(counts)
        }

    def divergence(self) -> str | None:
        """Why the physics can no longer be trusted (None while it can): MuJoCo met a NaN,
        an infinity or a huge value and reset the state, or a coordinate is not finite."""
        counts = self._warning_counts
        for name, index in _DIVERGENCE_INDICES:
            if counts[index]:
                return f"MuJoCo met a NaN, infinity or huge value ({name}) and reset the state"
        if not _all_finite(self._qpos, self._qvel):  # a compiled loop: checked every frame
            return "a position or velocity is not finite"
        return None

    def fall_reason(self) -> str | None:
        """Why the robot counts as fallen now (None while it is up).

        Tipping over forward or back (|pitch|) and onto its side (|roll|, after a push from
        the side) both count, against the same limit.
        """
        state = self.handles.read_balance_state(self.data)
        limit_deg = math.degrees(self.fall_pitch_rad)
        for name, angle in (("pitch", state.pitch_rad), ("roll", state.roll_rad)):
            if abs(angle) > self.fall_pitch_rad:
                return f"|{name}| {abs(math.degrees(angle)):.1f} deg > {limit_deg:g} deg"
        return None

    def has_fallen(self) -> bool:
        return self.fall_reason() is not None

    # -- stepping ------------------------------------------------------------------------

    def step(self, velocity_mps: float, yaw_rate_rad_s: float, n_steps: int = 1) -> None:
        """Advance ``n_steps`` physics steps with the LQR tracking one command."""
        self.run_commands(np.full(n_steps, velocity_mps), np.full(n_steps, yaw_rate_rad_s))

    def run_commands(self, velocities_mps: np.ndarray, yaw_rates_rad_s: np.ndarray) -> None:
        """Advance one physics step per command pair, the LQR tracking each in turn.

        This is the hot loop: per step only the controller, ``mj_step`` and one copy of
        the sensor data run.
        """
        model, data, step = self.model, self.data, mujoco.mj_step
        controller = self.controller
        control = bound_control(controller, data)  # everything it needs looked up once
        shove = self._shove
        max_pitch = self.max_abs_pitch_rad
        v = w = 0.0
        sensors, sensordata = self.sensors, data.sensordata
        rows, n, capacity = sensors.rows, sensors.count, len(sensors.rows)
        first = n  # the rows of these steps, checked against the collision region
        for v, w in zip(velocities_mps.tolist(), yaw_rates_rad_s.tolist(), strict=True):
            control(v, w)
            pitch = controller.last_pitch_rad
            if pitch > max_pitch or -pitch > max_pitch:
                max_pitch = abs(pitch)
            if shove is not None:
                self._apply_shove(shove)
            step(model, data)
            if n == capacity:
                self._check_region(first, n)
                sensors.count = n
                sensors.flush_full()
                n = first = sensors.count
            rows[n] = sensordata  # the state at the start of this step (see SensorSuite)
            n += 1
        sensors.count = n
        self._check_region(first, n)
        self.max_abs_pitch_rad = max_pitch
        if len(velocities_mps):
            self.command = (v, w)

    def step_torques(self, torques_nm: np.ndarray, n_steps: int = 1) -> None:
        """Advance with raw wheel torques (N·m, left and right), clipped at the motor limits."""
        limit = self.handles.torque_limit_nm
        self.data.ctrl[list(self.handles.actuator_ids)] = np.clip(torques_nm, -limit, limit)
        read = self.handles.read_balance_state  # no controller reads the pitch here
        sensors = self.sensors
        first = sensors.count  # the rows of these steps, checked against the collision region
        for _ in range(n_steps):
            if self._shove is not None:
                self._apply_shove(self._shove)
            mujoco.mj_step(self.model, self.data)
            if sensors.count == len(sensors.rows):
                self._check_region(first, sensors.count)
                sensors.flush_full()
                first = sensors.count
            sensors.rows[sensors.count] = self.data.sensordata
            sensors.count += 1
            self.max_abs_pitch_rad = max(self.max_abs_pitch_rad, abs(read(self.data).pitch_rad))
        self._check_region(first, sensors.count)

    def _check_region(self, first: int, stop: int) -> None:
        """Raise if the LiDAR origin of sensor rows ``first`` to ``stop`` (the physics
        steps just taken, each at the state its contacts were found in) left the collision
        region."""
        if self.region_guard is not None and stop > first:
            self.region_guard.check(self.sensors.rows[first:stop, self._lidar_position_cols])

    def set_shove(self, shove: Shove | None) -> None:
        """Start (or, with None, end) an external push on the body."""
        self._shove = shove
        if shove is None:
            self.data.xfrc_applied[self.handles.base_body_id] = 0.0

    @property
    def shove_active(self) -> bool:
        return self._shove is not None

    def _apply_shove(self, shove: Shove) -> None:
        # xfrc_applied acts at the body's centre of mass: move the force there with its torque
        body = self.handles.base_body_id
        point_world = self.data.xpos[body] + self.data.xmat[body].reshape(3, 3) @ shove.point_body_m
        lever = point_world - self.data.xipos[body]
        self.data.xfrc_applied[body, :3] = shove.force_world_n
        self.data.xfrc_applied[body, 3:] = np.cross(lever, shove.force_world_n)

    # -- sensing -------------------------------------------------------------------------

    def frame(self, index: int, phase: str = "") -> Frame:
        """The scan that ends now, with its labels, the truth at its stamp and the sensors.

        A rotating scan is the revolution of the last ``scan_time`` seconds, each beam
        cast from the sensor's pose at its own time; an instant scan is cast now. The
        truth is the robot's state at the scan's stamp (the time of beam 0): for a
        counter-clockwise revolution, the state when the previous frame was taken, so
        frames are meant to be taken every ``scan_time`` (the runner and the env do);
        the first frame after a reset is the revolution before it, the robot standing
        still where it was placed.
        """
        # after mj_step, derived quantities (site poses, sensors) lag qpos by one step:
        # recompute them so the scan, the IMU and the truth describe the same instant
        self.movers.pose(self.data, self.time_s)
        mujoco.mj_forward(self.model, self.data)
        if self.region_guard is not None:  # this state's contacts give the IMU's truth
            self.region_guard.check(self.data.site_xpos[self.handles.lidar_site_id][None, :])
        now = self.time_s
        lidar = self.lidar
        self.sensors.sync()
        truth = self.truth()
        if lidar.stamp_offset_s:  # beam 0 came first: the truth of the revolution's start
            truth, self._sweep_start_truth = self._sweep_start_truth, truth
            stamp = now + lidar.stamp_offset_s
            if abs(truth.stamp_s - stamp) < self.dt_s / 2:
                stamp = truth.stamp_s  # the same instant, the same float
            elif self._sweep_start_is_reset:
                truth = dataclasses.replace(truth, stamp_s=stamp)
            self._sweep_start_is_reset = False
        else:
            stamp = now
        if lidar.rotating:
            track = self.sensors.pose_track(self.data)
            reading = lidar.sweep(self.data, self.noise_rng, track, stamp)
        else:
            reading = lidar.scan(self.data, self.noise_rng)
        labels = self.level_view.relabel(self.data, reading)
        for array in (labels, reading.hit_points_world, reading.geom_ids):
            array.flags.writeable = False  # made for this frame alone: Frame keeps, not copies
        scan = Scan(
            ranges=reading.ranges,
            angle_min=self.lidar.angle_min,
            angle_increment=self.lidar.angle_increment,
            range_min=self.lidar.range_min,
            range_max=self.lidar.range_max,
            time_increment=self.lidar.time_increment,
            scan_time=self.lidar.scan_time,
            stamp=reading.stamp_s,
        )
        return Frame(
            index=index,
            scan=scan,
            labels=labels,
            hit_points_world=reading.hit_points_world,
            truth=truth,
            phase=phase,
            geom_ids=reading.geom_ids,
            sensors=self.sensors.readings(reading.stamp_s, now),
        )

    def truth(self) -> RobotTruth:
        """The robot's true state now."""
        data, handles = self.data, self.handles
        state = handles.read_balance_state(data)
        a, site = handles.qpos_adr, handles.lidar_site_id
        ctrl, sensordata, imu = data.ctrl, data.sensordata, handles.imu_slices
        left, right = handles.actuator_ids
        # every array of the truth in one read-only block (one copy, not nine): RobotTruth
        # keeps views of it as they are
        block = np.concatenate((
            data.qpos[a : a + 7],  # 0:3 position, 3:7 quaternion
            (state.left_wheel_speed_rad_s, state.right_wheel_speed_rad_s, ctrl[left], ctrl[right]),
            data.site_xpos[site],  # 11:14
            data.site_xmat[site],  # 14:23
            sensordata[imu["imu_gyro"]],  # 23:26
            sensordata[imu["imu_accel"]],  # 26:29
            sensordata[imu["imu_quat"]],  # 29:33
        ))  # fmt: skip
        block.flags.writeable = False
        return RobotTruth(
            stamp_s=self.time_s,
            position_base_in_world=block[0:3],
            quat_base_in_world=block[3:7],
            yaw_rad=state.yaw_rad,
            pitch_rad=state.pitch_rad,
            roll_rad=state.roll_rad,
            pitch_rate_rad_s=state.pitch_rate_rad_s,
            forward_velocity_mps=state.forward_velocity_mps,
            yaw_rate_rad_s=state.yaw_rate_rad_s,
            wheel_speeds_rad_s=block[7:9],
            wheel_torques_nm=block[9:11],
            command_velocity_mps=self.command[0],
            command_yaw_rate_rad_s=self.command[1],
            shove_active=self.shove_active,
            position_sensor_in_world=block[11:14],
            rotation_sensor_to_world=block[14:23].reshape(3, 3),
            imu_gyro_rad_s=block[23:26],
            imu_accel_mps2=block[26:29],
            imu_quat=block[29:33],
        )
