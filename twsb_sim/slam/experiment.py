"""The SLAM experiment (paper §IV-E, Table II, Fig. 8), with the simulator's exact truth.

Recipe: simulate each sequence once per seed (no filter in the loop); compute every
filter's removed beams over the recorded frames; run every SLAM system over the scans
minus those beams; score each trajectory against the LiDAR's true planar pose (ATE, eq. 7,
after an SE(2) alignment; tracking failure as :mod:`scaneval.slam.scoring` defines it).
The truth is the sensor's pose, not the base's: the scan is taken from the sensor, which
moves with pitch (about 4 cm at 14 deg), and a 2D SLAM estimates the sensor. Export
the trajectories as TUM files; draw the maps and trajectories of each sequence's first
seed, and record them for Rerun.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from pathlib import Path

import numpy as np

from scaneval.slam import score_trajectory
from scaneval.tum import write_tum
from twsb_sim.frame import Frame
from twsb_sim.labels import is_pitch_variation
from twsb_sim.robot_inputs import sensor_pose_2d
from twsb_sim.slam.methods import METHODS, removed_masks
from twsb_sim.slam.recording import record_frames
from twsb_sim.slam.sequences import SHIPPED_SEQUENCES, SlamSequence, hard_stop_sequence
from twsb_sim.slam.sequences import shipped_sequence as load_shipped
from twsb_sim.slam.systems import SYSTEMS, SystemRun, available_systems, run_system

RANDOM_HOUSE_SEEDS: tuple[int, ...] = (1, 2, 3, 4)


@dataclasses.dataclass(frozen=True)
class SlamConfig:
    """What the experiment runs.

    Attributes:
        sequences: shipped scenarios (the paper's House sequences by default).
        random_houses: seeds of the random houses, each with a hard-stop sequence.
        seeds: run seeds (the LiDAR's range noise; the physics is deterministic).
        methods: filters, see :mod:`twsb_sim.slam.methods`.
        systems: SLAM systems, see :mod:`twsb_sim.slam.systems` (those not installed are
            skipped).
        duration_s: cut every sequence to this many simulated seconds; None keeps all.
    """

    sequences: tuple[str, ...] = SHIPPED_SEQUENCES
    random_houses: tuple[int, ...] = RANDOM_HOUSE_SEEDS
    seeds: tuple[int, ...] = (0, 1, 2)
    methods: tuple[str, ...] = METHODS
    systems: tuple[str, ...] = SYSTEMS
    duration_s: float | None = None

    def __post_init__(self) -> None:
        if not self.seeds or any(seed < 0 for seed in self.seeds):
            raise ValueError(f"seeds: need at least one seed, all >= 0, got {self.seeds}")
        if not self.sequences and not self.random_houses:
            raise ValueError("sequences, random_houses: need at least one sequence")
        for name, allowed in (("methods", METHODS), ("systems", SYSTEMS)):
            unknown = set(getattr(self, name)) - set(allowed)
            if unknown:
                raise ValueError(f"{name}: unknown {sorted(unknown)}, known {list(allowed)}")

    @classmethod
    def quick(cls) -> SlamConfig:
        """A smoke run: house2_multi and one random house, one seed, 20 s each."""
        return cls(sequences=("house2_multi",), random_houses=(1,), seeds=(0,), duration_s=20.0)

    def slam_sequences(self) -> list[SlamSequence]:
        """Every sequence to run, shipped first, cut to ``duration_s``."""
        sequences = [load_shipped(name) for name in self.sequences]
        sequences += [hard_stop_sequence(seed) for seed in self.random_houses]
        return [cut(sequence, self.duration_s) for sequence in sequences]


def cut(sequence: SlamSequence, duration_s: float | None) -> SlamSequence:
    """The sequence with only its first ``duration_s`` simulated seconds (None: whole)."""
    scenario = sequence.scenario
    if duration_s is None or duration_s >= scenario.duration_s:
        return sequence
    scenario = dataclasses.replace(
        scenario,
        duration_s=duration_s,
        commands=tuple(c for c in scenario.commands if c.t_s + c.ramp_s <= duration_s),
        shoves=tuple(s for s in scenario.shoves if s.end_s <= duration_s),
    )
    return dataclasses.replace(sequence, scenario=scenario)


@dataclasses.dataclass(frozen=True)
class SlamRunResult:
    """One SLAM system on one filtered sequence: a row of ``results.json``.

    Attributes:
        sequence, house, seed: the recording.
        system, method: the SLAM system and the filter.
        ate_m: ATE RMSE (eq. 7) after the SE(2) alignment, m; NaN without an estimate.
        max_error_m: the largest aligned position error, m.
        failed: a tracking failure (the table's "–").
        failure: why, in words ("" when it did not fail).
        scans: scans in the sequence.
        slam_s: wall time of the SLAM loop, s.
        removed_beams: beams the filter removed over the sequence.
        removed_pitch_variation_beams: of those, beams labelled pitch-variation.
        pitch_variation_beams: valid pitch-variation beams in the sequence (truth).
        trajectory_file, truth_file: TUM files, relative to the output folder.
        alignment: the SE(2) alignment ``(x, y, theta)`` that maps the estimate onto the
            truth (m, m, rad); NaN without an estimate.
    """

    sequence: str
    house: str
    seed: int
    system: str
    method: str
    ate_m: float
    max_error_m: float
    failed: bool
    failure: str
    scans: int
    slam_s: float
    removed_beams: int
    removed_pitch_variation_beams: int
    pitch_variation_beams: int
    trajectory_file: str
    truth_file: str
    alignment: tuple[float, float, float]

    @property
    def scans_per_s(self) -> float:
        return self.scans / self.slam_s if self.slam_s > 0 else float("nan")


@dataclasses.dataclass(frozen=True, eq=False)
class SequenceOutcome:
    """Everything one recording gave, for the figures and the recording of its first seed.

    Attributes:
        sequence: the sequence.
        seed: the run seed.
        frames: the recorded frames.
        truth: ``(n, 3)`` true sensor poses in the world.
        removed: per method, the removed mask of every frame.
        runs: per ``(system, method)``, what the system made of it.
        results: per ``(system, method)``, the scored row.
    """

    sequence: SlamSequence
    seed: int
    frames: list[Frame]
    truth: np.ndarray
    removed: dict[str, list[np.ndarray]]
    runs: dict[tuple[str, str], SystemRun]
    results: dict[tuple[str, str], SlamRunResult]


def run_sequence(
    sequence: SlamSequence,
    seed: int,
    config: SlamConfig,
    out_dir: Path,
    on_run: Callable[[str], None] = lambda _: None,
) -> SequenceOutcome:
    """Simulate one sequence with one seed, and run and score every system and filter.

    Args:
        sequence: what to simulate.
        seed: the run seed.
        config: methods and systems.
        out_dir: where the TUM files go (``trajectories/<sequence>/seed<k>/``).
        on_run: called after every SLAM run with a short description (progress).
    """
    frames, _ = record_frames(sequence.scenario, seed)
    truth = np.array([sensor_pose_2d(f.truth) for f in frames])
    stamps = np.array([f.stamp_s for f in frames])
    folder = Path("trajectories") / sequence.name / f"seed{seed}"
    (out_dir / folder).mkdir(parents=True, exist_ok=True)
    truth_file = folder / "truth.tum"
    write_tum(out_dir / truth_file, stamps, truth)
    pitch_variation = [is_pitch_variation(f.labels) & f.scan.valid_mask() for f in frames]
    removed = {m: removed_masks(m, frames, sequence.scenario) for m in config.methods}
    systems = [s for s in config.systems if s in available_systems()]
    runs, results = {}, {}
    for system in systems:
        for method in config.methods:
            run = run_system(system, frames, removed[method])
            score = score_trajectory(run.poses, truth, stamps, run.lost_at_scan, run.error)
            trajectory_file = folder / f"{system}_{method}.tum"
            finite = np.all(np.isfinite(run.poses), axis=1)
            write_tum(out_dir / trajectory_file, stamps[finite], run.poses[finite])
            masks = removed[method]
            results[system, method] = SlamRunResult(
                sequence=sequence.name,
                house=sequence.house.name,
                seed=seed,
                system=system,
                method=method,
                ate_m=score.rmse_m,
                max_error_m=score.ate.max if score.ate is not None else float("nan"),
                failed=score.failed,
                failure=score.failure,
                scans=len(frames),
                slam_s=run.wall_s,
                removed_beams=int(sum(int(m.sum()) for m in masks)),
                removed_pitch_variation_beams=int(
                    sum(int((m & pv).sum()) for m, pv in zip(masks, pitch_variation, strict=True))
                ),
                pitch_variation_beams=int(sum(int(pv.sum()) for pv in pitch_variation)),
                trajectory_file=trajectory_file.as_posix(),
                truth_file=truth_file.as_posix(),
                alignment=tuple(
                    score.ate.alignment_pose.tolist() if score.ate is not None else [np.nan] * 3
                ),
            )
            runs[system, method] = run
            on_run(f"{sequence.name} seed {seed}: {system} / {method}")
    return SequenceOutcome(sequence, seed, frames, truth, removed, runs, results)
