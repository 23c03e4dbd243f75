"""The whole SLAM experiment, from simulation to ``report.md``, as ``twsb slam`` runs it."""

from __future__ import annotations

import dataclasses
from pathlib import Path

from tqdm import tqdm

from twsb_sim.slam.experiment import SlamConfig, SlamRunResult, run_sequence
from twsb_sim.slam.systems import available_systems


@dataclasses.dataclass(frozen=True)
class SlamOutputs:
    """What an experiment wrote (paths relative to its folder) and its rows."""

    results: list[SlamRunResult]
    figures: list[str]
    recordings: list[str]


def run_slam_experiment(
    config: SlamConfig,
    out_dir: Path,
    progress: bool = True,
    rerun: bool = True,
    command: str = "twsb slam",
) -> SlamOutputs:
    """Run every sequence, seed, filter and system; write the report, JSON, figures, TUM
    files and (with ``rerun``) one Rerun recording per sequence.

    The figures and recordings show each sequence's first seed.
    """
    from twsb_sim.slam.figures import draw_maps, draw_trajectories
    from twsb_sim.slam.report import write_report, write_results

    out_dir.mkdir(parents=True, exist_ok=True)
    sequences = config.slam_sequences()
    systems = [s for s in config.systems if s in available_systems()]
    total = len(sequences) * len(config.seeds) * len(systems) * len(config.methods)
    results, figures, recordings = [], [], []
    with tqdm(total=total, desc="SLAM runs", unit="run", disable=not progress) as bar:
        for sequence in sequences:
            for seed in config.seeds:
                bar.set_postfix_str(f"{sequence.name} seed {seed}: simulating")

                def advance(text: str) -> None:
                    bar.set_postfix_str(text)
                    bar.update()

                outcome = run_sequence(sequence, seed, config, out_dir, on_run=advance)
                results += list(outcome.results.values())
                if seed != config.seeds[0]:
                    continue
                bar.set_postfix_str(f"{sequence.name}: figures")
                for name, draw in (("maps", draw_maps), ("trajectories", draw_trajectories)):
                    figure = f"{name}_{sequence.name}.png"
                    draw(outcome, out_dir / figure)
                    figures.append(figure)
                if rerun:
                    from twsb_sim.slam.rerun_slam import record_sequence

                    recording = f"slam_{sequence.name}.rrd"
                    record_sequence(outcome, out_dir / recording)
                    recordings.append(recording)
    write_results(out_dir / "results.json", results, config)
    write_report(out_dir / "report.md", results, config, figures, command)
    return SlamOutputs(results, figures, recordings)
