"""The paper's experiments in simulation (section IV-C and IV-D), and why the filter misses.

``twsb eval --out DIR`` simulates the normal and disturb sequences in several houses and
seeds, once each, and replays the stored frames through the Pitch Variation Filter and
the baselines: PR curves and AUC from threshold sweeps, throughput measured in the same
run, the scan-matching experiment with ICP, NDT and HSM (Chamfer distance and the error
against the true relative pose), and a diagnosis of every missed beam and false alarm.

The names below load on first use, so the ``twsb`` command line, which registers
``eval`` from :mod:`twsb_sim.evaluation.cli`, starts without importing them.
"""

from __future__ import annotations

from twsb_sim.lazy_exports import lazy_exports

_HOMES = {  # public name -> the module that holds it
    "EvalConfig": "config",
    "parse_house": "config",
    "MISS_STAGES": "diagnosis",
    "Queue": "diagnosis",
    "RunDiagnosis": "diagnosis",
    "attribute_misses": "diagnosis",
    "describe_false_alarms": "diagnosis",
    "diagnose_run": "diagnosis",
    "Evaluation": "experiment",
    "run_evaluation": "experiment",
    "Recording": "recording",
    "record": "recording",
    "sequence_in_house": "recording",
    "Alignment": "scan_matching",
    "align": "scan_matching",
    "pitch_variation_runs": "scan_matching",
    "write_outputs": "report",
}
__getattr__, __all__ = lazy_exports(__name__, _HOMES)
