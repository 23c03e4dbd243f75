"""Labeled pitch-variation data sets: generate them, read them, export them to ROS bags.

Reading (:func:`open_dataset`, :class:`ScanDataset`, the schema) needs pyarrow and numpy
only; the generation side (:func:`generate`, :func:`run_episode`, ...) and the bag
export import the simulator or rosbags on first use.
"""

from __future__ import annotations

import importlib
from typing import Any

from twsb_sim.dataset.loader import (
    Episode,
    ScanDataset,
    ScanRecord,
    label_count_filter,
    open_dataset,
)
from twsb_sim.dataset.schema import COLUMNS, SCHEMA
from twsb_sim.dataset.store import DatasetMismatchError

_LAZY = {  # name: module, imported when the name is first used (they load MuJoCo)
    "Randomization": "twsb_sim.dataset.randomization",
    "load_randomization": "twsb_sim.dataset.randomization",
    "randomization_from_table": "twsb_sim.dataset.randomization",
    "GenerationReport": "twsb_sim.dataset.generate",
    "GenerationSettings": "twsb_sim.dataset.generate",
    "generate": "twsb_sim.dataset.generate",
    "EpisodeDraw": "twsb_sim.dataset.episode",
    "draw_episode": "twsb_sim.dataset.episode",
    "episode_seed_sequence": "twsb_sim.dataset.episode",
    "run_episode": "twsb_sim.dataset.episode",
    "export_bag": "twsb_sim.dataset.rosbag",
}

__all__ = [
    "COLUMNS",
    "SCHEMA",
    "DatasetMismatchError",
    "Episode",
    "ScanDataset",
    "ScanRecord",
    "label_count_filter",
    "open_dataset",
    *_LAZY,
]


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
