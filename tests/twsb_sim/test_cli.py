"""The ``twsb run`` command: a summary, written frames, one-line errors, exit codes."""

from __future__ import annotations

import json

import numpy as np
import pytest

from twsb_sim.cli import EXIT_FELL, EXIT_USAGE, main
from twsb_sim.filter_args import robot_geometry
from twsb_sim.scenario import load_scenario

SHORT = """
duration_s = 1.0
[[commands]]
t_s = 0.2
velocity_mps = 0.5
ramp_s = 0.5
"""


def test_run_prints_a_summary_and_writes_frames(tmp_path, capsys):
    scenario = tmp_path / "short.toml"
    scenario.write_text(SHORT)
    out = tmp_path / "run"
    assert main(["run", str(scenario), "--seed", "2", "--out", str(out), "--quiet"]) == 0
    printed = capsys.readouterr().out
    expected = ("simulated", "real time", "frames", "max |pitch|", "beams by label", "falls")
    for item in (*expected, "filter"):
        assert item in printed
    with np.load(out / "frames.npz") as frames:
        assert frames["ranges"].shape == (11, 720)
        assert frames["labels"].dtype == np.uint8
        assert frames["removed"].shape == (11, 720)
        assert frames["truth_pitch_rad"].shape == (11,)
        # per-beam timing of the rotating scan, and what the robot's sensors reported
        assert frames["time_increment"] == pytest.approx(0.1 / 720)
        np.testing.assert_allclose(np.diff(frames["stamps"]), 0.1, atol=1e-9)
        assert frames["sensor_attitude_rpy_rad"].shape == (11, 3)
        assert frames["sensor_pose_lidar_in_odom"].shape == (11, 3)
        per_frame = frames["imu_samples_per_frame"]
        assert frames["imu_samples"].shape == (per_frame.sum(), 10) and per_frame[1:].min() > 0
        assert frames["odometry_samples"].shape == (frames["odometry_samples_per_frame"].sum(), 6)
        # the robot the filter in the loop was told of, so an offline run sees the same one
        geometry = robot_geometry(load_scenario(scenario))
        assert {key: float(frames[key]) for key in geometry} == geometry
    summary = json.loads((out / "summary.json").read_text())
    assert summary["frames"] == 11 and summary["seed"] == 2
    assert (out / "scenario.toml").read_text() == SHORT


def test_shipped_scenarios_are_found_by_name(capsys):
    assert main(["run", "no_such_scenario"]) == EXIT_USAGE
    error = capsys.readouterr().err
    assert "no such scenario file" in error and "hard_stop" in error


def test_bad_scenario_is_one_line_naming_file_and_key(tmp_path, capsys):
    scenario = tmp_path / "bad.toml"
    scenario.write_text("duration_s = 1.0\n[robot]\nlidar_hieght_m = 0.3\n")
    assert main(["run", str(scenario)]) == EXIT_USAGE
    error = capsys.readouterr().err.strip()
    assert error.count("\n") == 0 and "Traceback" not in error
    assert str(scenario) in error and "robot.lidar_hieght_m" in error and "unknown key" in error


def test_a_fall_exits_with_its_own_status_and_keeps_the_frames(tmp_path, capsys):
    scenario = tmp_path / "fall.toml"
    scenario.write_text(
        "duration_s = 4.0\n[[shoves]]\nt_s = 0.5\nforce_n = [300.0, 0.0, 0.0]\nduration_s = 0.5\n"
    )
    out = tmp_path / "run"
    assert main(["run", str(scenario), "--out", str(out), "--quiet", "--no-filter"]) == EXIT_FELL
    assert "fell: |pitch|" in capsys.readouterr().out
    with np.load(out / "frames.npz") as frames:
        assert 0 < len(frames["stamps"]) < 41
        assert "removed" not in frames.files


def test_run_takes_any_registered_filter_a_user_s_own_too(tmp_path, capsys):
    import dataclasses

    from pvfilter import FilterEntry, FilterResult, register_filter
    from pvfilter.registry import unregister_filter

    @dataclasses.dataclass(frozen=True)
    class EverythingParams:
        p_th: float = 0.5

    class Everything:
        """Removes every valid beam."""

        def __init__(self, params=None):
            self.params = params or EverythingParams()

        def process(self, scan, **robot_inputs):
            removed = scan.valid_mask()
            return FilterResult(scan, removed, removed.astype(float))

        def reset(self):
            pass

    scenario = tmp_path / "short.toml"
    scenario.write_text(SHORT)
    register_filter(FilterEntry("everything", Everything, EverythingParams))
    try:
        for name in ("improved", "paper", "imu_gate", "datmo", "none", "everything"):
            assert main(["run", str(scenario), "--quiet", "--filter", name]) == 0, name
            printed = capsys.readouterr().out
            assert "filter " in printed, name
        assert "everything (in the loop): removed" in printed and "recall 1.000" in printed
    finally:
        unregister_filter("everything")
    assert main(["run", str(scenario), "--quiet", "--filter", "everything"]) == EXIT_USAGE
    assert "unknown filter 'everything'" in capsys.readouterr().err


def test_run_shows_the_improved_filter_in_the_loop_and_the_paper_s_beside_it(tmp_path, capsys):
    scenario = tmp_path / "short.toml"
    scenario.write_text(SHORT)
    out = tmp_path / "run"
    assert main(["run", str(scenario), "--quiet", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "filter          improved (in the loop): removed" in printed
    assert "paper (same frames):" in printed
    assert "why these differ: docs/filters.md#why-the-two-filters-differ" in printed
    summary = json.loads((out / "summary.json").read_text())
    assert summary["filter_name"] == "improved"
    assert [row["name"] for row in summary["compared"]] == ["paper"]
    assert 0.0 <= summary["compared"][0]["counts"]["precision"] <= 1.0
    # no comparison asked for, or the same filter: one line
    assert main(["run", str(scenario), "--quiet", "--filter", "paper"]) == 0
    assert "same frames" not in capsys.readouterr().out
    assert main(["run", str(scenario), "--quiet", "--compare"]) == 0
    assert "same frames" not in capsys.readouterr().out


def test_the_summary_s_pointer_to_the_docs_leads_somewhere():
    from pathlib import Path

    from twsb_sim.summary import WHY_FILTERS_DIFFER

    page, anchor = WHY_FILTERS_DIFFER.split("#")
    text = (Path(__file__).resolve().parents[2] / page).read_text(encoding="utf-8")
    headings = {line.lstrip("#").strip().lower().replace(" ", "-") for line in text.splitlines()
                if line.startswith("#")}  # fmt: skip
    assert anchor in headings
