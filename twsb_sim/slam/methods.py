"""The scan filters compared in the SLAM experiment: each turns a frame into a removed mask.

- ``none``: removes nothing (the paper's "w/o");
- ``pvf``: the Pitch Variation Filter with Table I's parameters (the paper's "w/");
- ``pvf_p04``: the same filter at P_th = 0.4, the best-F1 point of ``twsb eval``'s P_th
  sweep on the simulator's sequences (Table I's 0.8 keeps recall near 2 % there);
- ``improved``: the improved filter (``pvfilter.ImprovedPitchVariationFilter``, defaults,
  told the robot's LiDAR height; scans only, no IMU);
- ``imu_gate``: the IMU height gate, what Hector-SLAM and Cartographer users do when an
  IMU is present: beams ending outside 0.05-2.0 m above the floor, by the IMU's pitch and
  roll, are removed (floor and ceiling hits);
- ``truth_labels``: the simulator's ground truth removes exactly the pitch-variation
  beams, the bound a perfect filter would reach (no real robot has it).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from pvfilter import filter_entry
from twsb_sim.filter_args import robot_geometry
from twsb_sim.frame import Frame
from twsb_sim.labels import is_pitch_variation
from twsb_sim.robot_inputs import robot_inputs
from twsb_sim.scenario import Scenario

METHODS: tuple[str, ...] = ("none", "pvf", "pvf_p04", "improved", "imu_gate", "truth_labels")
METHOD_TITLES = {
    "none": "no filter",
    "pvf": "PVF",
    "pvf_p04": "PVF, P_th 0.4",
    "improved": "improved filter",
    "imu_gate": "IMU height gate",
    "truth_labels": "truth labels",
}
IMU_GATE_BAND_M = (0.05, 2.0)  # m above the floor: the gate keeps beams ending in here
LOW_P_TH = 0.4  # the PVF's best-F1 threshold in twsb eval (precision 0.7-0.8, recall ~0.4)
# method -> (registered filter, parameter values); "truth_labels" is the oracle, no filter
FILTERS: dict[str, tuple[str, dict[str, Any]]] = {
    "none": ("none", {}),
    "pvf": ("paper", {}),
    "pvf_p04": ("paper", {"p_th": LOW_P_TH}),
    "improved": ("improved", {}),
    "imu_gate": ("imu_gate", {"band_low_m": IMU_GATE_BAND_M[0], "band_high_m": IMU_GATE_BAND_M[1]}),
}


def removed_masks(method: str, frames: Sequence[Frame], scenario: Scenario) -> list[np.ndarray]:
    """The beams ``method`` removes from every frame's scan, in time order.

    Args:
        method: one of :data:`METHODS`.
        frames: a run's frames, in time order.
        scenario: the run's scenario (the robot's dimensions, for the filters that use them).

    Returns:
        One bool mask per frame, True = removed.
    """
    if method == "truth_labels":
        return [is_pitch_variation(f.labels) for f in frames]
    if method not in FILTERS:
        raise ValueError(f"method: expected one of {', '.join(METHODS)}, got {method!r}")
    name, fields = FILTERS[method]
    entry = filter_entry(name)
    scan_filter = entry.make(robot_geometry=robot_geometry(scenario), **fields)
    # each filter gets the inputs it needs: the improved filter runs on scans alone here
    return [scan_filter.process(f.scan, **robot_inputs(f, entry.needs)).removed for f in frames]
