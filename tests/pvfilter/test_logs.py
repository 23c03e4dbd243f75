"""False alarms on logs: the counts, the odometry of a log, the eval-logs command."""

import json
import math

import numpy as np
import pytest

from pvfilter import ImprovedPitchVariationFilter
from pvfilter.cli import main
from pvfilter.io import arrays_from_scans
from pvfilter.logs import evaluate_log, markdown, odometry_inputs
from pvfilter.synthetic import room_sequence


class RemovesTheFirstBeams:
    """A stand-in filter that removes the first ``k`` beams of scan ``k``."""

    def __init__(self):
        self.count = 0

    def process(self, scan, **inputs):
        removed = np.zeros(len(scan), bool)
        removed[: self.count] = True
        self.count += 1
        return type("Result", (), {"removed": removed})()

    def reset(self):
        self.count = 0


@pytest.fixture
def log_file(tmp_path):
    scans = room_sequence(30, event_every=1000).scans  # level: no floor line at all
    arrays = arrays_from_scans(scans)
    arrays["odom_poses"] = np.column_stack((0.01 * np.arange(30), np.zeros(30), np.zeros(30)))
    arrays["laser_offset"] = np.array([0.1, 0.0, 0.0])
    path = tmp_path / "level.npz"
    np.savez(path, **arrays)
    return path


def test_the_counts_are_the_removed_valid_beams_and_the_worst_scan(log_file):
    report = evaluate_log(log_file, "stand-in", RemovesTheFirstBeams)
    valid = 480  # 720 beams less the blocked sector
    # scan k loses its first k beams, of which those in the blocked sector are not valid
    assert report.scans == 30 and report.valid_beams == pytest.approx(30 * valid, rel=0.01)
    assert report.worst_scan == 29 and report.worst_scan_share == pytest.approx(
        29 / valid, rel=0.05
    )
    assert report.removed_beams == sum(range(30))
    assert "| level | stand-in | 30 |" in markdown([report])


def test_the_improved_filter_removes_nothing_from_a_level_log(log_file):
    report = evaluate_log(log_file, "improved", ImprovedPitchVariationFilter, odometry=True)
    assert report.removed_beams == 0 and report.worst_scan == -1 and report.odometry


def test_odometry_of_a_log_is_the_lidar_pose_in_the_odom_frame():
    arrays = {
        "odom_poses": np.array([[1.0, 2.0, math.pi / 2]]),
        "laser_offset": np.array([0.1, 0, 0]),
    }
    (inputs,) = odometry_inputs(arrays, 1)
    np.testing.assert_allclose(inputs["pose_sensor_in_odom"], [1.0, 2.1, math.pi / 2])
    assert odometry_inputs({}, 1) is None
    with pytest.raises(ValueError, match="odom_poses"):
        odometry_inputs({"odom_poses": np.zeros((2, 3))}, 1)


def test_the_command_reports_every_log_and_skips_files_without_scans(log_file, tmp_path, capsys):
    np.savez(tmp_path / "relations.npz", rel_pose=np.zeros((2, 3)))
    out = tmp_path / "report"
    assert main(["eval-logs", str(tmp_path), "--out", str(out), "--odometry"]) == 0
    printed = capsys.readouterr().out
    assert "relations.npz: no scans (skipped)" in printed
    rows = json.loads((out / "report.json").read_text())
    assert {(r["log"], r["filter"]) for r in rows} == {("level", "improved"), ("level", "paper")}
    assert all(r["removed_beams"] == 0 for r in rows if r["filter"] == "improved")
    assert "| level | improved |" in (out / "report.md").read_text()


def test_the_reports_say_what_parameters_each_filter_ran_with(log_file, tmp_path):
    out = tmp_path / "report"
    assert main(["eval-logs", str(log_file), "--out", str(out), "--set", "max_gap_s=1.0"]) == 0
    rows = json.loads((out / "report.json").read_text())
    assert {r["filter"]: r["settings"] for r in rows} == {
        "improved": "--set max_gap_s=1.0",
        "paper": "defaults",
    }
    assert (
        "Parameters: improved: --set max_gap_s=1.0; paper: defaults."
        in (out / "report.md").read_text()
    )


def test_the_command_names_a_missing_path(tmp_path, capsys):
    assert main(["eval-logs", str(tmp_path / "nowhere")]) == 2
    assert "nowhere: no such file or folder" in capsys.readouterr().err


def test_the_command_takes_parameters_and_names_a_bad_one(log_file, capsys):
    assert main(["eval-logs", str(log_file), "--set", "p_th=0.9", "--compare"]) == 0
    assert "level" in capsys.readouterr().out
    assert main(["eval-logs", str(log_file), "--set", "no_such=1"]) == 2
    assert "no_such" in capsys.readouterr().err


def test_a_tuned_filter_is_compared_with_its_own_defaults(log_file, tmp_path, capsys):
    out = tmp_path / "report"
    argv = ["eval-logs", str(log_file), "--set", "p_th=0.3", "--compare", "improved", "--out"]
    assert main([*argv, str(out)]) == 0
    rows = json.loads((out / "report.json").read_text())
    assert {r["filter"]: r["settings"] for r in rows} == {
        "improved": "--set p_th=0.3",
        "improved (defaults)": "defaults",
    }
    assert "improved (defaults)" in capsys.readouterr().out


def test_an_output_that_cannot_be_a_folder_is_refused_before_the_work(log_file, tmp_path, capsys):
    taken = tmp_path / "results.txt"
    taken.write_text("mine")
    assert main(["eval-logs", str(log_file), "--out", str(taken)]) == 2
    captured = capsys.readouterr()
    assert "--out" in captured.err and "results.txt" in captured.err
    assert "level" not in captured.out  # no log was read
    assert taken.read_text() == "mine"


def test_a_log_without_odometry_or_without_a_valid_beam_is_noted(tmp_path, capsys):
    arrays = arrays_from_scans(room_sequence(5, event_every=1000).scans)  # no odometry
    np.savez(tmp_path / "plain.npz", **arrays)
    np.savez(tmp_path / "millimetres.npz", **dict(arrays, ranges=1000.0 * arrays["ranges"]))
    assert main(["eval-logs", str(tmp_path), "--odometry", "--compare"]) == 0
    printed = capsys.readouterr().out
    assert "plain.npz: the log has no odometry (run without it)" in printed
    assert "millimetres.npz: no beam lies within [range_min, range_max]" in printed
    assert "plain.npz: no beam" not in printed


def test_a_filter_compared_twice_runs_once(log_file, tmp_path):
    out = tmp_path / "report"
    assert main(["eval-logs", str(log_file), "--compare", "paper", "paper", "--out", str(out)]) == 0
    rows = json.loads((out / "report.json").read_text())
    assert sorted(r["filter"] for r in rows) == ["improved", "paper"]
