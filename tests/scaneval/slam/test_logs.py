"""SLAM on scan files with and without a filter: the run without one tracks the file's
reference, a filter that removes nothing shifts nothing, one that removes walls does; and
the real logs (when present), where the improved filter must cost SLAM nothing."""

from __future__ import annotations

import json
import math
import os
from pathlib import Path

import numpy as np
import pytest

from pvfilter import FilterResult, make_filter
from pvfilter.io import arrays_from_scans
from pvfilter.result import without_removed
from scaneval.slam.logs import slam_on_log
from scaneval.synthetic import cluttered_room, scan_from_pose
from twsb_sim.cli import main

REAL_LOGS = Path(os.environ.get("PVFILTER_REAL_LOGS", Path(__file__).resolve().parents[3]
                                / ".." / "shared" / "realdata"))  # fmt: skip


class KeepsOnlyTheLeftWall:
    """A filter that removes every beam but those within 15 deg of the left: a stretch of
    wall along the travel, which cannot show it."""

    def process(self, scan, **_):
        removed = np.abs(scan.angles() - math.pi / 2) > math.radians(15.0)
        return FilterResult(without_removed(scan, removed), removed, removed.astype(float))

    def reset(self):
        pass


@pytest.fixture(scope="module")
def scan_file(tmp_path_factory) -> Path:
    """80 scans of a sensor driving 1.6 m along x and back in the cluttered room, with its
    true poses as the file's reference."""
    x = 1.6 * np.sin(np.linspace(0.0, np.pi, 80))
    poses = np.column_stack((x - 0.8, np.full(80, -0.4), np.zeros(80)))
    rng = np.random.default_rng(3)
    room = cluttered_room()
    scans = [scan_from_pose(room, pose, stamp=0.1 * k, rng=rng) for k, pose in enumerate(poses)]
    path = tmp_path_factory.mktemp("logs") / "drive.npz"
    np.savez(path, **arrays_from_scans(scans), ref_poses=poses)
    return path


def test_no_filter_tracks_the_reference_and_removing_nothing_shifts_nothing(scan_file):
    runs = slam_on_log(scan_file, {"keep": lambda: make_filter("none")}, ("hector",))
    assert [r.filter for r in runs] == ["none", "keep"]
    for run in runs:
        assert run.reference == "ref_poses" and not run.failed, run
        assert run.ate_m < 0.05 and run.removed_share == 0.0
    assert runs[1].shift_m == pytest.approx(0.0, abs=1e-9)


def test_a_filter_that_removes_what_shows_the_travel_shifts_the_trajectory(scan_file):
    runs = slam_on_log(scan_file, {"blind": KeepsOnlyTheLeftWall}, ("hector",))
    blind = runs[1]
    assert blind.removed_share > 0.8
    assert blind.shift_m > 0.1 and blind.ate_m > runs[0].ate_m


def test_the_command_writes_its_report_and_refuses_filters_that_need_inputs(scan_file, tmp_path):
    out = tmp_path / "report"
    argv = ["slam-logs", str(scan_file), "--out", str(out), "--systems", "hector", "--quiet"]
    assert main([*argv, "--filters", "improved"]) == 0
    results = json.loads((out / "results.json").read_text())
    assert [r["filter"] for r in results["runs"]] == ["none", "improved"]
    assert "| drive | hector | improved |" in (out / "report.md").read_text()
    assert main([*argv, "--filters", "imu_gate"]) == 2
    assert main(["slam-logs", str(tmp_path / "missing.npz"), "--out", str(out)]) == 2


@pytest.mark.skipif(not REAL_LOGS.is_dir(), reason=f"real logs not found at {REAL_LOGS}: set "
                    "PVFILTER_REAL_LOGS to their folder")  # fmt: skip
def test_the_improved_filter_costs_slam_nothing_on_a_real_rover_log():
    path = REAL_LOGS / "mines_exp1.npz"
    if not path.is_file():
        pytest.skip(f"{path}: not found")
    runs = slam_on_log(path, {"improved": lambda: make_filter("improved")}, ("hector",))
    none, improved = runs
    assert not none.failed and none.reference == "odom_poses"
    assert improved.removed_share == 0.0 and improved.shift_m < 1e-6
