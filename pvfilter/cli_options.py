"""What the ``pvfilter`` command's options ask for: a filter, its parameters, robot inputs.

Kept apart from the command's plumbing so each rule reads on its own: which filter the
options name, how flags and a parameter file combine, which per-scan robot inputs a scan
file carries.
"""

from __future__ import annotations

import argparse
import dataclasses
from collections.abc import Mapping
from typing import Any

import numpy as np

from pvfilter import toml_reader
from pvfilter.contract import ROBOT_INPUTS
from pvfilter.improved import ImprovedParams
from pvfilter.paper import CLUSTERING_MODES, FilterParams
from pvfilter.params_file import load_params, read_params_file
from pvfilter.registry import ROBOT_GEOMETRY_FIELDS, FilterEntry, entry_for_params, filter_entry

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


def filter_options(args: argparse.Namespace) -> tuple[FilterEntry, Any, dict[str, Any]]:
    """The filter the options name, its parameters (a parameter file's, or its defaults)
    and the values the options replace, checked by name: what can be told before the
    input is read.

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
    given_as = {key: f"--{key.replace('_', '-')}" for key in fields}  # (how each was given)
    if args.clustering:
        fields["clustering"], given_as["clustering"] = args.clustering, "--clustering"
    if args.detection_only:
        fields["tracking"], given_as["tracking"] = False, "--detection-only"
    for text in args.set or ():
        key, value = setting(text)
        fields[key], given_as[key] = value, f"--set {text}"
    if args.threaded and entry.name != "paper":
        raise ValueError(f"--threaded: the two-thread form is the paper filter's, not {entry.name}")
    if fields and params is None:
        raise ValueError(f"filter {entry.name!r} takes no parameters")
    for key in fields:
        if key not in _takes(params):
            raise ValueError(f"{given_as[key]}: filter {entry.name!r} has no parameter {key}")
    if args.lidar_height is not None and "lidar_height_m" not in _takes(params):
        raise ValueError(f"--lidar-height: filter {entry.name!r} does not use the LiDAR's height")
    return entry, params, fields


def chosen_filter(
    args: argparse.Namespace, stated: Mapping[str, float] | None = None, source: str = ""
) -> tuple[FilterEntry, Any]:
    """The filter and parameters the options ask for (:func:`filter_options`), with the
    robot geometry the input ``source`` states (``stated``; see :func:`with_geometry`)."""
    return with_geometry(args, filter_options(args), stated or {}, source)


def with_geometry(
    args: argparse.Namespace,
    options: tuple[FilterEntry, Any, dict[str, Any]],
    stated: Mapping[str, float],
    source: str,
) -> tuple[FilterEntry, Any]:
    """The filter and parameters of ``options`` (:func:`filter_options`), with the values
    the options replace and the robot geometry the input ``source`` states (``stated``;
    see :func:`robot_geometry`) all applied at once: a value checked against another (the
    axle's height against the LiDAR's) is checked against the one the filter runs with.

    Raises:
        ValueError: a value out of its bounds; the geometry the input states, where the
            parameters cannot take it (naming ``source``).
    """
    entry, params, fields = options
    geometry = robot_geometry(args, params, stated)
    if not (fields or geometry):
        return entry, params
    try:
        return entry, dataclasses.replace(params, **{**fields, **geometry})
    except ValueError as error:
        from_input = {k: v for k, v in stated.items() if geometry.get(k) == v}
        if not from_input:
            raise
        told = ", ".join(f"{k} {v:g}" for k, v in from_input.items())
        raise ValueError(f"{source}: with the robot geometry it states ({told}): {error}") from None


def robot_geometry(
    args: argparse.Namespace, params: Any, stated: Mapping[str, float]
) -> dict[str, float]:
    """The robot geometry to tell the filter: what the input states (``stated``), for the
    fields its parameters hold and ``--set`` leaves alone, then ``--lidar-height``.

    An input states the robot that recorded it, so its geometry wins over a parameter
    file's, as in ``pvfilter eval-labels``; a value set on the command line wins over both.

    ``--lidar-height`` is checked by :func:`filter_options`.
    """
    takes = _takes(params)
    geometry = {k: v for k, v in stated.items() if k in takes and k not in _set_by_hand(args)}
    if args.lidar_height is not None:
        geometry["lidar_height_m"] = args.lidar_height
    return geometry


def default_filter_note(command: str, args: argparse.Namespace) -> str:
    """A line for ``command``'s output where no option chose the filter and the paper's
    ran, the default ("" otherwise): its Table I parameters find little pitch variation
    on robots like the simulator's, and a user filtering their own scans without flags
    should know that the improved filter is one option away."""
    if args.improved or args.filter is not None or args.params:
        return ""
    return (
        f"{command}: the paper's filter ran, the default; --improved runs the improved "
        "filter ('pvfilter --list' names them all)"
    )


def filter_notes(
    command: str, args: argparse.Namespace, params: Any, stated: Mapping[str, float]
) -> list[str]:
    """The lines a filtering command prints after its summary: which filter ran when no
    option chose it, and the robot geometry it ran with (see the two notes)."""
    notes = (default_filter_note(command, args), geometry_note(command, args, params, stated))
    return [note for note in notes if note]


def geometry_note(
    command: str, args: argparse.Namespace, params: Any, stated: Mapping[str, float]
) -> str:
    """A line for ``command``'s output on the robot geometry the filter runs with, and
    where each value came from: the scan file (``stated``), the options, the parameter
    file or the filter's defaults ("" for a filter without geometry). The improved
    filter's scores move with the LiDAR's height: a user who never set it should know."""
    fields = [name for name in ROBOT_GEOMETRY_FIELDS if name in _takes(params)]
    if not fields:
        return ""
    by_hand = _set_by_hand(args) | ({"lidar_height_m"} if args.lidar_height is not None else set())
    in_file = set()
    if args.params:
        table = read_params_file(args.params)
        in_file = set(table.get(table.get("filter"), {}))
    origins: dict[str, list[str]] = {}  # "from the file: lidar_height_m 0.300", ...
    for name in fields:
        if name in by_hand:
            origin = "from the options"
        elif name in stated:
            origin = "from the file"
        elif name in in_file:
            origin = "from the parameter file"
        else:
            origin = "defaults"
        origins.setdefault(origin, []).append(f"{name} {getattr(params, name):.3f}")
    if list(origins) == ["defaults"]:
        return (
            f"{command}: no robot geometry given: the filter took its defaults, "
            f"{', '.join(origins['defaults'])} (m); set yours with --lidar-height M or "
            "--set NAME=VALUE"
        )
    parts = [f"{origin}: {', '.join(values)}" for origin, values in origins.items()]
    return f"{command}: robot geometry (m) " + "; ".join(parts)


def _takes(params: Any) -> set[str]:
    """The parameter names of ``params`` (none for a filter without parameters)."""
    return set() if params is None else {f.name for f in dataclasses.fields(params)}


def _set_by_hand(args: argparse.Namespace) -> set[str]:
    """The parameters ``--set`` names."""
    return {setting(text)[0] for text in args.set or ()}


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
