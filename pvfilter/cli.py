"""``pvfilter IN.npz OUT.npz``: run the filter over a scan file (layout in pvfilter.io).

The paper's filter by default (its Table I symbols as options); ``--improved`` runs the
improved filter, and ``--params FILE`` either filter with the parameters of a parameter
file (``twsb tune`` writes them; see :mod:`pvfilter.params_file`).
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time
from collections.abc import Sequence

from pvfilter.improved import ImprovedParams
from pvfilter.io import read_arrays, save_results, scans_from_arrays
from pvfilter.params import CLUSTERING_MODES, FilterParams
from pvfilter.params_file import filter_for, load_params
from pvfilter.threaded import ThreadedPitchVariationFilter

# the numeric fields are the paper's symbols; the others are mode switches
SYMBOLS = [f for f in dataclasses.fields(FilterParams) if type(f.default) in (int, float)]


def build_parser() -> argparse.ArgumentParser:
    """The command's arguments: files, every FilterParams symbol, the modes."""
    parser = argparse.ArgumentParser(
        prog="pvfilter",
        description="Remove pitch-variation points (floor and ceiling clusters) from the "
        "2D LiDAR scans of an .npz file and write the filtered scans, masks and scores.",
    )
    parser.add_argument("input", help="scan file (.npz: ranges, stamps, LaserScan fields)")
    parser.add_argument("output", help="where to write the filtered scan file (.npz)")
    for field in SYMBOLS:
        parser.add_argument(
            f"--{field.name.replace('_', '-')}",
            dest=field.name,
            type=type(field.default),
            help=f"{field.name} (Table I: {field.default})",
        )
    parser.add_argument("--clustering", choices=CLUSTERING_MODES, help="BFS neighbourhood")
    parser.add_argument("--detection-only", action="store_true", help="turn tracking off")
    parser.add_argument("--threaded", action="store_true", help="the paper's two-thread form")
    parser.add_argument(
        "--improved", action="store_true", help="run the improved filter (ImprovedParams defaults)"
    )
    parser.add_argument(
        "--params",
        metavar="FILE",
        help="a parameter file (TOML or JSON, e.g. from twsb tune); it names its filter",
    )
    parser.add_argument(
        "--lidar-height",
        type=float,
        metavar="M",
        help="improved filter: the scan plane's height above the floor, m",
    )
    return parser


def choose_params(args: argparse.Namespace, paper: dict) -> FilterParams | ImprovedParams:
    """The parameters the arguments ask for (raises ValueError naming the problem)."""
    params = load_params(args.params) if args.params else None
    improved = args.improved or isinstance(params, ImprovedParams)
    if improved:
        if paper or args.clustering or args.detection_only or args.threaded:
            raise ValueError("the paper's options apply to the paper's filter, not --improved")
        if args.params and not isinstance(params, ImprovedParams):
            raise ValueError(f"{args.params}: holds the paper's parameters, not the improved")
        params = params if params is not None else ImprovedParams()
        if args.lidar_height is not None:
            params = dataclasses.replace(params, lidar_height_m=args.lidar_height)
        return params
    if args.lidar_height is not None:
        raise ValueError("--lidar-height: applies to the improved filter only")
    if args.clustering:
        paper["clustering"] = args.clustering
    base = params if params is not None else FilterParams()
    return dataclasses.replace(base, **paper, tracking=base.tracking and not args.detection_only)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command; returns the exit status (0 ok, 1 bad file, 2 bad arguments)."""
    parser = build_parser()
    args = parser.parse_args(argv)
    chosen = {f.name: getattr(args, f.name) for f in SYMBOLS if getattr(args, f.name) is not None}
    try:
        params = choose_params(args, chosen)
    except OSError as error:
        print(f"pvfilter: error: {error}", file=sys.stderr)
        return 1
    except ValueError as error:
        parser.error(str(error))
    try:
        arrays = read_arrays(args.input)
        scans = scans_from_arrays(arrays, source=args.input)
    except (OSError, ValueError) as error:
        print(f"pvfilter: error: {error}", file=sys.stderr)
        return 1
    start = time.perf_counter()
    if args.threaded:
        with ThreadedPitchVariationFilter(params) as pvf:
            results = list(pvf.process_stream(scans))
    else:
        pvf = filter_for(params)
        results = [pvf.process(scan) for scan in scans]
    elapsed = time.perf_counter() - start
    save_results(args.output, arrays, results)
    valid = sum(int(scan.valid_mask().sum()) for scan in scans)
    removed = sum(int(result.removed.sum()) for result in results)
    share = 100.0 * removed / valid if valid else 0.0
    rate = len(scans) / elapsed if elapsed > 0 else float("inf")
    print(
        f"pvfilter: {len(scans)} scans, removed {removed} of {valid} valid beams "
        f"({share:.2f} %), {rate:.0f} scans/s; wrote {args.output}"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
