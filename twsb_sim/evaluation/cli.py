"""``twsb eval``: the paper's experiments in simulation, written as a report folder."""

from __future__ import annotations

import argparse
import shlex
import sys
from pathlib import Path

from twsb_sim.config_errors import ConfigError
from twsb_sim.output_paths import output_folder
from twsb_sim.staging import staged_folder


def add_eval_parser(commands: argparse._SubParsersAction) -> None:
    """Register the ``eval`` subcommand on the ``twsb`` command line."""
    parser = commands.add_parser(
        "eval",
        help="run the paper's experiments and write a report",
        description="Simulate the normal and disturb sequences in several houses and seeds, "
        "then compare the Pitch Variation Filter with the baselines (PR curves and AUC, "
        "throughput), run the scan-matching experiment (ICP, NDT, HSM with and without the "
        "filter), explain the filter's misses, and write report.md, results.json and plots.",
    )
    parser.add_argument("--out", type=Path, required=True, help="the report folder")
    parser.add_argument(
        "--quick", action="store_true", help="a smoke run: one house, one seed, 8 s, coarse sweeps"
    )
    parser.add_argument("--seeds", type=int, default=None, help="seeds 0..N-1 (default 3; quick 1)")
    parser.add_argument(
        "--houses",
        nargs="+",
        default=None,
        metavar="HOUSE",
        help="house1, house2 or random:<seed> (default: house1 house2 random:1 random:2)",
    )
    parser.add_argument(
        "--improved-params",
        type=Path,
        metavar="FILE",
        help="also compare the improved filter with these parameters (a twsb tune file)",
    )
    parser.add_argument(
        "--variations",
        action="store_true",
        help="also run held-out random houses and robot variations (LiDAR height, range "
        "noise, balance controller) for the paper's, the improved filter and the IMU gate",
    )
    parser.add_argument("--no-improved", action="store_true", help="leave the improved filter out")
    parser.add_argument(
        "--stress",
        action="store_true",
        help="run the stress matrix instead: conditions (scenarios/stress/*.toml) x methods "
        "(paper, improved, IMU gate, no filter, truth labels), with a heat map",
    )
    parser.add_argument(
        "--episodes", type=int, default=None, help="--stress: episodes per condition (default 6)"
    )
    parser.add_argument(
        "--conditions", nargs="+", default=None, metavar="NAME", help="--stress: these rows only"
    )
    parser.add_argument("--quiet", action="store_true", help="no progress bars")
    parser.set_defaults(handler=run_eval)


def _check_params_file(path: Path) -> None:
    """Read the parameter file now, so a bad one fails in one line before the simulations."""
    from pvfilter import ImprovedParams, load_params

    try:
        params = load_params(path)
    except ValueError as error:  # also UnicodeDecodeError and TOML / JSON decode errors
        raise ConfigError(path, "", str(error).removeprefix(f"{path}: ")) from None
    if not isinstance(params, ImprovedParams):
        raise ConfigError(path, "", "not improved-filter parameters (a twsb tune file)")


def run_eval(args: argparse.Namespace) -> int:
    """Run the evaluation the arguments ask for and write the report folder."""
    if args.stress:
        return run_stress_eval(args)
    for flag, value in (("--episodes", args.episodes), ("--conditions", args.conditions)):
        if value is not None:
            raise ConfigError(flag, "", "only with --stress")
    from twsb_sim.evaluation.config import EvalConfig
    from twsb_sim.evaluation.experiment import run_evaluation
    from twsb_sim.evaluation.report import write_outputs

    output_folder(args.out)
    overrides: dict[str, object] = {}
    if args.seeds is not None:
        if args.seeds < 1:
            raise ConfigError("--seeds", "", f"expected an integer >= 1, got {args.seeds}")
        overrides["seeds"] = tuple(range(args.seeds))
    if args.houses:
        overrides["houses"] = tuple(args.houses)
    if args.improved_params is not None:
        if not args.improved_params.is_file():
            raise ConfigError(args.improved_params, "", "no such parameter file")
        _check_params_file(args.improved_params)
        overrides["improved_params"] = str(args.improved_params)
    overrides["variations"] = args.variations
    overrides["improved"] = not args.no_improved
    try:
        config = EvalConfig.quick(**overrides) if args.quick else EvalConfig(**overrides)
    except ValueError as error:  # the message names the field: "houses: expected ..."
        raise ConfigError("twsb eval", "", str(error)) from None
    results, evaluation = run_evaluation(config, progress=not args.quiet)
    command = "twsb " + shlex.join(sys.argv[1:]) if sys.argv[1:2] == ["eval"] else "twsb eval"
    with staged_folder(args.out) as staging:  # the report appears whole or not at all
        write_outputs(results, evaluation, staging, command)
    print(f"report written to {args.out}/report.md")
    return 0


def run_stress_eval(args: argparse.Namespace) -> int:
    """``twsb eval --stress``: the conditions x methods matrix, written as a report folder."""
    from twsb_sim.evaluation.stress import StressConfig, run_stress
    from twsb_sim.evaluation.stress_conditions import condition_ranges
    from twsb_sim.evaluation.stress_report import write_stress_outputs

    overrides: dict[str, object] = {}
    if args.episodes is not None:
        overrides["episodes"] = args.episodes
    if args.conditions:
        for name in args.conditions:
            condition_ranges(name)  # an unknown name or a bad file: one line naming it
        overrides["conditions"] = tuple(args.conditions)
    try:
        config = StressConfig.quick(**overrides) if args.quick else StressConfig(**overrides)
    except ValueError as error:
        raise ConfigError("twsb eval --stress", "", str(error)) from None
    results = run_stress(config, progress=not args.quiet)
    command = "twsb " + shlex.join(sys.argv[1:]) if sys.argv[1:2] == ["eval"] else "twsb eval"
    write_stress_outputs(results, args.out, command)
    print(f"stress report written to {args.out}/report.md")
    return 0
