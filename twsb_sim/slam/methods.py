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

import numpy as np

from twsb_sim.frame import Frame
from twsb_sim.labels import is_pitch_variation
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


def removed_masks(method: str, frames: Sequence[Frame], scenario: Scenario) -> list[np.ndarray]:
    """The beams ``method`` removes from every frame's scan, in time order.

    Args:
        method: one of :data:`METHODS`.
        frames: a run's frames, in time order.
        scenario: the run's scenario (the robot's dimensions, for the IMU gate).

    Returns:
        One bool mask per frame, True = removed.
    """
    if method == "none":
        return [np.zeros(len(f.scan), dtype=bool) for f in frames]
    if method == "truth_labels":
        return [is_pitch_variation(f.labels) for f in frames]
    if method in ("pvf", "pvf_p04"):
        from pvfilter import FilterParams, PitchVariationFilter

        pvf = PitchVariationFilter(FilterParams(p_th=LOW_P_TH) if method == "pvf_p04" else None)
        return [pvf.process(f.scan).removed for f in frames]
    if method == "improved":
        from pvfilter import ImprovedParams, ImprovedPitchVariationFilter

        improved = ImprovedPitchVariationFilter(
            ImprovedParams(lidar_height_m=scenario.robot.lidar_height_m)
        )
        return [improved.process(f.scan).removed for f in frames]
    if method == "imu_gate":
        from scaneval.baselines import ImuHeightGate
        from twsb_sim.evaluation.methods import imu_pitch_roll

        gate = ImuHeightGate(
            scenario.robot.lidar_height_m,
            band_m=IMU_GATE_BAND_M,
            axle_height_m=scenario.robot.wheel_radius_m,
        )
        return [gate.process(f.scan, *imu_pitch_roll(f.truth.imu_quat)) for f in frames]
    raise ValueError(f"method: expected one of {', '.join(METHODS)}, got {method!r}")
