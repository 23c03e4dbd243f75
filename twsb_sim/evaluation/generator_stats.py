"""What the data-set generator's episodes hold: pitch events, falls, label shares.

Episodes are drawn and simulated exactly as ``twsb generate`` does (same draws, same
seeds), with the robot's pitch sampled at ``PITCH_RATE_HZ``. A **pitch event** is a
stretch where |pitch| exceeds ``EVENT_THRESHOLD_DEG``; stretches less than
``EVENT_GAP_S`` apart are one event (a sway after a push); its peak is the largest
|pitch| in it, its sign nose-down (+) or nose-up (-).
"""

from __future__ import annotations

import math
from collections import Counter
from concurrent.futures import ProcessPoolExecutor
from typing import Any

import numpy as np

from twsb_sim.dataset.episode import draw_episode
from twsb_sim.dataset.randomization import Randomization
from twsb_sim.frame import Frame, RobotTruth
from twsb_sim.labels import BeamLabel
from twsb_sim.runner import run_scenario
from twsb_sim.scenario import scenario_from_table
from twsb_sim.sinks import NullSink

PITCH_RATE_HZ = 100.0  # Hz
EVENT_THRESHOLD_DEG = 5.0  # deg
EVENT_GAP_S = 0.5  # s
PERCENTILES = (50, 75, 90, 95, 99)


class _Trace(NullSink):
    state_rate_hz = PITCH_RATE_HZ

    def __init__(self) -> None:
        self.pitch_rad: list[float] = []
        self.labels: Counter[int] = Counter()
        self.finite = 0
        self.ceiling_frames = 0

    def on_state(self, truth: RobotTruth) -> None:
        self.pitch_rad.append(truth.pitch_rad)

    def on_frame(self, frame: Frame, filter_result: Any | None) -> None:
        finite = np.isfinite(frame.scan.ranges)
        self.finite += int(finite.sum())
        counts = np.bincount(frame.labels[finite], minlength=len(BeamLabel))
        self.labels.update({int(k): int(v) for k, v in enumerate(counts) if v})
        self.ceiling_frames += bool(counts[BeamLabel.CEILING])


def pitch_events(pitch_deg: np.ndarray, rate_hz: float = PITCH_RATE_HZ) -> list[float]:
    """Signed peaks of the pitch events of one run (deg, + nose down)."""
    above = np.abs(pitch_deg) > EVENT_THRESHOLD_DEG
    if not above.any():
        return []
    idx = np.flatnonzero(above)
    breaks = np.flatnonzero(np.diff(idx) > EVENT_GAP_S * rate_hz)
    starts = np.concatenate(([idx[0]], idx[breaks + 1]))
    ends = np.concatenate((idx[breaks], [idx[-1]]))
    peaks = []
    for a, b in zip(starts, ends, strict=True):
        segment = pitch_deg[a : b + 1]
        peaks.append(float(segment[np.argmax(np.abs(segment))]))
    return peaks


def episode_statistics(seed: int, episode: int, ranges: Randomization) -> dict:
    """One generator episode: its class, events, fall and label counts."""
    draw = draw_episode(seed, episode, ranges)
    scenario = scenario_from_table(draw.scenario_table, source=f"episode {episode}")
    trace = _Trace()
    summary = run_scenario(scenario, seed=scenario.seed, sinks=[trace])
    return {
        "episode": episode,
        "robot_class": draw.robot_class,
        "house": draw.house.name,
        "fell": summary.fell,
        "events_deg": [round(p, 2) for p in pitch_events(np.degrees(trace.pitch_rad))],
        "labels": {BeamLabel(k).name: v for k, v in sorted(trace.labels.items())},
        "finite_beams": trace.finite,
        "ceiling_frames": trace.ceiling_frames,
        "frames": summary.frames,
        "people": len(draw.scenario_table.get("people", [])),
    }


def _class_row(peaks_deg: list[float]) -> dict:
    share = float(np.mean(np.array(peaks_deg) > 20.0)) if peaks_deg else math.nan
    return {"events": len(peaks_deg), "share_above_20_deg": share,
            "max_deg": max(peaks_deg, default=math.nan)}  # fmt: skip


def _one(args: tuple[int, int, Randomization]) -> dict:
    return episode_statistics(*args)


def generator_statistics(
    episodes: int, seed: int = 0, ranges: Randomization | None = None, workers: int = 1
) -> dict:
    """Pitch-event distribution, falls and label shares over ``episodes`` episodes."""
    ranges = ranges or Randomization()
    tasks = [(seed, k, ranges) for k in range(episodes)]
    if workers > 1:
        with ProcessPoolExecutor(workers) as pool:
            rows = list(pool.map(_one, tasks))
    else:
        rows = [_one(t) for t in tasks]
    peaks = np.array([p for r in rows for p in r["events_deg"]])
    magnitude = np.abs(peaks)
    labels: Counter[str] = Counter()
    for r in rows:
        labels.update(r["labels"])
    finite = sum(r["finite_beams"] for r in rows)
    by_class: dict[str, list[float]] = {}
    for r in rows:
        by_class.setdefault(r["robot_class"], []).extend(abs(p) for p in r["events_deg"])
    return {
        "episodes": episodes,
        "seed": seed,
        "events": int(peaks.size),
        "share_above_20_deg": float((magnitude > 20.0).mean()) if peaks.size else math.nan,
        "share_above_25_deg": float((magnitude > 25.0).mean()) if peaks.size else math.nan,
        "peak_percentiles_deg": {str(q): float(np.percentile(magnitude, q)) for q in PERCENTILES}
        if peaks.size
        else {},
        "max_peak_deg": float(magnitude.max()) if peaks.size else math.nan,
        "nose_down_share": float((peaks > 0).mean()) if peaks.size else math.nan,
        "falls": sum(r["fell"] for r in rows),
        "label_share_of_returns": {k: v / finite for k, v in sorted(labels.items())},
        "episodes_with_ceiling_hits": sum(r["ceiling_frames"] > 0 for r in rows),
        "by_class": {
            name: {
                "events": len(v),
                "share_above_20_deg": float(np.mean(np.array(v) > 20.0)) if v else math.nan,
                "max_deg": max(v, default=math.nan),
            }
            for name, v in sorted(by_class.items())
        },
        "rows": rows,
    }
