"""What an evaluation runs: sequences, houses, seeds and the threshold sweeps.

The defaults are the full evaluation (``twsb eval``); :meth:`EvalConfig.quick` is the
smoke-test variant (``twsb eval --quick``), which runs the same code on less data.
"""

from __future__ import annotations

import dataclasses

from pvfilter.labelled import THRESHOLD_SWEEP

SEQUENCES: tuple[str, ...] = ("normal_sequence", "disturb_sequence")  # the paper's IV-C data
DEFAULT_HOUSES: tuple[str, ...] = ("house1", "house2", "random:1", "random:2")
MATCHERS: tuple[str, ...] = ("icp", "ndt", "hsm")
FAMILIES: tuple[str, ...] = ("pvf", "pvf_detection_only", "datmo", "imu_gate", "imu_gate_truth")

# the P_th sweep: dense near 1, where the filter's operating points are (the one
# ``pvfilter eval-labels`` sweeps on labelled scan files)
P_TH_VALUES: tuple[float, ...] = THRESHOLD_SWEEP
# the DATMO-like speed threshold sweep, m/s; the paper's 0.1, 0.2 and 0.3 are in it
DATMO_SPEEDS_MPS: tuple[float, ...] = (
    0.02, 0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 5.0,
)  # fmt: skip
PAPER_DATMO_SPEEDS_MPS: tuple[float, ...] = (0.1, 0.2, 0.3)
# the IMU height gate's half-band sweep, m: beams ending farther than this above or below
# the scanner's mounting height are dropped (beyond the mounting height, 0.25 m, the
# floor is never dropped; beyond the ceiling's distance, nothing is)
IMU_BANDS_M: tuple[float, ...] = (
    0.02, 0.05, 0.1, 0.15, 0.2, 0.22, 0.24, 0.3, 0.5, 1.0, 2.0, 3.0,
)  # fmt: skip
DEFAULT_IMU_BAND_M = 0.2  # m, the gate's operating point in the timing pass
# robustness runs (--variations): random houses no other part of the evaluation uses, and
# robots that differ from the default one in one respect each
HELDOUT_HOUSES: tuple[str, ...] = ("random:101", "random:102", "random:103", "random:104")
VARIATION_HOUSES: tuple[str, ...] = ("random:101", "random:102")
ROBOT_VARIATIONS: dict[str, dict[str, dict[str, float]]] = {
    "default robot": {},
    "LiDAR at 0.15 m": {"robot": {"lidar_height_m": 0.15}},
    "LiDAR at 0.40 m": {"robot": {"lidar_height_m": 0.40}},
    "range noise 1 cm": {"lidar": {"range_noise_std_m": 0.01}},
    "range noise 5 cm": {"lidar": {"range_noise_std_m": 0.05}},
    "softer balance (aggressiveness 0.5)": {"controller": {"aggressiveness": 0.5}},
    "stiffer balance (aggressiveness 2)": {"controller": {"aggressiveness": 2.0}},
}


@dataclasses.dataclass(frozen=True)
class EvalConfig:
    """Everything an evaluation run needs.

    Attributes:
        sequences: shipped scenario names, each run in every house with every seed.
        houses: ``house1``, ``house2`` or ``random:<seed>`` (a random house).
        seeds: run seeds (they draw the LiDAR noise; the physics is deterministic).
        p_th_values: the filter's P_th sweep (paper Fig. 4).
        datmo_speeds_mps: the DATMO-like tracker's speed-threshold sweep, m/s.
        imu_bands_m: the IMU height gate's half-band sweep, m.
        families: the methods compared: ``pvf`` (detection + tracking),
            ``pvf_detection_only``, ``datmo`` (the DATMO-like tracker), ``imu_gate`` (on
            the robot's attitude estimate), ``imu_gate_truth`` (on the true attitude).
        matchers: scan matchers of the section IV-D experiment (scaneval names).
        duration_s: cut every sequence to this many simulated seconds (None: whole).
        max_events_per_run: at most this many pitch-variation events per run go to the
            scan-matching experiment (None: all).
        example_frames: example frames pictured per sequence by the miss diagnosis.
        improved: also evaluate the improved filter (side by side, ablation).
        improved_params: a parameter file of tuned improved-filter parameters to compare
            too (``twsb tune`` writes one), or None.
        variations: also run the robustness runs: the sequences in ``heldout_houses``,
            and in ``variation_houses`` with every robot of ``robot_variations``.
        heldout_houses: houses for the held-out runs.
        variation_houses: houses for the robot-variation runs.
        robot_variations: name -> overrides (tables ``robot``, ``lidar``, ``controller``
            of a scenario file).
    """

    sequences: tuple[str, ...] = SEQUENCES
    houses: tuple[str, ...] = DEFAULT_HOUSES
    seeds: tuple[int, ...] = (0, 1, 2)
    p_th_values: tuple[float, ...] = P_TH_VALUES
    datmo_speeds_mps: tuple[float, ...] = DATMO_SPEEDS_MPS
    imu_bands_m: tuple[float, ...] = IMU_BANDS_M
    families: tuple[str, ...] = FAMILIES
    matchers: tuple[str, ...] = MATCHERS
    duration_s: float | None = None
    max_events_per_run: int | None = None
    example_frames: int = 3
    improved: bool = True
    improved_params: str | None = None
    variations: bool = False
    heldout_houses: tuple[str, ...] = HELDOUT_HOUSES
    variation_houses: tuple[str, ...] = VARIATION_HOUSES
    robot_variations: dict = dataclasses.field(default_factory=lambda: dict(ROBOT_VARIATIONS))

    def __post_init__(self) -> None:
        if not self.sequences or not self.houses or not self.seeds:
            raise ValueError("sequences, houses, seeds: each needs at least one entry")
        if any(seed < 0 for seed in self.seeds):
            raise ValueError(f"seeds: must be >= 0, got {self.seeds}")
        for house in self.houses:
            parse_house(house)
        if "pvf" not in self.families or not set(self.families) <= set(FAMILIES):
            raise ValueError(f"families: pvf and any of {', '.join(FAMILIES)}, got {self.families}")
        for house in (*self.heldout_houses, *self.variation_houses):
            parse_house(house)

    @classmethod
    def quick(cls, **overrides: object) -> EvalConfig:
        """A smoke run: one house and seed, 8 s of each sequence, coarse sweeps."""
        settings = dict(
            houses=("house1",),
            seeds=(0,),
            p_th_values=(0.0, 0.5, 0.8, 0.95, 0.99),
            datmo_speeds_mps=(0.1, 0.2, 0.3, 1.0),
            imu_bands_m=(0.05, 0.2, 0.5),
            duration_s=8.0,
            max_events_per_run=2,
            example_frames=1,
            heldout_houses=("random:101",),
            variation_houses=("random:101",),
            robot_variations={k: ROBOT_VARIATIONS[k] for k in ("default robot", "LiDAR at 0.15 m")},
        )
        return cls(**{**settings, **overrides})


def parse_house(text: str) -> tuple[str | None, int | None]:
    """``"house1"`` -> ("house1", None); ``"random:7"`` -> (None, 7).

    Raises:
        ValueError: for anything else.
    """
    from twsb_sim.house import NAMED_HOUSES

    if text in NAMED_HOUSES:
        return text, None
    prefix, _, seed = text.partition(":")
    if prefix == "random" and seed.isdigit():
        return None, int(seed)
    known = ", ".join(sorted(NAMED_HOUSES))
    raise ValueError(f"houses: expected one of {known} or random:<seed>, got {text!r}")
