"""Where scenario files are: a path, or the name of one shipped in ``scenarios/``."""

from __future__ import annotations

from pathlib import Path

from twsb_sim.config_errors import ConfigError

SCENARIOS_DIR = Path(__file__).resolve().parents[1] / "scenarios"


def shipped_scenarios() -> list[str]:
    """The names of the shipped scenarios, sorted."""
    return sorted(p.stem for p in SCENARIOS_DIR.glob("*.toml"))


def resolve_scenario(name_or_path: str) -> Path:
    """A scenario file path, or the name of a shipped scenario (``hard_stop``).

    Raises:
        ConfigError: neither a file nor a shipped scenario.
    """
    path = Path(name_or_path)
    if path.is_file():
        return path
    shipped = SCENARIOS_DIR / f"{name_or_path.removesuffix('.toml')}.toml"
    if shipped.is_file():
        return shipped
    known = ", ".join(shipped_scenarios())
    raise ConfigError(name_or_path, "", f"no such scenario file (shipped scenarios: {known})")
