"""What recording a run to an .rrd file costs: the same run with and without the recording.

Runs the hard-stop scenario with the Pitch Variation Filter in the loop (what
``twsb run`` does), interleaved, in one process:

1. without recording (the do-nothing sink);
2. with a :class:`~twsb_sim.rerun_log.RerunLogger` writing an .rrd file, frames only;
3. the same with the robot-state hook at 50 Hz (the ``twsb run --rrd`` default).

Each run is timed whole (``run_scenario``, the recording's setup, final flush and file
footer included), as wall time and as the CPU time of the process (all its threads:
Rerun encodes and writes in background threads). CPU time is what the recording costs
however busy the machine is; wall time on a shared machine is noisy, so the script
reports the best of several repeats, each against the unrecorded run. Usage::

    python benchmarks/bench_rerun.py [--repeats 7] [--scenario normal_sequence]
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path

import rerun as rr

from pvfilter import PitchVariationFilter
from twsb_sim.rerun_log import APPLICATION_ID, RerunLogger
from twsb_sim.runner import run_scenario
from twsb_sim.scenario import load_scenario
from twsb_sim.scenario_files import resolve_scenario
from twsb_sim.sinks import NullSink


def timed_run(scenario, rrd: Path | None, state_rate_hz: float | None) -> tuple[float, float]:
    """Wall and process-CPU seconds of one run, with a recording to ``rrd`` or without."""
    started, cpu_started = time.perf_counter(), time.process_time()
    if rrd is None:
        sink = NullSink()
    else:
        rec = rr.RecordingStream(APPLICATION_ID)
        rec.save(rrd)
        sink = RerunLogger(rec, state_rate_hz=state_rate_hz, p_th=0.8, close_recording=True)
    run_scenario(scenario, seed=0, scan_filter=PitchVariationFilter(), sinks=[sink])
    return time.perf_counter() - started, time.process_time() - cpu_started


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7, help="measurements of each kind")
    parser.add_argument("--scenario", default="hard_stop", help="a shipped scenario or a file")
    args = parser.parse_args()
    os.environ.setdefault("CI", "1")  # no usage data from benchmark runs
    scenario = load_scenario(resolve_scenario(args.scenario))
    kinds = {
        "no recording": (False, None),
        "recording, frames only": (True, None),
        "recording + state 50 Hz": (True, 50.0),
    }
    times: dict[str, list[tuple[float, float]]] = {name: [] for name in kinds}
    with tempfile.TemporaryDirectory() as folder:
        rrd = Path(folder) / "bench.rrd"
        timed_run(scenario, rrd, 50.0)  # warm-up: imports, house cache, first file
        for _ in range(args.repeats):  # interleaved, so machine load hits all alike
            for name, (record, rate) in kinds.items():
                times[name].append(timed_run(scenario, rrd if record else None, rate))
        size_mb = rrd.stat().st_size / 1e6
    base = [min(t[i] for t in times["no recording"]) for i in (0, 1)]
    print(f"{scenario.name}, {scenario.duration_s:g} simulated s, filter in the loop")
    print(f"{'':26s}{'wall (best)':>22s}{'CPU (best)':>22s}")
    for name, values in times.items():
        cells = [min(v[i] for v in values) for i in (0, 1)]
        print(
            f"{name:26s}"
            + "".join(
                f"{c * 1e3:9.0f} ms ({c / b - 1:+6.1%})" for c, b in zip(cells, base, strict=True)
            )
        )
    print(f"(best of {args.repeats} each; the .rrd of one run: {size_mb:.1f} MB)")


if __name__ == "__main__":
    main()
