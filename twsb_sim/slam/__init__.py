"""SLAM in the loop (paper §IV-E, Table II, Fig. 8) with the simulator's exact truth.

``twsb slam --out DIR`` simulates the House sequences and hard stops in random houses
once per seed, runs the Hector-style SLAM and KISS-ICP (:mod:`scaneval.slam`) over the
scans with no filter, the PVF, the IMU height gate and the truth labels, and writes the
ATE table beside the paper's, the maps, the trajectories, TUM files and Rerun recordings.

The names below load on first use, so the ``twsb`` command line, which registers
``slam`` from :mod:`twsb_sim.slam.cli`, starts without importing them.
"""

from __future__ import annotations

from twsb_sim.lazy_exports import lazy_exports

_HOMES = {  # public name -> the module that holds it
    "SequenceOutcome": "experiment",
    "SlamConfig": "experiment",
    "SlamRunResult": "experiment",
    "run_sequence": "experiment",
    "draw_maps": "figures",
    "draw_trajectories": "figures",
    "METHODS": "methods",
    "removed_masks": "methods",
    "SlamOutputs": "pipeline",
    "run_slam_experiment": "pipeline",
    "record_frames": "recording",
    "write_report": "report",
    "write_results": "report",
    "record_sequence": "rerun_slam",
    "SlamSequence": "sequences",
    "hard_stop_sequence": "sequences",
    "shipped_sequence": "sequences",
    "SYSTEMS": "systems",
    "run_system": "systems",
}
__getattr__, __all__ = lazy_exports(__name__, _HOMES)
