"""One episode of a data set: draw it from its seed, simulate it, record it.

Episode ``k`` of a data set with seed ``S`` draws everything from
``SeedSequence(S, spawn_key=(k,))``, the ``k``-th child of ``SeedSequence(S)``, so its
content depends on ``(S, k)`` and the ranges only: not on how many workers run, nor
in which order episodes finish. Five independent streams are spawned from it: the
house (layout and start pose), the robot (its parameters), the motion (commands and
shoves), the run (the sensors' noise), the sensors' calibration (mount, error levels)
and the environment (floor features on the lane, a low ceiling, people, pets, doors,
light furniture, and the robot class), so narrowing, say, the motion ranges leaves the
houses and robots of a data set as they were.

An episode whose robot falls is **kept**, cut at the fall and flagged
(``fell`` and ``end_reason`` in its summary): the scans up to a fall are real data of a
robot pitching hard. Besides the run's own pitch limit, a robot tipped over sideways
(|roll| beyond the same limit) counts as fallen, and its scans from then on are dropped.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np
import pyarrow as pa

from twsb_sim.collision_region import LeftCollisionRegion
from twsb_sim.dataset import environment_draw
from twsb_sim.dataset.lane_region import lane_region
from twsb_sim.dataset.motion import Lane, plan_motion
from twsb_sim.dataset.randomization import Randomization, Range, SensorRanges
from twsb_sim.dataset.recorder import EpisodeRecorder
from twsb_sim.house import ROBOT_RADIUS_M, House, make_house, random_house
from twsb_sim.house.named import NAMED_HOUSES
from twsb_sim.house.spawn import Obstacles
from twsb_sim.labels import BeamLabel, is_pitch_variation
from twsb_sim.robot import BASE_BODY, HOME_KEY, IMU_SITE, LIDAR_SITE, RobotConfig, load_robot_spec
from twsb_sim.runner import run_scenario
from twsb_sim.scenario import scenario_from_table
from twsb_sim.sensors.imu import ImuConfig

FOOTPRINT_TOLERANCE_M = 0.05  # the footprint disc is an over-estimate: touch counts beyond this


def episode_seed_sequence(seed: int, episode: int) -> np.random.SeedSequence:
    """The seed sequence of episode ``episode`` of a data set with seed ``seed``."""
    return np.random.SeedSequence(seed, spawn_key=(episode,))


@dataclass(frozen=True)
class EpisodeDraw:
    """Everything drawn for one episode, before it is simulated."""

    episode: int
    scenario_table: dict[str, Any]  # a scenario file's body: scenario_from_table() reads it
    house: House
    spawn: int  # index of the start pose among the house's spawn poses
    reversed_start: bool  # the robot starts facing back along the lane
    lane: Lane
    robot_class: str = "lqr"  # a name of twsb_sim.robot_classes.ROBOT_CLASSES


def _uniform(rng: np.random.Generator, bounds: Range, digits: int = 4) -> float:
    low, high = bounds
    return round(float(rng.uniform(low, high)) if high > low else float(low), digits)


def _seed32(sequence: np.random.SeedSequence) -> int:
    return int(sequence.generate_state(1, np.uint32)[0])


def planned_duration_s(seed: int, episode: int, ranges: Randomization) -> float:
    """How long episode ``episode`` lasts (s), without drawing the rest of it."""
    motion_seq = episode_seed_sequence(seed, episode).spawn(5)[2]
    return round(_uniform(np.random.default_rng(motion_seq), ranges.episode.duration_s), 1)


def draw_episode(seed: int, episode: int, ranges: Randomization) -> EpisodeDraw:
    """Draw house, start, robot and timeline of episode ``episode`` (no simulation)."""
    streams = episode_seed_sequence(seed, episode).spawn(6)
    house_seq, robot_seq, motion_seq, run_seq, sensor_seq, environment_seq = streams
    house_rng = np.random.default_rng(house_seq)
    if house_rng.random() < ranges.house.named_fraction:
        name = sorted(NAMED_HOUSES)[int(house_rng.integers(len(NAMED_HOUSES)))]
        house, house_table = make_house(name), {"name": name}
    else:
        house_seed = _seed32(house_seq.spawn(1)[0])
        house, house_table = random_house(house_seed), {"seed": house_seed}
    spawn = int(house_rng.integers(len(house.spawn_poses)))
    pose = house.spawn_poses[spawn]
    reversed_start = bool(house_rng.random() < ranges.house.reversed_start_probability)
    ahead, behind, yaw = pose.clear_ahead_m, pose.clear_behind_m, pose.yaw_rad
    if reversed_start:
        ahead, behind, yaw = behind, ahead, math.remainder(yaw + math.pi, math.tau)
    margin = ranges.motion.lane_margin_m
    lane = Lane(behind_m=max(behind - margin, 0.0), ahead_m=max(ahead - margin, 0.0))
    house_table["start"] = [pose.x_m, pose.y_m, round(math.degrees(yaw), 6)]

    r = ranges.robot
    robot_rng = np.random.default_rng(robot_seq)
    robot = {
        "lidar_height_m": _uniform(robot_rng, r.lidar_height_m),
        "body_mass_kg": _uniform(robot_rng, r.body_mass_kg),
        "com_height_offset_m": _uniform(robot_rng, r.com_height_offset_m),
        "wheel_friction": _uniform(robot_rng, r.floor_friction),
    }
    noise = _uniform(robot_rng, r.range_noise_std_m, digits=5)
    log_low, log_high = (math.log(v) for v in r.aggressiveness)
    aggressiveness = round(math.exp(_uniform(robot_rng, (log_low, log_high), digits=12)), 4)

    sensor_tables = _draw_sensors(np.random.default_rng(sensor_seq), ranges.sensors)
    robot.update(sensor_tables.pop("robot"))
    duration = planned_duration_s(seed, episode, ranges)
    plan = plan_motion(
        np.random.default_rng(motion_seq.spawn(1)[0]),
        lane,
        ranges.motion,
        ranges.shoves,
        duration,
    )
    table = {
        "name": f"episode_{episode:06d}",
        "description": f"data set seed {seed}, episode {episode}",
        "duration_s": duration,
        "seed": _seed32(run_seq),
        "house": house_table,
        "commands": [dict(c) for c in plan.commands],
        "shoves": [dict(s) for s in plan.shoves],
        "robot": robot,
        "lidar": {"range_noise_std_m": noise, **sensor_tables.pop("lidar")},
        "controller": {"aggressiveness": aggressiveness},
        **sensor_tables,
    }
    start = (pose.x_m, pose.y_m, yaw)
    class_name = _draw_environment(environment_seq, table, house, start, lane, ranges)
    return EpisodeDraw(episode, table, house, spawn, reversed_start, lane, class_name)


def _draw_environment(
    sequence: np.random.SeedSequence,
    table: dict[str, Any],
    house: House,
    start: tuple[float, float, float],
    lane: Lane,
    ranges: Randomization,
) -> str:
    """Add the environment's tables and the robot class to a scenario table; the class."""
    rng = np.random.default_rng(sequence)
    name, class_tables = environment_draw.robot_class(rng, ranges.robot_classes.weights())
    for key, values in class_tables.items():
        table[key] = {**table.get(key, {}), **values}
    ceiling = environment_draw.ceiling(rng, ranges.ceiling)
    if ceiling is not None:
        table["ceiling"] = ceiling
    features = environment_draw.floor_features(rng, lane, ranges.floor)
    if features:
        table["floor_features"] = features
    movers = environment_draw.movers(rng, house, start, lane, ranges.movers, table["duration_s"])
    table.update({key: rows for key, rows in movers.items() if rows})
    return name


def _draw_sensors(rng: np.random.Generator, r: SensorRanges) -> dict[str, dict[str, Any]]:
    """One robot's sensor calibration and error levels, as scenario-file tables."""
    tilt = math.radians(_uniform(rng, r.lidar_tilt_deg))
    towards = rng.uniform(0.0, math.tau)
    scale = _uniform(rng, r.imu_error_scale)
    imu = ImuConfig()
    return {
        "robot": {
            "lidar_tilt_pitch_deg": round(math.degrees(tilt * math.cos(towards)), 4),
            "lidar_tilt_roll_deg": round(math.degrees(tilt * math.sin(towards)), 4),
            "lidar_offset_x_m": _uniform(rng, r.lidar_offset_x_m),
        },
        "lidar": {
            "range_noise_fraction": _uniform(rng, r.range_noise_fraction, digits=5),
            "dropout_probability": _uniform(rng, r.dropout_probability, digits=5),
        },
        "imu": {
            name: float(f"{getattr(imu, name) * scale:.6g}")
            for name in (
                "gyro_noise_density_rad_s_sqrt_hz",
                "gyro_bias_offset_rad_s",
                "accel_noise_density_mps2_sqrt_hz",
                "accel_bias_offset_mps2",
            )
        },
        "odometry": {
            "left_wheel_radius_error": _uniform(rng, r.wheel_radius_error, digits=5),
            "right_wheel_radius_error": _uniform(rng, r.wheel_radius_error, digits=5),
        },
    }


@dataclass(frozen=True)
class EpisodeResult:
    """A simulated episode: its rows and its summary."""

    table: pa.Table
    summary: dict[str, Any]


def run_episode(seed: int, episode: int, ranges: Randomization) -> EpisodeResult:
    """Draw and simulate episode ``episode`` of the data set with seed ``seed``.

    The house's geoms far from the episode's lane are out of collision (the same frames,
    a cheaper physics step: :mod:`twsb_sim.dataset.lane_region`); a robot that leaves the
    lane's region has its episode simulated again with every geom in collision.
    """
    draw = draw_episode(seed, episode, ranges)
    scenario = scenario_from_table(draw.scenario_table, source=f"episode {episode}")
    x, y, yaw_deg = scenario.house.start
    region = lane_region((x, y, math.radians(yaw_deg)), draw.lane, scenario.robot.lidar_height_m)
    recorder = EpisodeRecorder()
    try:
        run = run_scenario(scenario, seed=scenario.seed, sinks=[recorder], collision_region=region)
    except LeftCollisionRegion:
        recorder = EpisodeRecorder()
        run = run_scenario(scenario, seed=scenario.seed, sinks=[recorder])
    fell, end_reason = run.fell, run.end_reason
    roll_limit = math.radians(scenario.simulation.fall_pitch_deg)
    rolled = np.flatnonzero(np.abs(recorder.scalars["roll_rad"]) > roll_limit)
    if rolled.size:
        first = int(rolled[0])
        roll_deg = abs(math.degrees(recorder.scalars["roll_rad"][first]))
        fell = True
        end_reason = (
            f"fell: |roll| {roll_deg:.1f} deg > {scenario.simulation.fall_pitch_deg:g} deg"
            f" at t={recorder.stamps[first]:.2f} s"
        )
        recorder.truncate(first)
    table = recorder.to_table(episode)
    summary = _summary(draw, table, fell, end_reason, recorder.intrinsics)
    summary["scan"] = recorder.intrinsics
    return EpisodeResult(table, summary)


def _summary(
    draw: EpisodeDraw,
    table: pa.Table,
    fell: bool,
    end_reason: str,
    scan: dict[str, float] | None,
) -> dict[str, Any]:
    """The episode's record in the metadata (plain JSON values)."""
    n = table.num_rows
    labels = table["labels"].combine_chunks().values.to_numpy().reshape(n, -1)
    n_beams = labels.shape[1] if n else 0
    angles = np.arange(n_beams) * (2 * math.pi / n_beams) - math.pi if n_beams else np.zeros(0)
    ahead = np.cos(angles) > 0
    pv = is_pitch_variation(labels)
    pitch = table["pitch_rad"].to_numpy()
    roll = table["roll_rad"].to_numpy()
    xy = np.column_stack([table["base_x_m"].to_numpy(), table["base_y_m"].to_numpy()])
    inside = Obstacles(draw.house.parts()).is_free(xy, ROBOT_RADIUS_M - FOOTPRINT_TOLERANCE_M)
    robot = RobotConfig(**draw.scenario_table["robot"])
    # a counter-clockwise scan's stamp is the start of its revolution: the run ran on to its end
    revolution_s = max(0.0, scan["time_increment"] * scan["beams"]) if scan else 0.0
    return {
        "episode": draw.episode,
        "scans": n,
        "fell": fell,
        "end_reason": end_reason,
        "house": draw.house.name,
        "spawn": draw.spawn,
        "reversed_start": draw.reversed_start,
        "robot_class": draw.robot_class,
        "lane_m": [round(-draw.lane.behind_m, 3), round(draw.lane.ahead_m, 3)],
        "simulated_s": round(float(table["stamp_s"][-1].as_py()) + revolution_s, 3) if n else 0.0,
        "beams_per_label": {
            label.name: int(np.count_nonzero(labels == label)) for label in BeamLabel
        },
        "pitch_variation_scans": int(np.count_nonzero(pv.any(axis=1))),
        "pitch_variation_beams_ahead": int(np.count_nonzero(pv[:, ahead])),
        "pitch_variation_beams_behind": int(np.count_nonzero(pv[:, ~ahead])),
        "max_abs_pitch_deg": round(float(np.degrees(np.abs(pitch).max())) if n else 0.0, 3),
        "max_abs_roll_deg": round(float(np.degrees(np.abs(roll).max())) if n else 0.0, 3),
        "footprint_overlap_scans": int(np.count_nonzero(~inside)),
        "mounts": sensor_mounts(robot),
        "scenario": draw.scenario_table,
    }


def sensor_mounts(robot: RobotConfig) -> dict[str, list[float]]:
    """Poses of the LiDAR and the IMU in the base frame: ``[x, y, z, qw, qx, qy, qz]``.

    The base frame is the body's (origin at the wheel axle centre); both sensors are
    rigidly mounted, so these are the static transforms of a ROS ``tf`` tree.
    """
    model = load_robot_spec(robot).compile()
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key(HOME_KEY).id)
    mujoco.mj_forward(model, data)
    base = data.body(BASE_BODY)
    base_rotation = base.xmat.reshape(3, 3)
    mounts = {}
    for frame, site_name in (("laser", LIDAR_SITE), ("imu", IMU_SITE)):
        site = data.site(site_name)
        position = base_rotation.T @ (site.xpos - base.xpos)
        quat = np.zeros(4)
        mujoco.mju_mat2Quat(quat, (base_rotation.T @ site.xmat.reshape(3, 3)).reshape(-1))
        quat = -quat if quat[0] < 0 else quat
        mounts[frame] = [round(float(v), 9) for v in (*position, *quat)]
    return mounts
