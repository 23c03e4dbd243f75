"""A small data set, generated once per test session and shared (read-only) by the tests."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pyarrow.parquet as pq
import pytest

from twsb_sim.dataset.generation import GenerationSettings, generate
from twsb_sim.dataset.randomization import randomization_from_table
from twsb_sim.dataset.schema import SENSOR_COLUMNS

SEED = 11
EPISODES = 12
# short episodes (2-3 s, 21-31 scans) with shoves and turns likely, so a run takes seconds
SHORT = {
    "episode": {"duration_s": [2.0, 3.0]},
    "motion": {"pause_s": [0.2, 0.6]},
    "shoves": {"probability": 0.6},
}
SHORT_TOML = """\
[episode]
duration_s = [2.0, 3.0]
[motion]
pause_s = [0.2, 0.6]
[shoves]
probability = 0.6
"""


@pytest.fixture(scope="session")
def short_settings() -> GenerationSettings:
    return GenerationSettings(seed=SEED, randomization=randomization_from_table(SHORT))


@pytest.fixture(scope="session")
def short_ranges_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("ranges") / "short.toml"
    path.write_text(SHORT_TOML)
    return path


@pytest.fixture(scope="session")
def reference(tmp_path_factory: pytest.TempPathFactory, short_settings) -> Path:
    """EPISODES episodes generated in this process, uninterrupted."""
    root = tmp_path_factory.mktemp("reference") / "data"
    generate(root, EPISODES, short_settings, workers=1, progress=False)
    return root


def shard_bytes(root: Path) -> dict[str, bytes]:
    """Every shard of a data set by its relative path."""
    return {str(p.relative_to(root)): p.read_bytes() for p in sorted(root.glob("data/*/*"))}


def as_format_1(reference: Path, root: Path) -> None:
    """A copy of ``reference`` as format 1 wrote it: no sensor columns, format 1 in info."""
    shutil.copytree(reference, root)
    info_path = root / "meta" / "info.json"
    info = json.loads(info_path.read_text())
    info["format_version"] = info["settings"]["format_version"] = 1
    info_path.write_text(json.dumps(info))
    sensor_names = [name for name, _, _ in SENSOR_COLUMNS]
    for path in root.glob("data/*/*.parquet"):
        table = pq.read_table(path)
        pq.write_table(table.drop_columns(sensor_names), path)
