"""``twsb envelope``: measure what the robots survive and what the generator draws.

Writes one JSON file: the default robot's envelope (tilt recovery, shove limits per
direction and height, standing and driving, hard stop), each robot class's, the
randomized robots' of the data-set generator (their draws, their limits, percentiles),
and, with ``--episodes N``, the pitch events, falls and label shares of N generator
episodes. ``docs/envelope.md`` explains the numbers.
"""

from __future__ import annotations

import argparse
import json
import shlex
import sys
import time
from pathlib import Path

import numpy as np

from twsb_sim.config_errors import ConfigError


def add_envelope_parser(commands: argparse._SubParsersAction) -> None:
    """Register ``envelope`` on the ``twsb`` command line."""
    parser = commands.add_parser(
        "envelope",
        help="measure the survivable envelope of the robots and the generator's pitch events",
        description="Measure how hard the default robot, each robot class and the "
        "generator's randomized robots can be pushed (per direction and height) and how far "
        "they tilt, and optionally the pitch events and label shares of generator episodes; "
        "write the numbers to a JSON file.",
    )
    parser.add_argument("--out", type=Path, required=True, help="the JSON file to write")
    parser.add_argument(
        "--robots", type=int, default=24, help="randomized robots measured (default 24)"
    )
    parser.add_argument(
        "--episodes", type=int, default=0, help="generator episodes simulated (default 0)"
    )
    parser.add_argument("--seed", type=int, default=0, help="generator seed (default 0)")
    parser.add_argument("--ranges", type=Path, default=None, help="a generator ranges file")
    parser.add_argument("--workers", type=int, default=1, help="processes for --episodes")
    parser.add_argument(
        "--quick",
        action="store_true",
        help="a smoke run: the default robot from behind and the left at one height, no "
        "classes, at most one randomized robot",
    )
    parser.set_defaults(handler=run_envelope)


def _limits(envelope: dict, key: str = "shoves_standing") -> dict[str, float]:
    """Direction -> smallest survived angular impulse over the heights (N·m·s)."""
    out: dict[str, float] = {}
    for row in envelope[key]:
        out[row["direction"]] = min(out.get(row["direction"], np.inf), row["angular_impulse_n_m_s"])
    return out


def run_envelope(args: argparse.Namespace) -> int:
    """Measure and write the JSON file."""
    from twsb_sim.dataset.episode import draw_episode
    from twsb_sim.dataset.randomization import load_randomization
    from twsb_sim.evaluation.envelope import (
        DIRECTIONS,
        HEIGHTS_M,
        RobotUnderTest,
        measure_envelope,
    )
    from twsb_sim.evaluation.generator_stats import generator_statistics
    from twsb_sim.robot_classes import ROBOT_CLASSES
    from twsb_sim.scenario import scenario_from_table

    for flag, value in (("--robots", args.robots), ("--episodes", args.episodes),
                        ("--seed", args.seed)):  # fmt: skip
        if value < 0:
            raise ConfigError(flag, "", f"expected an integer >= 0, got {value}")
    ranges = load_randomization(args.ranges)
    started = time.perf_counter()
    heights = (0.3,) if args.quick else HEIGHTS_M
    directions = ("behind", "left") if args.quick else tuple(DIRECTIONS)
    result: dict = {"command": "twsb " + shlex.join(sys.argv[1:])}
    result["default_robot"] = measure_envelope(
        RobotUnderTest(), heights, directions, driving=not args.quick, tilt=not args.quick
    )
    classes = {} if args.quick else ROBOT_CLASSES
    result["robot_classes"] = {}
    for name, robot_class in classes.items():
        scenario = scenario_from_table({"duration_s": 1.0, **robot_class.tables}, f"class {name}")
        under_test = RobotUnderTest(scenario.robot, scenario.controller, scenario.balance)
        result["robot_classes"][name] = measure_envelope(
            under_test, (0.3,), ("behind", "front", "left"), driving=False, tilt=False
        )
    robots = []
    robot_directions = ("behind", "left") if args.quick else ("behind", "front", "left")
    for k in range(min(args.robots, 1) if args.quick else args.robots):
        draw = draw_episode(args.seed, k, ranges)
        scenario = scenario_from_table(draw.scenario_table, source=f"episode {k}")
        under_test = RobotUnderTest(scenario.robot, scenario.controller, scenario.balance)
        envelope = measure_envelope(under_test, (0.3,), robot_directions, driving=False, tilt=False)
        robots.append({"episode": k, "robot_class": draw.robot_class,
                       "tables": {t: draw.scenario_table.get(t, {})
                                  for t in ("robot", "controller", "balance")},
                       **envelope})  # fmt: skip
    limits = [_limits(r) for r in robots]
    result["randomized_robots"] = {
        "robots": robots,
        "angular_impulse_percentiles_n_m_s": {
            d: {str(q): float(np.percentile([lim[d] for lim in limits], q)) for q in (10, 25, 50)}
            for d in robot_directions
        }
        if robots
        else {},
    }
    if args.episodes:
        result["generator"] = generator_statistics(args.episodes, args.seed, ranges, args.workers)
    result["wall_s"] = round(time.perf_counter() - started, 1)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")
    print(f"envelope written to {args.out} ({result['wall_s']} s)")
    return 0
