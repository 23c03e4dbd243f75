"""Labeled pitch-variation data sets: generate them, read them, export them to ROS bags.

Reading (:func:`open_dataset`, :class:`ScanDataset`, the schema) needs pyarrow and numpy
only; generating (:func:`generate`, :func:`run_episode`, ...) loads the simulator, and
the bag export rosbags. Names are imported on first use, so importing this package
costs nothing and reading a data set never loads MuJoCo.
"""

from __future__ import annotations

from twsb_sim.lazy_exports import lazy_exports

_MODULES = {  # public name: the module that defines it
    "COLUMNS": "schema",
    "SCHEMA": "schema",
    "Episode": "loader",
    "ScanDataset": "loader",
    "ScanRecord": "loader",
    "label_count_filter": "loader",
    "open_dataset": "loader",
    "DatasetMismatchError": "store",
    "DatasetFormatWarning": "loader",
    "Randomization": "randomization",
    "load_randomization": "randomization",
    "randomization_from_table": "randomization",
    "GenerationReport": "generation",
    "GenerationSettings": "generation",
    "generate": "generation",
    "EpisodeDraw": "episode",
    "draw_episode": "episode",
    "episode_seed_sequence": "episode",
    "run_episode": "episode",
    "export_bag": "rosbag",
}

__getattr__, __all__ = lazy_exports(__name__, _MODULES)
