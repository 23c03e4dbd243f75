"""What each sensor imperfection does to the Pitch Variation Filter, one at a time.

Runs a scenario (default: the hard stop) with the filter in the loop, first with sensors
like those of earlier versions (an instant, error-free scan with 2 cm noise from a level
mount on the axle), then with each default imperfection added alone, then with all the
defaults, and prints the beams the filter removed, how many of them were pitch-variation
points, and how many pitch-variation beams the scans held. docs/sensors.md's table::

    python docs/sensor_effects.py [--scenario hard_stop] [--seed 0] [--p-th 0.8]
"""

from __future__ import annotations

import argparse
import dataclasses

import numpy as np

from pvfilter import FilterParams, PitchVariationFilter
from twsb_sim.cli import resolve_scenario
from twsb_sim.labels import is_pitch_variation
from twsb_sim.lidar import LidarConfig
from twsb_sim.robot import RobotConfig
from twsb_sim.runner import run_scenario
from twsb_sim.scenario import load_scenario
from twsb_sim.sinks import NullSink

LEVEL_MOUNT = {"lidar_offset_x_m": 0.0, "lidar_tilt_pitch_deg": 0.0, "lidar_tilt_roll_deg": 0.0}
EARLIER = {"sweep": "instant", "range_noise_std_m": 0.02}  # on top of LidarConfig.ideal()
DEFAULTS = LidarConfig()
LIDAR_EFFECTS = {  # name: LidarConfig fields set to their defaults
    "rotating sweep": ("sweep",),
    "range noise growing with range": ("range_noise_std_m", "range_noise_fraction"),
    "quantisation": ("range_resolution_m",),
    "random dropouts": ("dropout_probability",),
    "grazing dropouts": ("grazing_dropout_start_deg",),
    "mixed pixels": ("mixed_pixel_probability",),
    "0.15 m minimum range": ("range_min_m",),
}
MOUNT_EFFECTS = {  # name: RobotConfig fields set to their defaults
    "mount 1.0 deg nose down": ("lidar_tilt_pitch_deg",),
    "mount 0.5 deg roll": ("lidar_tilt_roll_deg",),
    "mount 3 cm ahead of the axle": ("lidar_offset_x_m",),
}


class Count(NullSink):
    """Removed beams, those of them that are pitch-variation points, and all such points."""

    def __init__(self) -> None:
        self.removed = self.true_positives = self.positives = 0

    def on_frame(self, frame, filter_result) -> None:
        positive = is_pitch_variation(frame.labels) & np.isfinite(frame.scan.ranges)
        self.removed += int(filter_result.removed.sum())
        self.true_positives += int((filter_result.removed & positive).sum())
        self.positives += int(positive.sum())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", default="hard_stop")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--p-th", type=float, default=0.8, help="the filter's P_th (Table I)")
    args = parser.parse_args()
    scenario = load_scenario(resolve_scenario(args.scenario))
    earlier_lidar = LidarConfig.ideal(**EARLIER)
    level = dataclasses.replace(scenario.robot, **LEVEL_MOUNT)
    default_robot = dataclasses.replace(scenario.robot, **{k: getattr(RobotConfig(), k)
                                                            for k in LEVEL_MOUNT})  # fmt: skip
    rows = [("sensors of earlier versions", level, earlier_lidar)]
    for name, fields in LIDAR_EFFECTS.items():
        changes = {f: getattr(DEFAULTS, f) for f in fields}
        rows.append((f"+ {name}", level, dataclasses.replace(earlier_lidar, **changes)))
    for name, fields in MOUNT_EFFECTS.items():
        robot = dataclasses.replace(level, **{f: getattr(RobotConfig(), f) for f in fields})
        rows.append((f"+ {name}", robot, earlier_lidar))
    rows.append(("all defaults", default_robot, DEFAULTS))
    print(f"{args.scenario}, seed {args.seed}, PitchVariationFilter P_th {args.p_th:g}")
    print(f"{'sensors':34s} {'removed':>8s} {'of them PV':>11s} {'PV beams':>9s}")
    for name, robot, lidar in rows:
        count = Count()
        run_scenario(
            dataclasses.replace(scenario, robot=robot, lidar=lidar),
            seed=args.seed,
            scan_filter=PitchVariationFilter(FilterParams(p_th=args.p_th)),
            sinks=[count],
        )
        print(f"{name:34s} {count.removed:8d} {count.true_positives:11d} {count.positives:9d}")


if __name__ == "__main__":
    main()
