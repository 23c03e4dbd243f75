"""``twsb tune``: fit the improved filter's parameters to a robot from generated episodes.

Simulates training episodes and held-out episodes (another data-set seed: other houses,
robots, motions, noise). The search (:mod:`twsb_sim.tuning.search`) fits the objective
(:mod:`twsb_sim.tuning.objective`) on two thirds of the training episodes; the defaults
and the search's best sets are scored on the other third, and the best of them is kept
(so a set that only fits the search's episodes is not). The operating point is chosen on
all training episodes; defaults and tuned parameters are then scored on the held-out
episodes, and the parameter file that ``pvfilter`` loads (``pvfilter.load_params``) is
written.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import shlex
import sys
import time
from pathlib import Path

import numpy as np

from twsb_sim.config_errors import ConfigError
from twsb_sim.output_paths import output_file
from twsb_sim.staging import staged_file

QUICK = {"episodes": 3, "heldout": 1, "samples": 3, "rounds": 1, "duration_s": 12.0}
VALIDATED = 5  # best sets of the search that are scored on the validation episodes


def add_tune_parser(commands: argparse._SubParsersAction) -> None:
    """Register ``tune`` on the ``twsb`` command line."""
    parser = commands.add_parser(
        "tune",
        help="fit the improved filter's parameters to a robot from generated episodes",
        description="Simulate random training episodes (as twsb generate draws them), search "
        "the improved filter's parameters for the objective on them, choose the operating "
        "point, report defaults and tuned parameters on held-out episodes (another seed: "
        "houses, robots, motions never seen), and write a parameter file that pvfilter "
        "loads (pvfilter --params FILE, pvfilter.load_params).",
    )
    parser.add_argument("--out", type=Path, required=True, help="parameter file (.toml or .json)")
    parser.add_argument(
        "--episodes",
        type=int,
        default=12,
        help="training episodes (default 12: two thirds fit the search, one third validates)",
    )
    parser.add_argument("--heldout", type=int, default=4, help="held-out episodes (default 4)")
    parser.add_argument("--seed", type=int, default=0, help="training data-set seed (default 0)")
    parser.add_argument(
        "--heldout-seed", type=int, default=1000, help="held-out data-set seed (default 1000)"
    )
    parser.add_argument(
        "--ranges",
        type=Path,
        default=None,
        help="TOML file of randomization ranges (twsb generate's): fix your robot here, "
        "e.g. [robot] lidar_height_m = 0.30",
    )
    parser.add_argument(
        "--objective",
        choices=("auc", "f1"),
        default="auc",
        help="auc: area under the P_th sweep's PR curve (default); f1: best F1 at or above "
        "--precision",
    )
    parser.add_argument(
        "--precision",
        type=float,
        default=0.9,
        help="target precision of the operating point (and of the f1 objective), default 0.9",
    )
    parser.add_argument("--imu", action="store_true", help="tune for use with the IMU's pitch/roll")
    parser.add_argument(
        "--samples", type=int, default=24, help="Latin-hypercube points (default 24)"
    )
    parser.add_argument("--rounds", type=int, default=4, help="pattern-search sweeps (default 4)")
    parser.add_argument(
        "--quick",
        action="store_true",
        help="a smoke run: 3 short training episodes, 1 held-out, 3 points, 1 sweep",
    )
    parser.add_argument("--quiet", action="store_true", help="no progress bars")
    parser.set_defaults(handler=run_tune)


def run_tune(args: argparse.Namespace) -> int:
    """Run the tuning the arguments ask for, print the report and write the file."""
    from pvfilter import ImprovedParams, save_params
    from twsb_sim.dataset.randomization import load_randomization
    from twsb_sim.tuning.data import episodes
    from twsb_sim.tuning.objective import count_positives, score
    from twsb_sim.tuning.search import SPACE, search

    settings = {k: getattr(args, k) for k in ("episodes", "heldout", "samples", "rounds")}
    ranges = load_randomization(args.ranges)
    if args.quick:
        settings.update({k: v for k, v in QUICK.items() if k != "duration_s"})
        episode = dataclasses.replace(ranges.episode, duration_s=(QUICK["duration_s"],) * 2)
        ranges = dataclasses.replace(ranges, episode=episode)
    for name in ("episodes", "heldout"):
        if settings[name] < 1:
            raise ConfigError(f"--{name}", "", f"expected an integer >= 1, got {settings[name]}")
    if not 0.0 < args.precision <= 1.0:
        raise ConfigError("--precision", "", f"expected a value in (0, 1], got {args.precision}")
    if args.out.suffix.lower() not in (".toml", ".json"):
        raise ConfigError(args.out, "", "the parameter file must end in .toml or .json")
    output_file(args.out)
    progress = not args.quiet
    started = time.perf_counter()
    train = _simulate(episodes(args.seed, settings["episodes"], ranges), settings["episodes"],
                      "training episodes", progress)  # fmt: skip
    seen = frozenset(run.house for run in train)
    heldout = _simulate(
        episodes(args.heldout_seed, settings["heldout"], ranges, avoid_houses=seen),
        settings["heldout"], "held-out episodes", progress,
    )  # fmt: skip
    heights = sorted({run.geometry["lidar_height_m"] for run in train})
    median_height = round(float(np.median([r.geometry["lidar_height_m"] for r in train])), 4)
    base = ImprovedParams(lidar_height_m=median_height)

    # the search fits on every third training episode left out; those validate: the best
    # few sets of the search and the defaults are scored on them, and the best one wins
    # (a set that only fits the search's episodes does not)
    fit = [run for i, run in enumerate(train) if i % 3 != 2 or len(train) < 3]
    validation = [run for i, run in enumerate(train) if i % 3 == 2] or train
    if count_positives(fit) == 0:
        raise ConfigError(
            "--episodes",
            "",
            "the training episodes hold no pitch-variation beam: nothing to tune on; ask "
            "for more or longer episodes",
        )
    if count_positives(validation) == 0:  # nothing to validate on: judge on the fit
        validation = fit

    def objective(params: ImprovedParams) -> float:
        return score(params, fit, args.precision, args.imu).value(args.objective)

    log = search(objective, base, settings["samples"], settings["rounds"], args.seed, progress)
    finalists = [base, *(p for _, p in sorted(log.tried, key=lambda t: -t[0])[:VALIDATED])]
    validated = [score(p, validation, args.precision, args.imu).value(args.objective)
                 for p in finalists]  # fmt: skip
    best = finalists[int(np.argmax(validated))]
    trained = score(best, train, args.precision, args.imu, choose=True)
    tuned = dataclasses.replace(best, p_th=trained.p_th)
    rows = {
        "defaults, training": score(base, train, args.precision, args.imu),
        "tuned, training": score(tuned, train, args.precision, args.imu),
        "defaults, held-out": score(base, heldout, args.precision, args.imu),
        "tuned, held-out": score(tuned, heldout, args.precision, args.imu),
    }
    command = "twsb " + shlex.join(sys.argv[1:]) if sys.argv[1:2] == ["tune"] else "twsb tune"
    tuning = {
        "command": command,
        "objective": args.objective,
        "target_precision": args.precision,
        "imu": args.imu,
        "training": {
            "seed": args.seed,
            "episodes": [r.name for r in train],
            "houses": sorted(seen),
            "lidar_heights_m": heights,
        },
        "heldout": {
            "seed": args.heldout_seed,
            "episodes": [r.name for r in heldout],
            "houses": sorted({r.house for r in heldout}),
        },
        "searched": [d.name for d in SPACE],
        "fit_episodes": [r.name for r in fit],
        "validation_episodes": [r.name for r in validation],
        "validation_scores": {"defaults": validated[0], "best of the search": max(validated[1:])},
        "defaults_kept": best is base,
        "points_scored": len(log.tried),
        "results": {name: dataclasses.asdict(s) for name, s in rows.items()},
        "wall_s": round(time.perf_counter() - started, 1),
    }
    warnings = _undefined_warnings(rows)
    if warnings:
        tuning["warnings"] = warnings
    with staged_file(args.out) as temporary:  # never a half-written parameter file
        save_params(temporary, tuned, tuning)
    print(_report(rows, tuned, base, log, tuning))
    for warning in warnings:
        print(f"twsb tune: warning: {warning}", file=sys.stderr)
    print(f"parameters written to {args.out} (pvfilter --params {args.out})")
    if args.quick:  # (its held-out scores can read 0: one short episode, one sweep)
        print(
            "note: --quick is a smoke run of the command (a few short episodes, one "
            "sweep): its scores and parameters say nothing; tune without it for use"
        )
    return 0


def _simulate(runs, count: int, desc: str, progress: bool) -> list:
    from tqdm import tqdm

    return list(tqdm(runs, total=count, desc=desc, unit="episode", disable=not progress))


def _undefined_warnings(rows: dict) -> list[str]:
    """A warning per set of episodes with no pitch-variation beam (scores undefined)."""
    empty = sorted({name.split(", ")[1] for name, s in rows.items() if not s.defined})
    return [
        f"the {what} episodes hold no pitch-variation beam: their AUC, F1 and recall are "
        "undefined (n/a); ask for more or longer episodes to score them"
        for what in empty
    ]


def _number(value: float, width: int, digits: int) -> str:
    """A score, or ``n/a`` where it is undefined (NaN)."""
    return f"{'n/a':>{width}s}" if math.isnan(value) else f"{value:{width}.{digits}f}"


def _report(rows: dict, tuned, base, log, tuning: dict) -> str:
    checked = tuning["validation_scores"]
    kept = "the defaults" if tuning["defaults_kept"] else "the search's best"
    lines = [
        f"objective: {tuning['objective']} (target precision {tuning['target_precision']:g}); "
        f"{tuning['points_scored']} parameter sets scored in {tuning['wall_s']:.0f} s",
        f"validation episodes: defaults {checked['defaults']:.3f}, best of the search "
        f"{checked['best of the search']:.3f}: {kept} kept",
        "",
        f"{'':22s} {'AUC':>6s} {'F1@P':>6s} {'p_th':>5s} {'precision':>9s} {'recall':>7s}"
        f" {'STATIC %':>8s}",
    ]
    for name, s in rows.items():
        lines.append(
            f"{name:22s} {_number(s.auc, 6, 3)} {_number(s.f1, 6, 3)} {s.p_th:5.2f} "
            f"{_number(s.precision, 9, 3)} {_number(s.recall, 7, 3)} {s.static_removed_pct:8.2f}"
        )
    changed = [
        f"  {f.name}: {getattr(base, f.name)!r} -> {getattr(tuned, f.name)!r}"
        for f in dataclasses.fields(tuned)
        if getattr(base, f.name) != getattr(tuned, f.name)
    ]
    return "\n".join([*lines, "", "changed parameters:", *(changed or ["  (none)"])])
