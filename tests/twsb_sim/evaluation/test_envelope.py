"""The survivable envelope and the generator's pitch events: bisection, event splitting,
the command's file."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from twsb_sim.cli import main
from twsb_sim.evaluation.envelope import Bench, RobotUnderTest, shove_limit
from twsb_sim.evaluation.generator_stats import pitch_events


def test_the_shove_limit_is_the_largest_push_survived():
    bench = Bench(RobotUnderTest())
    limit = shove_limit(bench, "behind", 0.3)
    assert 3.0 <= limit.angular_impulse_n_m_s <= 6.0  # ~10 deg per N·m·s, falls near 45 deg
    assert limit.impulse_n_s == pytest.approx(limit.force_n * 0.1, rel=1e-3)
    assert limit.peak_deg > 30.0
    assert bench.shove_trial("behind", 0.3, limit.force_n, False)[0]
    assert not bench.shove_trial("behind", 0.3, 1.05 * limit.force_n, False)[0]
    assert bench.shove_trial("behind", 0.3, 0.5 * limit.force_n, False)[1] < limit.peak_deg


def test_pitch_events_split_at_gaps_and_keep_their_signed_peaks():
    t = np.arange(0, 6, 0.01)
    pitch = 12 * np.exp(-((t - 1) ** 2) / 0.02) - 25 * np.exp(-((t - 3) ** 2) / 0.02)
    pitch += 8 * np.exp(-((t - 3.35) ** 2) / 0.005)  # a sway 0.35 s later: the same event
    events = pitch_events(pitch, 100.0)
    assert events == pytest.approx([12.0, -25.0], abs=0.05)
    assert pitch_events(np.full(100, 4.9), 100.0) == []


def test_envelope_command_writes_its_numbers(tmp_path):
    out = tmp_path / "envelope.json"
    assert main(["envelope", "--out", str(out), "--quick", "--robots", "1"]) == 0
    result = json.loads(out.read_text())
    rows = result["default_robot"]["shoves_standing"]
    assert {r["direction"] for r in rows} == {"behind", "left"}
    behind, left = (next(r for r in rows if r["direction"] == d) for d in ("behind", "left"))
    assert (
        left["angular_impulse_n_m_s"] < behind["angular_impulse_n_m_s"]
    )  # it tips sideways sooner
    assert result["default_robot"]["hard_stop_deg"]["nose_up"] < -10.0
    (robot,) = result["randomized_robots"]["robots"]
    assert robot["robot_class"] and math.isfinite(robot["shoves_standing"][0]["force_n"])


def test_envelope_command_refuses_a_negative_count(tmp_path, capsys):
    assert main(["envelope", "--out", str(tmp_path / "e.json"), "--robots", "-1"]) == 2
    assert "--robots" in capsys.readouterr().err
