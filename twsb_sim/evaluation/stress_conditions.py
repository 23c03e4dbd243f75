"""The conditions of the stress matrix: one data-set ranges file each.

A condition is a family of episodes: the ranges file of ``twsb generate`` that draws them
(``scenarios/stress/<name>.toml``), so anyone can generate a data set of it::

    twsb generate --ranges scenarios/stress/people.toml --out data/people --episodes 100

``twsb eval --stress`` draws the first episodes of each family and evaluates every method
on them. More conditions join the matrix through :func:`register_condition`, which is also
the hook for the realistic sensors (a rotating sweep, LiDAR imperfections, an IMU attitude
estimate, wheel odometry): each becomes a condition once its ranges file can ask for it.
"""

from __future__ import annotations

from pathlib import Path

from twsb_sim.config_errors import ConfigError
from twsb_sim.dataset.randomization import Randomization, load_randomization

STRESS_DIR = Path(__file__).resolve().parents[2] / "scenarios" / "stress"
# the matrix's rows, in this order; each a ranges file in STRESS_DIR
CORE_CONDITIONS: tuple[str, ...] = (
    "baseline",
    "hard_stops",
    "strong_shoves",
    "shoves_turning",
    "thresholds_carpets",
    "ramps",
    "low_ceilings",
    "people",
    "doors",
    "high_lidar",
    "level_mount",
)
_REGISTERED: dict[str, Path] = {name: STRESS_DIR / f"{name}.toml" for name in CORE_CONDITIONS}


def register_condition(name: str, ranges_file: str | Path) -> None:
    """Add a condition to the stress matrix (after the core ones, in registration order).

    Args:
        name: the row's name.
        ranges_file: a ``twsb generate`` ranges file drawing its episodes.

    Raises:
        ConfigError: the name is taken or the file does not exist.
    """
    path = Path(ranges_file)
    if name in _REGISTERED:
        raise ConfigError(path, "", f"stress condition {name!r} exists already")
    if not path.is_file():
        raise ConfigError(path, "", "no such ranges file")
    _REGISTERED[name] = path


def condition_names() -> tuple[str, ...]:
    """Every condition of the matrix, in order."""
    return tuple(_REGISTERED)


def condition_ranges(name: str) -> Randomization:
    """The ranges that draw a condition's episodes.

    Raises:
        ConfigError: an unknown condition, or a bad ranges file (naming file and key).
    """
    if name not in _REGISTERED:
        known = ", ".join(_REGISTERED)
        raise ConfigError("--conditions", "", f"unknown stress condition {name!r} (known: {known})")
    return load_randomization(_REGISTERED[name])
