"""Motion plans: valid timelines that keep the commanded position inside the lane."""

from __future__ import annotations

import math

import numpy as np
import pytest

from twsb_sim.dataset.motion import Lane, plan_motion
from twsb_sim.dataset.randomization import Randomization
from twsb_sim.scenario import scenario_from_table
from twsb_sim.timeline import sample_commands

DT = 0.002  # s, the physics step
RANGES = Randomization()
LANES = [Lane(0.0, 0.0), Lane(0.0, 1.0), Lane(0.3, 6.0), Lane(4.0, 4.0), Lane(9.0, 0.5)]


def plans(n: int):
    for k in range(n):
        rng = np.random.default_rng(k)
        lane = LANES[k % len(LANES)]
        duration = 40.0
        yield lane, duration, plan_motion(rng, lane, RANGES.motion, RANGES.shoves, duration)


def along_lane(plan, duration: float) -> np.ndarray:
    """Planned position along the lane at every physics step: the integral of the
    commanded velocity along the heading, plus each shove's planned displacement."""
    commands = tuple(scenario_from_table(
        {"duration_s": duration, "commands": list(plan.commands)}
    ).commands)  # fmt: skip
    n = round(duration / DT)
    samples = sample_commands(commands, DT, n)
    heading = np.cumsum(samples.yaw_rate_rad_s) * DT
    position = np.cumsum(samples.velocity_mps * np.cos(heading)) * DT
    k = RANGES.shoves.displacement_m_per_n_s
    for shove in plan.shoves:
        step = round(shove["t_s"] / DT)
        fx, fy, _ = shove["force_n"]  # heading frame: its component along the lane moves it
        along = fx * np.cos(heading[step]) - fy * np.sin(heading[step])
        position[step:] += k * along * shove["duration_s"]
    return position, heading, samples


@pytest.mark.parametrize(("lane", "duration", "plan"), list(plans(60)))
def test_plan_stays_in_its_lane_within_the_speed_limits(lane, duration, plan):
    position, heading, samples = along_lane(plan, duration)
    assert position.min() >= -lane.behind_m - 0.02
    assert position.max() <= lane.ahead_m + 0.02
    assert np.abs(samples.velocity_mps).max() <= 1.0 + 1e-9
    assert np.abs(samples.yaw_rate_rad_s).max() <= 0.6 * 1.001
    # turns happen in place and end along the lane (turned back, or turned about)
    moving = heading[np.abs(samples.velocity_mps) > 0]
    off_lane = np.abs(np.remainder(moving + math.pi / 2, math.pi) - math.pi / 2)
    assert off_lane.max(initial=0.0) < 0.01


def test_plans_mix_the_maneuvers():
    labels = {c["label"] for _, _, plan in plans(30) for c in plan.commands}
    shoves = {s["label"] for _, _, plan in plans(30) for s in plan.shoves}
    assert {"accelerate", "cruise", "hard stop", "brake", "reversal"} <= labels
    assert {"turn", "turn back", "turnabout", "pause"} <= labels
    assert {"shove from behind", "shove from the front"} <= shoves
    assert {"shove from the left", "shove from the right"} <= shoves


def test_shoves_respect_the_angular_impulse_caps():
    """A push's angular impulse stays within the cap of its direction (blended for a push
    at an angle to the heading: one while turning), and spans the envelope."""
    r = RANGES.shoves
    shares = []
    for _, _, plan in plans(60):
        for shove in plan.shoves:
            fx, fy, _ = shove["force_n"]
            lever = shove["duration_s"] * shove["point_m"][2]
            # angular impulse over the cap of the push's direction in the heading frame
            x, y = fx / r.max_angular_impulse_n_m_s, fy / r.max_sideways_angular_impulse_n_m_s
            shares.append(lever * math.hypot(x, y))
            assert shares[-1] <= r.impulse_fraction[1] * 1.001
            assert fx == 0.0 or fy == 0.0 or shove["label"].endswith("while turning")
    assert max(shares) > 0.8 and min(shares) < 0.3  # across the envelope


def test_same_generator_same_plan():
    a = plan_motion(np.random.default_rng(5), LANES[3], RANGES.motion, RANGES.shoves, 30.0)
    b = plan_motion(np.random.default_rng(5), LANES[3], RANGES.motion, RANGES.shoves, 30.0)
    assert a == b
