"""The command-line options that pick a registered filter, shared by the ``twsb`` commands.

``--filter NAME`` names any filter of the registry (:func:`pvfilter.filter_names`),
``--filter-params FILE`` reads its parameters from a parameter file, and
``--robot-inputs`` also hands it the optional robot inputs it accepts (the simulated
IMU's attitude); the inputs a filter needs are always handed over. ``--compare NAME ...``
runs other filters on the same frames for the summary.
"""

from __future__ import annotations

import argparse
import math

from pvfilter import filter_entry, filter_names, load_params
from pvfilter.registry import entry_for_params
from twsb_sim.config_errors import ConfigError
from twsb_sim.frame_filter import FrameFilter, frame_filter
from twsb_sim.scenario import Scenario


def add_filter_args(parser: argparse.ArgumentParser, default: str) -> None:
    """Add ``--filter``, ``--filter-params``, ``--robot-inputs`` and ``--no-filter``."""
    parser.add_argument(
        "--filter",
        metavar="NAME",
        default=None,
        help=f"the filter in the loop: {', '.join(filter_names())} (default: {default})",
    )
    parser.add_argument(
        "--filter-params", metavar="FILE", help="the filter's parameter file (names its filter)"
    )
    parser.add_argument(
        "--robot-inputs",
        action="store_true",
        help="also give the filter the robot inputs it can use (the IMU's attitude)",
    )
    parser.add_argument("--no-filter", action="store_true", help="run no filter in the loop")
    parser.add_argument(
        "--compare",
        metavar="NAME",
        nargs="*",
        default=["paper"],
        help="also run these filters on the same frames, for the summary (default: paper)",
    )
    parser.set_defaults(default_filter=default)


def filter_from_args(args: argparse.Namespace, scenario: Scenario) -> FrameFilter | None:
    """The filter the options ask for, told the scenario's robot geometry; None with
    ``--no-filter``.

    Raises:
        ConfigError: an unknown name, a parameter file that cannot be used, or options
            that contradict each other.
    """
    if args.no_filter:
        if args.filter or args.filter_params:
            raise ConfigError("--no-filter", "", "given with --filter or --filter-params")
        return None
    params = None
    name = args.filter
    if args.filter_params:
        try:
            params = load_params(args.filter_params)
            entry = entry_for_params(params)
        except (OSError, ValueError) as error:
            # (the error names the file once: the reader's messages name it already, and
            # a system error's text is its reason alone)
            if isinstance(error, OSError):
                message = error.strerror or str(error)
            else:
                message = str(error).removeprefix(f"{args.filter_params}: ")
            raise ConfigError(args.filter_params, "", message) from None
        if name is not None and name != entry.name:
            message = f"holds parameters of {entry.name!r}, not of --filter {name!r}"
            raise ConfigError(args.filter_params, "", message)
        name = entry.name
    name = name or args.default_filter
    try:
        entry = filter_entry(name)
    except ValueError as error:
        raise ConfigError("--filter", "", str(error).removeprefix("filter: ")) from None
    inputs = entry.needs + (entry.accepts if args.robot_inputs else ())
    geometry = robot_geometry(scenario)
    return frame_filter(name, name, params, geometry, inputs)


def compared_filters(
    args: argparse.Namespace, scenario: Scenario, in_loop: FrameFilter | None
) -> dict[str, FrameFilter]:
    """The filters ``--compare`` names, minus the one in the loop, each with its defaults."""
    names = [n for n in args.compare if in_loop is None or n != in_loop.label]
    geometry = robot_geometry(scenario)
    compared = {}
    for name in names:
        try:
            entry = filter_entry(name)
        except ValueError as error:
            raise ConfigError("--compare", "", str(error).removeprefix("filter: ")) from None
        compared[name] = frame_filter(name, name, None, geometry, entry.needs)
    return compared


def robot_geometry(scenario: Scenario) -> dict[str, float]:
    """The scenario robot's LiDAR and axle heights and how far ahead of the axle the LiDAR
    sits, m, as filters take them."""
    return {
        "lidar_height_m": scenario.robot.lidar_height_m,
        "axle_height_m": scenario.robot.wheel_radius_m,
        "lidar_ahead_m": scenario.robot.lidar_offset_x_m,
    }


def operating_threshold(scan_filter: FrameFilter | None) -> float:
    """The filter's decision threshold (``p_th``) for displays, NaN where it has none."""
    params = getattr(scan_filter.scan_filter, "params", None) if scan_filter else None
    return float(getattr(params, "p_th", math.nan))
