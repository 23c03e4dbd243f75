"""The Gymnasium environment of the TWSB robot: LiDAR scans with ground truth at every step.

:class:`TwsbEnv` runs the episode loop shared by both action variants
(:class:`~twsb_sim.envs.velocity_env.TwsbVelocityEnv`,
:class:`~twsb_sim.envs.torque_env.TwsbTorqueEnv`): one env step advances the physics by
one control period, split where a scan is due, a shove ends or a hard stop ends. Every
scan goes to the optional filter and to the sink, in time order. Conventions follow
Gymnasium's MuJoCo environments: randomness only from ``self.np_random``, reward terms in
``info``, termination on a fall, truncation left to the ``TimeLimit`` that ``gymnasium.make``
adds from the registered ``max_episode_steps``.
"""

from __future__ import annotations

import math
from typing import Any, ClassVar

import gymnasium as gym
import mujoco
import numpy as np

from twsb_sim.control.lqr import LqrConfig
from twsb_sim.envs.disturbances import Disturbances, draw_hard_stop, draw_shove
from twsb_sim.envs.episode import EpisodeState, fall_reason, step_info
from twsb_sim.envs.houses import (
    HouseKey,
    HouseOption,
    SimulationCache,
    check_house_option,
    choose_house,
)
from twsb_sim.envs.observation import RobotSensors, make_observation, observation_space
from twsb_sim.envs.options import Range, coerce, make_scan_filter, value_range
from twsb_sim.envs.render import TrackingRenderer
from twsb_sim.envs.reward import RewardConfig, reward_terms
from twsb_sim.frame import Frame, RobotTruth
from twsb_sim.house import House
from twsb_sim.lidar import LidarConfig
from twsb_sim.robot import RobotConfig, load_robot_spec
from twsb_sim.scenario import HouseChoice, Scenario, SimulationConfig
from twsb_sim.sensors import AttitudeFilterConfig, ImuConfig, OdometryConfig
from twsb_sim.simulation import Shove, Simulation
from twsb_sim.sinks import FrameSink, NullSink
from twsb_sim.summary import RunSummary
from twsb_sim.timeline import heading_force_to_world

RESET_OPTIONS = ("house", "spawn", "target")


def _next_multiple(step: int, every: int) -> int | None:
    """The next physics step after ``step`` that is a multiple of ``every`` (None if 0)."""
    return (step // every + 1) * every if every else None


class TwsbEnv(gym.Env[dict[str, np.ndarray], np.ndarray]):
    """A TWSB robot with a labeled 2D LiDAR in a house (base of the action variants).

    Args:
        house: ``"house1"``, ``"house2"``, a random layout's seed, ``"random"`` (a new
            layout per reset) or a list of those (one drawn per reset).
        spawn: index into the house's spawn poses, or None for one drawn per reset.
        control_period_s: simulated time per env step, s (a multiple of the 2 ms physics
            step); the LiDAR keeps its own rate, and the observation holds the latest scan.
        target_velocity_mps, target_yaw_rate_rad_s: the task's target, a value or a
            (low, high) range drawn from per reset; m/s and rad/s.
        max_velocity_mps, max_yaw_rate_rad_s: bounds of the targets (and of the velocity
            variant's actions).
        reward: weights of the reward terms (a :class:`RewardConfig` or a dict of its fields).
        disturbances: shoves and hard stops (a :class:`Disturbances` or a dict of its
            fields); none by default.
        scan_filter: the name of a registered filter (``"improved"``, ``"paper"``, ...;
            given the robot inputs it needs), True for the paper's filter with Table I
            parameters, the parameters of a registered filter, or a
            :class:`pvfilter.ScanFilter` (run on the scans alone); its mask goes to
            ``info["filter_removed"]``.
        sink: receives every frame, the filter's result and the events (a
            :class:`twsb_sim.sinks.FrameSink`, such as the Rerun logger).
        robot, lidar, controller: the simulator's subsystem parameters.
        imu, attitude, odometry: the robot's IMU, attitude filter and wheel odometry,
            whose readings (not the truth) the observation holds.
        fall_pitch_deg, fall_roll_deg: |pitch| or |roll| beyond which the robot has fallen.
        render_mode: None or ``"rgb_array"``.
        render_size: (width, height) of rendered pictures, pixels.
    """

    metadata: ClassVar[dict[str, Any]] = {"render_modes": ["rgb_array"], "render_fps": 10}

    def __init__(
        self,
        *,
        house: HouseOption = "house1",
        spawn: int | None = None,
        control_period_s: float = 0.1,
        target_velocity_mps: Range = (0.0, 0.5),
        target_yaw_rate_rad_s: Range = (-0.3, 0.3),
        max_velocity_mps: float = 1.0,
        max_yaw_rate_rad_s: float = 1.0,
        reward: RewardConfig | dict[str, float] | None = None,
        disturbances: Disturbances | dict[str, Any] | None = None,
        scan_filter: Any = None,
        sink: FrameSink | None = None,
        robot: RobotConfig | None = None,
        lidar: LidarConfig | None = None,
        controller: LqrConfig | None = None,
        imu: ImuConfig | None = None,
        attitude: AttitudeFilterConfig | None = None,
        odometry: OdometryConfig | None = None,
        fall_pitch_deg: float = 45.0,
        fall_roll_deg: float = 45.0,
        render_mode: str | None = None,
        render_size: tuple[int, int] = (640, 480),
    ) -> None:
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode: expected None or 'rgb_array', got {render_mode!r}")
        check_house_option(house)
        self.render_mode = render_mode
        self._house_option, self._spawn = house, spawn
        self._target_ranges = (
            value_range("target_velocity_mps", target_velocity_mps, max_velocity_mps),
            value_range("target_yaw_rate_rad_s", target_yaw_rate_rad_s, max_yaw_rate_rad_s),
        )
        self.reward_config = coerce(RewardConfig, reward, "reward")
        self.disturbances = coerce(Disturbances, disturbances, "disturbances")
        self.scan_filter = make_scan_filter(scan_filter)
        self.sink: FrameSink = sink if sink is not None else NullSink()
        self.fall_roll_rad = math.radians(fall_roll_deg)
        self.robot_config = robot = robot if robot is not None else RobotConfig()
        self.lidar_config = lidar = lidar if lidar is not None else LidarConfig()
        self.controller_config = controller if controller is not None else LqrConfig()
        self.imu_config = imu if imu is not None else ImuConfig()
        self.attitude_config = attitude if attitude is not None else AttitudeFilterConfig()
        self.odometry_config = odometry if odometry is not None else OdometryConfig()
        self.fall_pitch_deg = fall_pitch_deg

        def build(h: House) -> Simulation:
            return Simulation(
                h, robot, lidar, self.controller_config, fall_pitch_deg,
                imu=self.imu_config, attitude=self.attitude_config, odometry=self.odometry_config,
            )  # fmt: skip

        self._sims = SimulationCache(build)
        self.sim: Simulation | None = None  # the current house's, from the first reset on
        dt = float(load_robot_spec(robot).option.timestep)
        self.steps_per_control = round(control_period_s / dt)
        if self.steps_per_control < 1 or abs(self.steps_per_control * dt - control_period_s) > 1e-9:
            raise ValueError(
                f"control_period_s: expected a positive multiple of {dt:g} s,"
                f" got {control_period_s!r}"
            )
        self.control_period_s = self.steps_per_control * dt
        self.steps_per_scan = round(1.0 / (lidar.rate_hz * dt))
        # optional sink hook: robot states between scans, for sinks that set a rate
        state_rate_hz = getattr(self.sink, "state_rate_hz", None)
        self.steps_per_state = max(1, round(1.0 / (state_rate_hz * dt))) if state_rate_hz else 0
        self.metadata = {**self.metadata, "render_fps": round(1.0 / self.control_period_s)}
        self._target_limits = (max_velocity_mps, max_yaw_rate_rad_s)
        self.observation_space = observation_space(
            lidar.beams_per_revolution, lidar.range_max_m, self._target_limits
        )
        self.action_space = self._make_action_space(max_velocity_mps, max_yaw_rate_rad_s)
        self._render_size = render_size
        self._renderer: TrackingRenderer | None = None
        self._episode: EpisodeState | None = None
        self._episodes = 0

    # -- the variants' part ---------------------------------------------------------------

    def _make_action_space(self, max_velocity_mps: float, max_yaw_rate_rad_s: float) -> gym.Space:
        raise NotImplementedError

    def _advance(self, action: np.ndarray, n_steps: int, hard_stop: bool) -> None:
        """Run ``n_steps`` physics steps under ``action`` (and a hard stop, if one is on)."""
        raise NotImplementedError

    # -- Gymnasium API --------------------------------------------------------------------

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        """Start an episode. ``options`` may hold ``house`` (as the constructor's),
        ``spawn`` (an index) and ``target`` ((v m/s, w rad/s)) for this episode only."""
        super().reset(seed=seed)
        options = dict(options or {})
        unknown = set(options) - set(RESET_OPTIONS)
        if unknown:
            raise ValueError(f"options: unknown keys {sorted(unknown)}; known: {RESET_OPTIONS}")
        rng = self.np_random
        house = options.get("house", self._house_option)
        check_house_option(house)
        house_key = choose_house(house, rng)
        self.sim = sim = self._sims.get(house_key)
        poses = sim.house.spawn_poses
        spawn = options.get("spawn", self._spawn)
        if spawn is None:
            spawn = int(rng.integers(len(poses)))
        if not 0 <= spawn < len(poses):
            raise ValueError(f"spawn: {sim.house.name} has {len(poses)} spawn poses, got {spawn}")
        noise_seed = int(rng.integers(2**63 - 1))
        sim.reset(poses[spawn], noise_seed)
        if "target" in options:
            target = self._check_target(options["target"])
        else:
            target = tuple(float(rng.uniform(low, high)) for low, high in self._target_ranges)
        self._episode = EpisodeState(target=target)
        self._episodes += 1
        if self.scan_filter is not None:
            self.scan_filter.reset()
        self._summary = RunSummary(
            scenario=self.spec.id if self.spec is not None else type(self).__name__,
            seed=noise_seed,
            house=sim.house.name,
        )
        if hasattr(self.sink, "on_start"):  # optional sink hook, as in the scenario runner
            self.sink.on_start(self._scenario(house_key, spawn, noise_seed), sim)
        pose = poses[spawn]
        self.sink.on_event(
            0.0,
            f"episode {self._episodes}: {sim.house.name}, spawn {spawn} at "
            f"({pose.x_m:.2f}, {pose.y_m:.2f}) m, {math.degrees(pose.yaw_rad):.0f} deg",
        )
        if self.steps_per_state:
            self.sink.on_state(sim.truth())
        self._take_frame()
        truth = self._truth_now(self._episode)
        return self._observation(truth), self._info(truth)

    def step(
        self, action: np.ndarray
    ) -> tuple[dict[str, np.ndarray], float, bool, bool, dict[str, Any]]:
        """Advance one control period under ``action``."""
        episode, sim = self._require_episode(), self.sim
        action = np.asarray(action, dtype=np.float64).reshape(self.action_space.shape)
        self._start_disturbances(episode)
        end = episode.step + self.steps_per_control
        while episode.step < end:
            # run to the next breakpoint: a scan, the end of a shove or hard stop, the step's end
            next_scan = _next_multiple(episode.step, self.steps_per_scan)
            next_state = _next_multiple(episode.step, self.steps_per_state)
            stops = [end, next_scan, next_state, episode.shove_end_step, episode.hard_stop_end_step]
            until = min(k for k in stops if k is not None)
            self._advance(action, until - episode.step, episode.hard_stop_active)
            episode.step = until
            if until == episode.shove_end_step:
                sim.set_shove(None)
                episode.shove_end_step = None
            if until == episode.hard_stop_end_step:
                episode.hard_stop_end_step = None
            if until == next_state:
                self.sink.on_state(sim.truth())
            if until == next_scan:
                self._take_frame()
        truth = self._truth_now(episode)
        fell = False
        if not episode.fall_reason:  # a fallen robot stays fallen: penalise the fall once
            episode.fall_reason = fall_reason(
                truth, sim.data, sim.fall_pitch_rad, self.fall_roll_rad
            )
            fell = bool(episode.fall_reason)
        if fell:
            self.sink.on_event(sim.time_s, f"fell: {episode.fall_reason}")
            self._summary.fell, self._summary.end_reason = True, f"fell: {episode.fall_reason}"
        target_v, target_w = episode.effective_target
        terms = reward_terms(
            self.reward_config,
            self.control_period_s,
            truth.forward_velocity_mps - target_v,
            truth.yaw_rate_rad_s - target_w,
            truth.pitch_rad,
            truth.pitch_rate_rad_s,
            truth.wheel_torques_nm / sim.handles.torque_limit_nm,
            fell,
        )
        info = self._info(truth)
        info.update(terms)
        reward = float(sum(terms.values()))
        return self._observation(truth), reward, bool(episode.fall_reason), False, info

    def render(self) -> np.ndarray | None:
        """An RGB picture (uint8[height, width, 3]) from a camera following the robot, with
        the latest scan's hit points coloured by label; None unless render_mode is
        ``"rgb_array"``."""
        if self.render_mode != "rgb_array":
            return None
        frame = self._require_episode().frame
        if self._renderer is None or self._renderer.model is not self.sim.model:
            self._close_renderer()  # a new house: a new model to draw
            width, height = self._render_size
            self._renderer = TrackingRenderer(
                self.sim.model, self.sim.handles.base_body_id, width, height
            )
        return self._renderer.render(self.sim.data, frame.truth.yaw_rad, frame)

    def close(self) -> None:
        """Free the renderer and hand the last episode's summary to the sink (once)."""
        self._close_renderer()
        if self._episode is not None:
            self.sink.close(self._summary)
            self._episode = None

    @property
    def latest_frame(self) -> Frame | None:
        """The latest scan with all its ground truth (hit points, sensor pose, ...), as the
        sink received it; None before the first reset."""
        return self._episode.frame if self._episode is not None else None

    # -- the loop's parts -----------------------------------------------------------------

    def _require_episode(self) -> EpisodeState:
        if self._episode is None:
            raise gym.error.ResetNeeded("call reset() before step() or render()")
        return self._episode

    def _check_target(self, value: Any) -> tuple[float, float]:
        v, w = (float(x) for x in value)
        value_range("target velocity", v, self._target_limits[0])
        value_range("target yaw rate", w, self._target_limits[1])
        return v, w

    def _start_disturbances(self, episode: EpisodeState) -> None:
        """Draw this step's shove and hard stop (always both draws, in a fixed order)."""
        rng, sim, config = self.np_random, self.sim, self.disturbances
        shove = draw_shove(config, rng, self.control_period_s)
        hard_stop = draw_hard_stop(config, rng, self.control_period_s)
        if shove is not None and episode.shove_end_step is None:
            force = heading_force_to_world(shove.force_heading_n, sim.truth().yaw_rad)
            sim.set_shove(Shove(force_world_n=force, point_body_m=np.array(shove.point_body_m)))
            episode.shove_end_step = episode.step + max(1, round(shove.duration_s / sim.dt_s))
            self.sink.on_event(sim.time_s, f"shove: {np.linalg.norm(force):.0f} N")
        if hard_stop and episode.hard_stop_end_step is None:
            duration = max(1, round(config.hard_stop_duration_s / sim.dt_s))
            episode.hard_stop_end_step = episode.step + duration
            self.sink.on_event(sim.time_s, f"hard stop for {duration * sim.dt_s:g} s")

    def _take_frame(self) -> None:
        """Cast the LiDAR now; hand the frame to the filter, the summary and the sink."""
        episode, sim = self._require_episode(), self.sim
        frame = sim.frame(episode.frames, phase="hard stop" if episode.hard_stop_active else "")
        result = self.scan_filter.process(frame) if self.scan_filter is not None else None
        episode.frame, episode.filter_result = frame, result
        episode.frames += 1
        self._summary.add_frame(frame, None if result is None else result.removed)
        self.sink.on_frame(frame, result)

    def _truth_now(self, episode: EpisodeState) -> RobotTruth:
        frame = episode.frame
        if frame is not None and frame.truth.stamp_s == self.sim.time_s:
            return frame.truth  # the scan was just taken and its truth is current
        mujoco.mj_forward(self.sim.model, self.sim.data)  # sensors lag mj_step by one step
        return self.sim.truth()

    def _observation(self, truth: RobotTruth) -> dict[str, np.ndarray]:
        episode, sensors, now = self._require_episode(), self.sim.sensors, self.sim.time_s
        sensors.sync()
        robot = RobotSensors(
            sensors.latest_imu(now), sensors.attitude_at(now), sensors.pose_at(now),
            sensors.twist_at(now),
        )  # fmt: skip
        return make_observation(
            episode.frame.scan.ranges,
            self.sim.lidar.range_max,
            truth,
            robot,
            episode.effective_target,
            self.observation_space,
        )

    def _scenario(self, house: HouseKey, spawn: int, seed: int) -> Scenario:
        """The episode described as a scenario, for sinks that want one at the start."""
        limit = self.spec.max_episode_steps if self.spec is not None else None
        return Scenario(
            name=self.spec.id if self.spec is not None else type(self).__name__,
            duration_s=limit * self.control_period_s if limit else 0.0,
            house=HouseChoice(name=house, spawn=spawn)
            if isinstance(house, str)
            else HouseChoice(name=None, seed=house, spawn=spawn),
            robot=self.robot_config,
            lidar=self.lidar_config,
            controller=self.controller_config,
            simulation=SimulationConfig(fall_pitch_deg=self.fall_pitch_deg),
            imu=self.imu_config,
            attitude=self.attitude_config,
            odometry=self.odometry_config,
            description="an episode of the Gymnasium environment",
            seed=seed,
        )

    def _info(self, truth: RobotTruth) -> dict[str, Any]:
        return step_info(self._require_episode(), truth, self.sim, self.scan_filter is not None)

    def _close_renderer(self) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
