"""The improved filter in twsb eval: one-pass sweeps, robot overrides, the report's section."""

from __future__ import annotations

import json

import numpy as np
import pytest

from pvfilter import ImprovedParams, save_params
from pvfilter.synthetic import cross_line, room_segments
from twsb_sim.cli import main
from twsb_sim.evaluation.improved import improved_filter, one_pass
from twsb_sim.evaluation.passes import sweep_counts
from twsb_sim.evaluation.recording import Recording, sequence_in_house, with_robot
from twsb_sim.summary import RunSummary

ROOM = room_segments(4.0, 4.0, 2.0, 2.0)


def recording_of(frames) -> Recording:
    return Recording(
        sequence="synthetic", house="none", seed=0, frames=tuple(frames),
        geom_names=("wall", "floor"),
        geometry={"lidar_height_m": 0.25, "axle_height_m": 0.08, "lidar_ahead_m": 0.0},
        summary=RunSummary(scenario="synthetic", seed=0, house="none"),
    )  # fmt: skip


def test_one_pass_equals_a_fresh_filter_per_threshold(make_frame):
    floors = [None, None, cross_line(1.2, 1.5), cross_line(1.0, 1.5), None, None]
    recording = recording_of([make_frame(k, ROOM, f) for k, f in enumerate(floors)])
    thresholds = (0.0, 0.3, 0.5, 0.9)
    counts, removed, total, seconds = one_pass(
        recording, improved_filter(recording), thresholds, 0.5
    )
    fresh = sweep_counts(
        recording, lambda v: improved_filter(recording, ImprovedParams(p_th=v)), thresholds
    )
    np.testing.assert_array_equal(counts, fresh)
    assert counts[2, 0] > 0 and removed == 0 and total > 0 and seconds.shape == (6,)


def test_robot_overrides_change_only_what_they_name():
    scenario, _ = sequence_in_house("normal_sequence", "house1", None, 2.0)
    changed = with_robot(scenario, {"robot": {"lidar_height_m": 0.4},
                                    "controller": {"aggressiveness": 2.0}})  # fmt: skip
    assert changed.robot.lidar_height_m == 0.4 and changed.controller.aggressiveness == 2.0
    assert changed.robot.body_mass_kg == scenario.robot.body_mass_kg
    assert changed.lidar == scenario.lidar


@pytest.fixture(scope="module")
def quick_report(tmp_path_factory):
    out = tmp_path_factory.mktemp("eval_improved")
    params = out / "tuned.toml"
    save_params(params, ImprovedParams(p_th=0.4))
    argv = ["eval", "--quick", "--quiet", "--variations", "--improved-params", str(params),
            "--out", str(out)]  # fmt: skip
    assert main(argv) == 0
    return out


def test_quick_eval_compares_the_improved_filter(quick_report):
    results = json.loads((quick_report / "results.json").read_text())
    improved = results["improved"]
    methods = {
        "pvf",
        "imu_gate",
        "improved",
        "improved_imu",
        "improved_imu_truth",
        "improved_tuned",
    }
    for group in ("sequences", "heldout", "variations"):
        for per_method in improved[group].values():
            assert set(per_method) == methods
            for m in per_method.values():
                assert 0.0 <= m["auc"] <= 1.0 and 0.0 <= m["static_removed_pct"] <= 100.0
    assert set(improved["variations"]) == {"default robot", "LiDAR at 0.15 m"}
    ablation = improved["ablation"]["normal_sequence"]
    assert {"full", "no_line_length", "no_sweep_bend", "with_imu", "with_odometry",
            "with_imu_odometry"} <= set(ablation)  # fmt: skip
    assert set(ablation) == set(improved["ablation_switches"])
    # the same frames through the same filter with the same inputs give the same numbers
    assert ablation["with_imu"]["auc"] == improved["sequences"]["normal_sequence"][
        "improved_imu"]["auc"]  # fmt: skip
    assert improved["tuned_params"]["p_th"] == 0.4
    assert improved["timing"]["same_loop_improved"]["rate_hz"] > 0
    diagnosis = improved["diagnosis"]["normal_sequence"]
    assert sum(diagnosis["misses"].values()) <= diagnosis["positives"]
    report = (quick_report / "report.md").read_text()
    for heading in ("The improved filter beside the paper's", "Ablation", "Held-out random houses",
                    "Robot variations: LiDAR at 0.15 m", "still fails"):  # fmt: skip
        assert heading in report
    assert (quick_report / "improved_pr_curves.png").stat().st_size > 0


def test_a_missing_parameter_file_is_a_usage_error(tmp_path, capsys):
    argv = ["eval", "--quick", "--out", str(tmp_path), "--improved-params", "nope.toml"]
    assert main(argv) == 2
    assert "no such parameter file" in capsys.readouterr().err
