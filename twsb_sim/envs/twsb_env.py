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

from pvfilter import FilterParams, PitchVariationFilter
from twsb_sim.control.lqr import LqrConfig
from twsb_sim.envs.disturbances import Disturbances, draw_hard_stop, draw_shove
from twsb_sim.envs.episode import EpisodeState, fall_reason
from twsb_sim.envs.houses import HouseOption, SimulationCache, check_house_option, choose_house
from twsb_sim.envs.observation import WheelOdometry, make_observation, observation_space
from twsb_sim.envs.render import TrackingRenderer
from twsb_sim.envs.reward import RewardConfig, reward_terms
from twsb_sim.frame import Frame, RobotTruth
from twsb_sim.house import House
from twsb_sim.lidar import LidarConfig
from twsb_sim.robot import RobotConfig
from twsb_sim.simulation import Shove, Simulation
from twsb_sim.sinks import FrameSink, NullSink
from twsb_sim.summary import RunSummary
from twsb_sim.timeline import heading_force_to_world

RESET_OPTIONS = ("house", "spawn", "target")
Range = float | tuple[float, float]


def _range(name: str, value: Range, limit: float) -> tuple[float, float]:
    low, high = (value, value) if isinstance(value, int | float) else tuple(value)
    if not -limit <= low <= high <= limit:
        raise ValueError(
            f"{name}: expected a value or (low, high) within ±{limit:g}, got {value!r}"
        )
    return float(low), float(high)


def _make_filter(scan_filter: Any) -> Any | None:
    if scan_filter is None or scan_filter is False:
        return None
    if scan_filter is True:
        return PitchVariationFilter()
    if isinstance(scan_filter, FilterParams):
        return PitchVariationFilter(scan_filter)
    return scan_filter  # anything with process(scan) -> result.removed, and reset()


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
        reward: weights of the reward terms.
        disturbances: shoves and hard stops (a :class:`Disturbances` or a dict of its
            fields); none by default.
        scan_filter: True for a :class:`pvfilter.PitchVariationFilter` with Table I
            parameters, a :class:`pvfilter.FilterParams`, or any object with
            ``process(scan)`` and ``reset()``; its mask goes to ``info["filter_removed"]``.
        sink: receives every frame, the filter's result and the events (a
            :class:`twsb_sim.sinks.FrameSink`, such as the Rerun logger).
        robot, lidar, controller: the simulator's subsystem parameters.
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
        reward: RewardConfig | None = None,
        disturbances: Disturbances | dict[str, Any] | None = None,
        scan_filter: Any = None,
        sink: FrameSink | None = None,
        robot: RobotConfig | None = None,
        lidar: LidarConfig | None = None,
        controller: LqrConfig | None = None,
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
            _range("target_velocity_mps", target_velocity_mps, max_velocity_mps),
            _range("target_yaw_rate_rad_s", target_yaw_rate_rad_s, max_yaw_rate_rad_s),
        )
        self.reward_config = reward if reward is not None else RewardConfig()
        self.disturbances = Disturbances.coerce(disturbances)
        self.scan_filter = _make_filter(scan_filter)
        self.sink: FrameSink = sink if sink is not None else NullSink()
        self.fall_roll_rad = math.radians(fall_roll_deg)
        lidar = lidar if lidar is not None else LidarConfig()

        def build(h: House) -> Simulation:
            return Simulation(
                h, robot or RobotConfig(), lidar, controller or LqrConfig(), fall_pitch_deg
            )

        self._sims = SimulationCache(build)
        self.sim = self._sims.get(choose_house(house, np.random.default_rng(0)))
        dt = self.sim.dt_s
        self.steps_per_control = round(control_period_s / dt)
        if self.steps_per_control < 1 or abs(self.steps_per_control * dt - control_period_s) > 1e-9:
            raise ValueError(
                f"control_period_s: expected a positive multiple of {dt:g} s,"
                f" got {control_period_s!r}"
            )
        self.control_period_s = self.steps_per_control * dt
        self.steps_per_scan = round(1.0 / (lidar.rate_hz * dt))
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
        self.sim = sim = self._sims.get(choose_house(house, rng))
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
        self._odometry = WheelOdometry(sim.handles.wheel_radius_m, sim.handles.track_width_m)
        self._odometry.reset(self._wheel_angles())
        if self.scan_filter is not None:
            self.scan_filter.reset()
        self._summary = RunSummary(
            scenario=self.spec.id if self.spec is not None else type(self).__name__,
            seed=noise_seed,
            house=sim.house.name,
        )
        pose = poses[spawn]
        self.sink.on_event(
            0.0,
            f"episode {self._episodes}: {sim.house.name}, spawn {spawn} at "
            f"({pose.x_m:.2f}, {pose.y_m:.2f}) m, {math.degrees(pose.yaw_rad):.0f} deg",
        )
        self._take_frame()
        truth = self._episode.frame.truth
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
            next_scan = (episode.step // self.steps_per_scan + 1) * self.steps_per_scan
            stops = [end, next_scan, episode.shove_end_step, episode.hard_stop_end_step]
            until = min(k for k in stops if k is not None)
            self._advance(action, until - episode.step, episode.hard_stop_active)
            episode.step = until
            if until == episode.shove_end_step:
                sim.set_shove(None)
                episode.shove_end_step = None
            if until == episode.hard_stop_end_step:
                episode.hard_stop_end_step = None
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
        if self._renderer is None or self._renderer.model is not self.sim.model:
            self._close_renderer()
            width, height = self._render_size
            self._renderer = TrackingRenderer(
                self.sim.model, self.sim.handles.base_body_id, width, height
            )
        episode = self._episode
        frame = episode.frame if episode is not None else None
        yaw = frame.truth.yaw_rad if frame is not None else 0.0
        return self._renderer.render(self.sim.data, yaw, frame)

    def close(self) -> None:
        """Free the renderer and hand the last episode's summary to the sink (once)."""
        self._close_renderer()
        if self._episode is not None:
            self.sink.close(self._summary)
            self._episode = None

    # -- the loop's parts -----------------------------------------------------------------

    def _require_episode(self) -> EpisodeState:
        if self._episode is None:
            raise gym.error.ResetNeeded("call reset() before step()")
        return self._episode

    def _check_target(self, value: Any) -> tuple[float, float]:
        v, w = (float(x) for x in value)
        _range("target velocity", v, self._target_limits[0])
        _range("target yaw rate", w, self._target_limits[1])
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
        result = self.scan_filter.process(frame.scan) if self.scan_filter is not None else None
        episode.frame, episode.filter_result = frame, result
        episode.frames += 1
        self._summary.add_frame(frame, None if result is None else result.removed)
        self.sink.on_frame(frame, result)

    def _truth_now(self, episode: EpisodeState) -> RobotTruth:
        frame = episode.frame
        if frame is not None and frame.stamp_s == self.sim.time_s:
            return frame.truth  # the scan was just taken: its truth is current
        mujoco.mj_forward(self.sim.model, self.sim.data)  # sensors lag mj_step by one step
        return self.sim.truth()

    def _wheel_angles(self) -> np.ndarray:
        return self.sim.data.qpos[list(self.sim.handles.wheel_qpos_adr)]

    def _observation(self, truth: RobotTruth) -> dict[str, np.ndarray]:
        episode = self._require_episode()
        return make_observation(
            episode.frame.scan.ranges,
            self.sim.lidar.range_max,
            truth,
            self._odometry.update(self._wheel_angles()),
            episode.effective_target,
            self.observation_space,
        )

    def _info(self, truth: RobotTruth) -> dict[str, Any]:
        episode = self._require_episode()
        frame: Frame = episode.frame
        info: dict[str, Any] = {
            "time_s": self.sim.time_s,
            "house": self.sim.house.name,
            "pose_world": np.array([*truth.position_base_in_world[:2], truth.yaw_rad]),
            "pitch_rad": truth.pitch_rad,
            "roll_rad": truth.roll_rad,
            "pitch_rate_rad_s": truth.pitch_rate_rad_s,
            "forward_velocity_mps": truth.forward_velocity_mps,
            "yaw_rate_rad_s": truth.yaw_rate_rad_s,
            "labels": frame.labels.copy(),
            "scan_ranges_m": frame.scan.ranges.copy(),
            "scan_stamp_s": frame.stamp_s,
            "shove_active": episode.shove_end_step is not None,
            "hard_stop_active": episode.hard_stop_active,
            "fall_reason": episode.fall_reason,
        }
        if self.scan_filter is not None:
            info["filter_removed"] = np.array(episode.filter_result.removed, dtype=bool)
        return info

    def _close_renderer(self) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
