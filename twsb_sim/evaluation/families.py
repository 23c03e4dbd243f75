"""The filter families of the paper's experiments: a registered filter, a label, a sweep.

Each family is one registered filter whose one parameter is swept for a PR curve (P_th,
the DATMO-like speed, the IMU gate's band) and that runs at one operating point in the
timed pass. The DATMO-like tracker gets the sensor's true pose, as the paper fed DATMO
SLAM poses; the IMU gate gets the robot's attitude estimate (noisy, lagging), and once
more the true attitude, so the report shows what the realistic estimate costs.
"""

from __future__ import annotations

from pvfilter import FilterParams
from twsb_sim.evaluation.config import DEFAULT_IMU_BAND_M, PAPER_DATMO_SPEEDS_MPS, EvalConfig
from twsb_sim.evaluation.recording import Recording
from twsb_sim.frame_filter import FrameFilter, frame_filter

# filter families: key -> label; each has a sweep and an operating point
LABELS: dict[str, str] = {
    "pvf": "PVF (detection + tracking)",
    "pvf_detection_only": "PVF (detection only)",
    "datmo": "DATMO-like",
    "imu_gate": "IMU height gate",
    "imu_gate_truth": "IMU height gate (true attitude)",
}
OPERATING_POINTS = {  # the value each family runs at in the timed pass
    "pvf": FilterParams().p_th,
    "pvf_detection_only": FilterParams().p_th,
    "datmo": PAPER_DATMO_SPEEDS_MPS[0],
    "imu_gate": DEFAULT_IMU_BAND_M,
    "imu_gate_truth": DEFAULT_IMU_BAND_M,
}
SWEPT = {
    "pvf": "P_th",
    "pvf_detection_only": "P_th",
    "datmo": "speed, m/s",
    "imu_gate": "band, m",
    "imu_gate_truth": "band, m",
}
FILTERS = {
    "pvf": "paper",
    "pvf_detection_only": "paper",
    "datmo": "datmo",
    "imu_gate": "imu_gate",
    "imu_gate_truth": "imu_gate",
}


def family_filter(family: str, value: float, recording: Recording) -> FrameFilter:
    """The registered filter of a family at one swept value."""
    name, label = FILTERS[family], LABELS[family]
    if family == "pvf":
        return frame_filter(name, label, p_th=value)
    if family == "pvf_detection_only":
        return frame_filter(name, label, p_th=value, tracking=False)
    if family == "datmo":
        return frame_filter(name, label, truth_inputs=True, speed_threshold_mps=value)
    # the IMU gate keeps a band of +/- value around the scanner's height
    height = recording.geometry["lidar_height_m"]
    band = {"band_low_m": height - value, "band_high_m": height + value}
    truth = family == "imu_gate_truth"
    return frame_filter(name, label, geometry=recording.geometry, truth_inputs=truth, **band)


def sweep_values(config: EvalConfig, family: str) -> tuple[float, ...]:
    """The values a family's sweep runs over."""
    if family.startswith("pvf"):
        return config.p_th_values
    return config.datmo_speeds_mps if family == "datmo" else config.imu_bands_m  # both gates
