"""What the ``pvfilter`` command's options ask for: a filter, its parameters, robot inputs.

Kept apart from the command's plumbing so each rule reads on its own: which filter the
options name, how flags and a parameter file combine, which per-scan robot inputs a scan
file carries.
"""

from __future__ import annotations

import argparse
import dataclasses
from typing import Any

import numpy as np

from pvfilter import toml_reader
from pvfilter.contract import ROBOT_INPUTS
from pvfilter.improved import ImprovedParams
from pvfilter.paper import CLUSTERING_MODES, FilterParams
from pvfilter.params_file import load_params
from pvfilter.registry import FilterEntry, entry_for_params, filter_entry

# the paper's Table I symbols are flags of their own (--d-th ...); the others are switches
SYMBOLS = [f for f in dataclasses.fields(FilterParams) if type(f.default) in (int, float)]


def add_filter_options(parser: argparse.ArgumentParser) -> None:
    """The options that choose a filter and its parameters (shared by the commands)."""
    parser.add_argument("--filter", metavar="NAME", help="the filter to run (default: paper)")
    parser.add_argument("--improved", action="store_true", help="short for --filter improved")
    parser.add_argument("--params", metavar="FILE", help="a parameter file (names its filter)")
    parser.add_argument(
        "--set", action="append", metavar="NAME=VALUE", help="set one parameter (repeatable)"
    )
    improved_defaults = {f.name: f.default for f in dataclasses.fields(ImprovedParams)}
    for field in SYMBOLS:
        also = field.name in improved_defaults  # p_th: the improved filter's threshold too
        parser.add_argument(
            f"--{field.name.replace('_', '-')}",
            dest=field.name,
            type=type(field.default),
            help=f"{field.name} (paper's Table I: {field.default}"
            + (f"; improved filter: {improved_defaults[field.name]})" if also else ")"),
        )
    parser.add_argument("--clustering", choices=CLUSTERING_MODES, help="paper: BFS neighbourhood")
    parser.add_argument("--detection-only", action="store_true", help="paper: no tracking")
    parser.add_argument(
        "--lidar-height", type=float, metavar="M", help="the scan plane's height above the floor, m"
    )
    parser.set_defaults(threaded=False)


def chosen_filter(args: argparse.Namespace) -> tuple[FilterEntry, Any]:
    """The filter and parameters the options ask for.

    Raises:
        ValueError: options that contradict each other or name no parameter of the filter.
        OSError: the parameter file cannot be read.
    """
    params = load_params(args.params) if args.params else None
    name = "improved" if args.improved else args.filter
    if params is not None:
        from_file = entry_for_params(params)
        if name is not None and name != from_file.name:
            raise ValueError(f"{args.params}: holds parameters of {from_file.name!r}, not {name!r}")
        entry = from_file
    else:
        entry = filter_entry(name or "paper")
        params = entry.default_params()
    fields = {f.name: getattr(args, f.name) for f in SYMBOLS if getattr(args, f.name) is not None}
    if args.clustering:
        fields["clustering"] = args.clustering
    if args.detection_only:
        fields["tracking"] = False
    fields.update(dict(setting(text) for text in args.set or ()))
    if args.threaded and entry.name != "paper":
        raise ValueError(f"--threaded: the two-thread form is the paper filter's, not {entry.name}")
    if fields:
        if params is None:
            raise ValueError(f"filter {entry.name!r} takes no parameters")
        known = {f.name for f in dataclasses.fields(params)}
        for key in fields:
            if key not in known:
                flag = key.replace("_", "-")
                raise ValueError(f"--{flag}: filter {entry.name!r} has no parameter {key}")
        params = dataclasses.replace(params, **fields)
    return entry, params


def robot_geometry(args: argparse.Namespace, entry: FilterEntry, params: Any) -> dict[str, float]:
    """``--lidar-height`` as robot geometry, for filters whose parameters hold it."""
    if args.lidar_height is None:
        return {}
    if params is None or "lidar_height_m" not in {f.name for f in dataclasses.fields(params)}:
        raise ValueError(f"--lidar-height: filter {entry.name!r} does not use the LiDAR's height")
    return {"lidar_height_m": args.lidar_height}


def robot_inputs(arrays: dict[str, np.ndarray], count: int, source: str) -> list[dict[str, Any]]:
    """Per scan, the robot inputs a scan file carries (``pitch_rad``, ``roll_rad``: (m,);
    ``pose_sensor_in_odom``: (m, 3)); empty dicts when it carries none.

    Raises:
        ValueError: ``"<source>: <key>: ..."`` for an array of the wrong shape.
    """
    per_scan: list[dict[str, Any]] = [{} for _ in range(count)]
    for key in ROBOT_INPUTS:
        if key not in arrays:
            continue
        values = np.asarray(arrays[key], dtype=np.float64)
        shape = (count, 3) if key == "pose_sensor_in_odom" else (count,)
        if values.shape != shape:
            raise ValueError(f"{source}: {key}: must have shape {shape}, got {values.shape}")
        for inputs, value in zip(per_scan, values, strict=True):
            inputs[key] = value if values.ndim == 2 else float(value)
    return per_scan


def setting(text: str) -> tuple[str, Any]:
    """``NAME=VALUE`` of ``--set``; the value read as TOML (``0.5``, ``true``, ``"radius"``;
    a bare word is a string).

    Raises:
        ValueError: text without ``=`` or a name.
    """
    name, sep, text_value = text.partition("=")
    if not sep or not name.strip():
        raise ValueError(f"--set: expected NAME=VALUE, got {text!r}")
    return name.strip().replace("-", "_"), toml_reader.value(text_value)
