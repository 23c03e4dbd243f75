"""What ``twsb generate`` randomizes per episode, and within which ranges.

Every range is ``[low, high]`` (a draw is uniform in it, log-uniform for
``robot.aggressiveness``); a single number fixes the value. A TOML file overrides any of
them (``twsb generate --ranges my_ranges.toml``; ``twsb generate --show-ranges`` prints
the defaults in that form):

.. code-block:: toml

    [episode]
    duration_s = [10.0, 20.0]
    [shoves]
    probability = 0.6
    [robot]
    lidar_height_m = 0.30        # fixed
    [sensors]
    lidar_tilt_deg = 0.0         # a level scan plane on every robot

Mistakes raise :class:`~twsb_sim.config_errors.ConfigError` naming the file and the key.
"""

from __future__ import annotations

import dataclasses
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from twsb_sim.config_errors import ConfigError, apply_overrides
from twsb_sim.dataset.environment_ranges import (
    CeilingRanges,
    FloorRanges,
    MoverRanges,
    RobotClassWeights,
)
from twsb_sim.dataset.ranges_checks import Range, normalize, within
from twsb_sim.scenario import MAX_VELOCITY_MPS, MAX_YAW_RATE_RAD_S


@dataclass(frozen=True)
class EpisodeRanges:
    """Length of an episode."""

    duration_s: Range | float = (20.0, 40.0)  # s of simulated time (10 scans per s)

    def __post_init__(self) -> None:
        normalize(self)
        within("duration_s", self.duration_s, 1.0, 3600.0)


@dataclass(frozen=True)
class HouseRanges:
    """Where an episode happens."""

    named_fraction: float = 0.0  # probability of a named layout (house1, house2), else random
    reversed_start_probability: float = 0.5  # start facing the other way along the lane

    def __post_init__(self) -> None:
        within("named_fraction", self.named_fraction, 0.0, 1.0)
        within("reversed_start_probability", self.reversed_start_probability, 0.0, 1.0)


@dataclass(frozen=True)
class MotionRanges:
    """The command profile: drives, stops, reversals, turns in place, pauses.

    An episode is a chain of maneuvers planned along the free lane of its start pose,
    so the robot stays ``lane_margin_m`` away from what ends the lane.
    """

    cruise_velocity_mps: Range | float = (0.2, 1.0)  # m/s, forward drives
    reverse_velocity_mps: Range | float = (0.2, 0.6)  # m/s, backward drives (magnitude)
    acceleration_mps2: Range | float = (0.5, 3.0)  # m/s², speed-up ramps
    braking_mps2: Range | float = (0.5, 3.0)  # m/s², ramped stops and reversals
    hard_stop_probability: float = 0.5  # a stop or reversal is a step, not a ramp
    reversal_probability: float = 0.25  # a drive reverses straight into the other way
    backward_probability: float = 0.3  # a drive goes backward (when there is room both ways)
    turn_probability: float = 0.3  # a maneuver is a turn in place
    turnabout_probability: float = 0.3  # a turn is a 180 deg turnabout (no turn back)
    pause_probability: float = 0.15  # a maneuver is a pause
    turn_rate_rad_s: Range | float = (0.2, 0.6)  # rad/s
    turn_angle_deg: Range | float = (20.0, 120.0)  # deg, turned and then turned back
    pause_s: Range | float = (0.3, 2.0)  # s, standing still between maneuvers
    lane_margin_m: float = 0.6  # m, kept free at both ends of the lane (stop overshoot, shoves)
    min_drive_m: float = 0.4  # m, shortest drive

    def __post_init__(self) -> None:
        normalize(self)
        for name in ("cruise_velocity_mps", "reverse_velocity_mps"):
            within(name, getattr(self, name), 0.05, MAX_VELOCITY_MPS)
        for name in ("acceleration_mps2", "braking_mps2"):
            within(name, getattr(self, name), 0.05, 50.0)
        for name in (
            "hard_stop_probability",
            "reversal_probability",
            "backward_probability",
            "turn_probability",
            "turnabout_probability",
            "pause_probability",
        ):
            within(name, getattr(self, name), 0.0, 1.0)
        if self.turn_probability + self.pause_probability > 1.0:
            raise ValueError(
                "turn_probability: turn_probability + pause_probability must be <= 1, got "
                f"{self.turn_probability + self.pause_probability:g}"
            )
        within("turn_rate_rad_s", self.turn_rate_rad_s, 0.05, MAX_YAW_RATE_RAD_S)
        within("turn_angle_deg", self.turn_angle_deg, 1.0, 360.0)
        within("pause_s", self.pause_s, 0.05, 60.0)
        within("lane_margin_m", self.lane_margin_m, 0.0, 5.0)
        within("min_drive_m", self.min_drive_m, 0.05, 20.0)


@dataclass(frozen=True)
class ShoveRanges:
    """Pushes on the robot's body: from behind or the front, or (fewer) from a side; while
    it stands, drives, brakes or turns in place.

    How hard a push tips the robot depends on its angular impulse about the axle
    (force x duration x height): about 10 deg of pitch per N·m·s; the default robot
    survives up to 3.7-4.4 N·m·s from behind or the front and 1.7-2.2 N·m·s from a side,
    the randomized robots 3.4 / 3.6 / 4.6 N·m·s (10th / 25th / 50th percentile) and
    1.8 / 1.9 / 2.2 N·m·s (``twsb envelope``, docs/envelope.md). A push's angular
    impulse is drawn as ``impulse_fraction`` of the cap of its direction, and its force
    follows from the drawn duration and height; with ``impulse_fraction = 0`` the force
    is drawn from the force ranges instead and cut to the caps.
    """

    probability: float = 0.45  # a pause, a drive or a turn carries a shove
    sideways_fraction: float = 0.2  # of the shoves, those that push from a side
    longitudinal_force_n: Range | float = (15.0, 70.0)  # N, from behind or from the front
    lateral_force_n: Range | float = (5.0, 25.0)  # N, from the left or the right
    duration_s: Range | float = (0.08, 0.25)  # s
    height_m: Range | float = (0.25, 0.45)  # m above the axle where the force acts
    # caps: about the 25th (10th) percentile of what the randomized robots survive
    max_angular_impulse_n_m_s: float = 3.6  # N·m·s, cap of a push from behind or the front
    max_sideways_angular_impulse_n_m_s: float = 1.8  # N·m·s, cap of a push from a side
    displacement_m_per_n_s: float = 0.12  # m per N·s a push moves the robot (for planning)
    impulse_fraction: Range | float = (0.1, 0.95)  # of the cap; 0 = draw forces instead
    braking_probability: float = 0.3  # a drive's shove lands while it brakes, not cruises
    turning_probability: float = 0.5  # a turn in place carries a shove (x probability)

    def __post_init__(self) -> None:
        normalize(self)
        within("probability", self.probability, 0.0, 1.0)
        within("sideways_fraction", self.sideways_fraction, 0.0, 1.0)
        within("longitudinal_force_n", self.longitudinal_force_n, 0.0, 500.0)
        within("lateral_force_n", self.lateral_force_n, 0.0, 500.0)
        within("duration_s", self.duration_s, 0.01, 5.0)
        within("height_m", self.height_m, 0.01, 1.0)
        within("max_angular_impulse_n_m_s", self.max_angular_impulse_n_m_s, 0.0, 100.0)
        within(
            "max_sideways_angular_impulse_n_m_s",
            self.max_sideways_angular_impulse_n_m_s,
            0.0,
            100.0,
        )
        within("displacement_m_per_n_s", self.displacement_m_per_n_s, 0.0, 1.0)
        within("impulse_fraction", self.impulse_fraction, 0.0, 2.0)
        within("braking_probability", self.braking_probability, 0.0, 1.0)
        within("turning_probability", self.turning_probability, 0.0, 1.0)


@dataclass(frozen=True)
class RobotRanges:
    """The robot, its LiDAR, its controller and the floor."""

    lidar_height_m: Range | float = (0.2, 0.35)  # m, scanner above the floor
    body_mass_kg: Range | float = (4.5, 7.0)  # kg
    com_height_offset_m: Range | float = (-0.03, 0.05)  # m, centre of mass shift along body z
    floor_friction: Range | float = (0.6, 1.2)  # tyre-floor sliding friction coefficient
    range_noise_std_m: Range | float = (0.0, 0.03)  # m, LiDAR range noise
    aggressiveness: Range | float = (0.5, 2.0)  # LQR weight scale, drawn log-uniform

    def __post_init__(self) -> None:
        normalize(self)
        within("lidar_height_m", self.lidar_height_m, 0.15, 1.0)
        within("body_mass_kg", self.body_mass_kg, 0.5, 50.0)
        within("com_height_offset_m", self.com_height_offset_m, -0.2, 0.3)
        within("floor_friction", self.floor_friction, 0.05, 3.0)
        within("range_noise_std_m", self.range_noise_std_m, 0.0, 1.0)
        within("aggressiveness", self.aggressiveness, 0.01, 100.0)


@dataclass(frozen=True)
class SensorRanges:
    """How far each robot's sensors stray from the defaults (``docs/sensors.md``).

    The LiDAR's scan plane is tilted by ``lidar_tilt_deg`` towards a uniformly drawn
    direction (pitch and roll); the IMU's noise densities and bias offsets are the
    defaults (BMI088) times ``imu_error_scale``; each wheel's radius error is drawn on
    its own.
    """

    lidar_tilt_deg: Range | float = (0.0, 3.0)  # deg, the scan plane off level on the robot
    lidar_offset_x_m: Range | float = (-0.02, 0.05)  # m, LiDAR ahead of the axle centre
    range_noise_fraction: Range | float = (0.005, 0.015)  # std per metre of range
    dropout_probability: Range | float = (0.0, 0.02)  # returns lost at random
    imu_error_scale: Range | float = (0.5, 2.0)  # times the data sheet's noise and offsets
    wheel_radius_error: Range | float = (-0.01, 0.01)  # believed / true radius - 1, per wheel

    def __post_init__(self) -> None:
        normalize(self)
        within("lidar_tilt_deg", self.lidar_tilt_deg, 0.0, 10.0)
        within("lidar_offset_x_m", self.lidar_offset_x_m, -0.15, 0.15)
        within("range_noise_fraction", self.range_noise_fraction, 0.0, 1.0)
        within("dropout_probability", self.dropout_probability, 0.0, 1.0)
        within("imu_error_scale", self.imu_error_scale, 0.0, 100.0)
        within("wheel_radius_error", self.wheel_radius_error, -0.2, 0.2)


@dataclass(frozen=True)
class Randomization:
    """All the ranges, one table each in a ranges file."""

    episode: EpisodeRanges = field(default_factory=EpisodeRanges)
    house: HouseRanges = field(default_factory=HouseRanges)
    motion: MotionRanges = field(default_factory=MotionRanges)
    shoves: ShoveRanges = field(default_factory=ShoveRanges)
    robot: RobotRanges = field(default_factory=RobotRanges)
    sensors: SensorRanges = field(default_factory=SensorRanges)
    floor: FloorRanges = field(default_factory=FloorRanges)
    ceiling: CeilingRanges = field(default_factory=CeilingRanges)
    movers: MoverRanges = field(default_factory=MoverRanges)
    robot_classes: RobotClassWeights = field(default_factory=RobotClassWeights)

    def to_dict(self) -> dict[str, dict[str, Any]]:
        """Plain values (ranges as lists), the form of a ranges file and of the metadata."""
        return {
            f.name: {
                k: list(v) if isinstance(v, tuple) else v
                for k, v in dataclasses.asdict(getattr(self, f.name)).items()
            }
            for f in dataclasses.fields(self)
        }

    def to_toml(self) -> str:
        """The ranges as a TOML file that :func:`randomization_from_table` reads back."""
        lines = []
        for table, values in self.to_dict().items():
            lines.append(f"[{table}]")
            for key, value in values.items():
                text = f"[{value[0]!r}, {value[1]!r}]" if isinstance(value, list) else repr(value)
                lines.append(f"{key} = {text}")
            lines.append("")
        return "\n".join(lines)


def randomization_from_table(
    table: dict[str, Any], source: str | Path = "<table>"
) -> Randomization:
    """Apply a parsed ranges table on top of the defaults.

    Raises:
        ConfigError: an unknown table or key, or a value out of its bounds.
    """
    defaults = Randomization()
    known = {f.name for f in dataclasses.fields(defaults)}
    for key in table:
        if key not in known:
            raise ConfigError(source, key, f"unknown table (known: {', '.join(sorted(known))})")
    return Randomization(
        **{
            name: apply_overrides(getattr(defaults, name), table.get(name, {}), source, name)
            for name in known
        }
    )


def load_randomization(path: str | Path | None) -> Randomization:
    """The default ranges, overridden by the TOML file at ``path`` when given."""
    if path is None:
        return Randomization()
    path = Path(path)
    try:
        table = tomllib.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise ConfigError(path, "", "no such ranges file") from None
    except IsADirectoryError:
        raise ConfigError(path, "", "is a folder, not a ranges file") from None
    except UnicodeDecodeError as error:
        raise ConfigError(
            path, "", f"not UTF-8 text (byte {error.start}): not a TOML file"
        ) from None
    except tomllib.TOMLDecodeError as error:
        raise ConfigError(path, "", f"not valid TOML: {error}") from None
    return randomization_from_table(table, source=path)
