"""Scenario files: what the robot is told to do, where, and with which parameters.

A scenario is a TOML file (see ``scenarios/`` and the README's "Scenario files"):

.. code-block:: toml

    name = "hard_stop"
    duration_s = 8.0
    [house]
    name = "house1"          # or: seed = 12 (a random house); spawn = 0 (which start pose)
    [[commands]]
    t_s = 1.0
    velocity_mps = 1.0
    ramp_s = 1.5
    [[shoves]]
    t_s = 5.0
    force_n = [60.0, 0.0, 0.0]
    [robot]                  # overrides of RobotConfig, LidarConfig, LqrConfig, SimulationConfig,
    lidar_height_m = 0.30    # ImuConfig, AttitudeFilterConfig, OdometryConfig
    [lidar]
    sweep = "instant"        # a global-shutter scan (default: "rotating")
    [imu]
    rate_hz = 400.0

Every mistake is reported as a :class:`~twsb_sim.config_errors.ConfigError` naming the
file, the key and what was expected, so the command line prints one line, not a
traceback.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from twsb_sim.config_errors import ConfigError, apply_overrides, coerce_value
from twsb_sim.control.balance import BalanceConfig
from twsb_sim.control.lqr import LqrConfig
from twsb_sim.environment import ENVIRONMENT_KEYS, Environment, environment_from_table
from twsb_sim.house.named import NAMED_HOUSES
from twsb_sim.lidar import LidarConfig
from twsb_sim.robot import RobotConfig
from twsb_sim.sensors.attitude import AttitudeFilterConfig
from twsb_sim.sensors.imu import ImuConfig
from twsb_sim.sensors.odometry import OdometryConfig
from twsb_sim.timeline import CommandPoint, Shove

MAX_VELOCITY_MPS = 2.0  # m/s, beyond what a small home TWSB robot can do
MAX_YAW_RATE_RAD_S = 3.0  # rad/s
MAX_SHOVE_FORCE_N = 500.0  # N
MAX_DURATION_S = 3600.0  # s
MAX_SHOVE_POINT_M = 1.0  # m, per body-frame coordinate: a push lands on the robot
MAX_START_YAW_DEG = 360.0  # deg


@dataclass(frozen=True)
class SimulationConfig:
    """How the run itself behaves."""

    fall_pitch_deg: float = 45.0  # deg, |pitch| or |roll| beyond which the robot has fallen

    def __post_init__(self) -> None:
        if not 5.0 <= self.fall_pitch_deg <= 90.0:
            raise ValueError(f"fall_pitch_deg: expected 5 to 90 deg, got {self.fall_pitch_deg}")


@dataclass(frozen=True)
class HouseChoice:
    """Which house to build and where the robot starts in it.

    Exactly one of ``name`` (a fixed layout: ``house1``, ``house2``) or ``seed`` (a
    random house). The start is spawn pose number ``spawn`` of the house, unless
    ``start`` gives an explicit pose ``(x_m, y_m, yaw_deg)``.
    """

    name: str | None = "house1"
    seed: int | None = None
    spawn: int = 0
    start: tuple[float, float, float] | None = None  # (m, m, deg)

    def __post_init__(self) -> None:
        if (self.name is None) == (self.seed is None):
            raise ValueError("name: give exactly one of house.name or house.seed")
        if self.spawn < 0:
            raise ValueError(f"spawn: expected a spawn pose index >= 0, got {self.spawn}")
        if self.seed is not None and self.seed < 0:
            raise ValueError(f"seed: expected an integer >= 0, got {self.seed}")
        if self.name is not None and self.name not in NAMED_HOUSES:
            raise ValueError(
                f"name: expected one of {sorted(NAMED_HOUSES)} (or house.seed for a random"
                f" house), got {self.name!r}"
            )
        if self.start is not None:
            yaw_deg = self.start[2]
            if not all(math.isfinite(v) for v in self.start):
                raise ValueError(f"start: expected finite (x m, y m, yaw deg), got {self.start}")
            if abs(yaw_deg) > MAX_START_YAW_DEG:
                raise ValueError(
                    f"start: expected a yaw within +-{MAX_START_YAW_DEG:g} deg, got {yaw_deg:g}"
                )


@dataclass(frozen=True)
class Scenario:
    """Everything a run needs besides its seed."""

    name: str
    duration_s: float  # s of simulated time, after settling
    house: HouseChoice = field(default_factory=HouseChoice)
    commands: tuple[CommandPoint, ...] = ()
    shoves: tuple[Shove, ...] = ()
    robot: RobotConfig = field(default_factory=RobotConfig)
    lidar: LidarConfig = field(default_factory=LidarConfig)
    controller: LqrConfig = field(default_factory=LqrConfig)
    simulation: SimulationConfig = field(default_factory=SimulationConfig)
    imu: ImuConfig = field(default_factory=ImuConfig)
    attitude: AttitudeFilterConfig = field(default_factory=AttitudeFilterConfig)
    odometry: OdometryConfig = field(default_factory=OdometryConfig)
    description: str = ""
    seed: int = 0  # default seed; the command line's --seed wins
    source: str = "<code>"  # the file it was read from
    environment: Environment = field(default_factory=Environment)  # floor, ceilings, movers
    balance: BalanceConfig = field(default_factory=BalanceConfig)  # LQR or PID, stop brake


_TOP_LEVEL_SCALARS = {"name": str, "description": str, "duration_s": float, "seed": int}
_OVERRIDE_TABLES = {
    "robot": RobotConfig,
    "lidar": LidarConfig,
    "controller": LqrConfig,
    "simulation": SimulationConfig,
    "imu": ImuConfig,
    "attitude": AttitudeFilterConfig,
    "odometry": OdometryConfig,
    "balance": BalanceConfig,
}
_KNOWN_KEYS = {
    *_TOP_LEVEL_SCALARS,
    *_OVERRIDE_TABLES,
    "house",
    "commands",
    "shoves",
    *ENVIRONMENT_KEYS,
}


def load_scenario(path: str | Path) -> Scenario:
    """Read and validate a scenario file.

    Raises:
        ConfigError: the file is missing, is not valid TOML, or holds a key or value
            we cannot use; the message names the file and the key.
    """
    path = Path(path)
    try:
        table = tomllib.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise ConfigError(path, "", "no such scenario file") from None
    except IsADirectoryError:
        raise ConfigError(path, "", "is a folder, not a scenario file") from None
    except UnicodeDecodeError as error:
        raise ConfigError(
            path, "", f"not UTF-8 text (byte {error.start}): not a TOML file"
        ) from None
    except tomllib.TOMLDecodeError as error:
        raise ConfigError(path, "", f"not valid TOML: {error}") from None
    return scenario_from_table(table, source=path, default_name=path.stem)


def scenario_from_table(
    table: dict[str, Any], source: str | Path = "<table>", default_name: str = "scenario"
) -> Scenario:
    """Validate a parsed scenario table (the body of a scenario file)."""
    for key in table:
        if key not in _KNOWN_KEYS:
            raise ConfigError(
                source, key, f"unknown key (known keys: {', '.join(sorted(_KNOWN_KEYS))})"
            )
    if "duration_s" not in table:
        raise ConfigError(source, "duration_s", "missing: the simulated time of the run, in s")
    scalars = {
        k: coerce_value(table[k], tp, source, k)
        for k, tp in _TOP_LEVEL_SCALARS.items()
        if k in table
    }
    duration_s = scalars["duration_s"]
    if not 0.0 < duration_s <= MAX_DURATION_S:
        raise ConfigError(
            source,
            "duration_s",
            f"expected 0 < duration_s <= {MAX_DURATION_S:g} s, got {duration_s}",
        )
    if scalars.get("seed", 0) < 0:
        raise ConfigError(source, "seed", f"expected an integer >= 0, got {scalars['seed']}")
    overrides = {
        name: apply_overrides(config_type(), table.get(name, {}), source, name)
        for name, config_type in _OVERRIDE_TABLES.items()
    }
    return Scenario(
        name=scalars.get("name", default_name),
        description=scalars.get("description", ""),
        duration_s=duration_s,
        seed=scalars.get("seed", 0),
        house=apply_overrides(
            HouseChoice(), _house_table(table.get("house", {}), source), source, "house"
        ),
        commands=_commands(table.get("commands", []), duration_s, source),
        shoves=_shoves(table.get("shoves", []), duration_s, source),
        source=str(source),
        environment=environment_from_table(table, source),
        **overrides,
    )


def _house_table(table: Any, source: str | Path) -> Any:
    # a seed picks a random house, so it replaces the default named layout
    if isinstance(table, dict) and "seed" in table and "name" not in table:
        return {"name": None, **table}
    return table


def _array_of_tables(value: Any, source: str | Path, key: str) -> list[dict[str, Any]]:
    if not isinstance(value, list) or not all(isinstance(v, dict) for v in value):
        raise ConfigError(source, key, f"expected an array of tables ([[{key}]]), got {value!r}")
    return value


def _commands(value: Any, duration_s: float, source: str | Path) -> tuple[CommandPoint, ...]:
    points = []
    for i, row in enumerate(_array_of_tables(value, source, "commands")):
        where = f"commands[{i}]"
        if "t_s" not in row:
            raise ConfigError(source, f"{where}.t_s", "missing: the time the command starts, in s")
        point = apply_overrides(CommandPoint(t_s=0.0), row, source, where)
        _check_range(source, f"{where}.t_s", point.t_s, 0.0, duration_s, "s")
        _check_range(source, f"{where}.ramp_s", point.ramp_s, 0.0, duration_s, "s")
        _check_range(
            source,
            f"{where}.velocity_mps",
            point.velocity_mps,
            -MAX_VELOCITY_MPS,
            MAX_VELOCITY_MPS,
            "m/s",
        )
        _check_range(
            source,
            f"{where}.yaw_rate_rad_s",
            point.yaw_rate_rad_s,
            -MAX_YAW_RATE_RAD_S,
            MAX_YAW_RATE_RAD_S,
            "rad/s",
        )
        if points and point.t_s < points[-1].t_s + points[-1].ramp_s:
            previous_end = points[-1].t_s + points[-1].ramp_s
            raise ConfigError(
                source,
                f"{where}.t_s",
                f"times out of order: starts at {point.t_s} s, before the previous"
                f" command's ramp ends at {previous_end} s",
            )
        points.append(point)
    return tuple(points)


def _shoves(value: Any, duration_s: float, source: str | Path) -> tuple[Shove, ...]:
    shoves = []
    for i, row in enumerate(_array_of_tables(value, source, "shoves")):
        where = f"shoves[{i}]"
        for required in ("t_s", "force_n"):
            if required not in row:
                raise ConfigError(source, f"{where}.{required}", "missing")
        shove = apply_overrides(Shove(t_s=0.0, force_n=(0.0, 0.0, 0.0)), row, source, where)
        _check_range(source, f"{where}.t_s", shove.t_s, 0.0, duration_s, "s")
        _check_range(source, f"{where}.duration_s", shove.duration_s, 1e-3, 5.0, "s")
        magnitude = math.hypot(*shove.force_n)
        _check_range(source, f"{where}.force_n", magnitude, 0.0, MAX_SHOVE_FORCE_N, "N (magnitude)")
        for axis, value in zip("xyz", shove.point_m, strict=True):
            _check_range(
                source,
                f"{where}.point_m",
                value,
                -MAX_SHOVE_POINT_M,
                MAX_SHOVE_POINT_M,
                f"m ({axis} in the body frame)",
            )
        if shoves and shove.t_s < shoves[-1].t_s:
            raise ConfigError(
                source,
                f"{where}.t_s",
                f"times out of order: {shove.t_s} s after {shoves[-1].t_s} s",
            )
        shoves.append(shove)
    return tuple(shoves)


def _check_range(
    source: str | Path, key: str, value: float, low: float, high: float, unit: str
) -> None:
    if not low <= value <= high:
        raise ConfigError(source, key, f"expected {low:g} to {high:g} {unit}, got {value:g}")
