"""``twsb slam``'s outputs on a short run: report, JSON, figures, TUM files that evo scores
exactly as we do, and a Rerun recording with the maps, trajectories and scans."""

import json
import shutil
import subprocess

import numpy as np
import pytest

from scaneval.tum import read_tum
from twsb_sim.cli import main
from twsb_sim.slam.experiment import SlamConfig
from twsb_sim.slam.pipeline import run_slam_experiment
from twsb_sim.slam.systems import available_systems

# house1_single up to its second leg: evo's 3D alignment refuses a straight-line path
# ("degenerate covariance rank"), so the path must turn and go on
SHORT = SlamConfig(
    sequences=("house1_single",),
    random_houses=(),
    seeds=(0,),
    methods=("none", "pvf"),
    duration_s=23.0,
)


@pytest.fixture(scope="module")
def short_experiment(tmp_path_factory):
    out = tmp_path_factory.mktemp("slam")
    return out, run_slam_experiment(SHORT, out, progress=False, rerun=True)


def test_writes_the_report_json_figures_and_recording(short_experiment):
    out, outputs = short_experiment
    report = (out / "report.md").read_text()
    assert "Table II" in report and "House1" in report and "1.0522" in report  # the paper's
    results = json.loads((out / "results.json").read_text())
    assert {r["system"] for r in results["runs"]} == set(available_systems())
    assert len(results["runs"]) == len(outputs.results) >= 2
    assert {r["method"] for r in results["runs"]} == {"none", "pvf"}
    assert results["failure_distance_m"] == pytest.approx(1.0)
    for figure in outputs.figures:
        assert (out / figure).read_bytes()[:4] == b"\x89PNG"
    assert outputs.recordings == ["slam_house1_single.rrd"]


def test_tum_files_hold_one_pose_per_scan(short_experiment):
    out, outputs = short_experiment
    for result in outputs.results:
        stamps, rows = read_tum(out / result.trajectory_file)
        truth_stamps, _ = read_tum(out / result.truth_file)
        assert len(stamps) == result.scans == len(truth_stamps)
        np.testing.assert_allclose(rows[:, 2], 0.0)  # planar: z = 0


def test_our_ate_equals_evo_ape_on_the_same_files(short_experiment):
    pytest.importorskip("evo")
    from evo.core import sync
    from evo.core.metrics import PoseRelation
    from evo.main_ape import ape
    from evo.tools import file_interface

    out, outputs = short_experiment
    for result in outputs.results:
        truth = file_interface.read_tum_trajectory_file(out / result.truth_file)
        estimate = file_interface.read_tum_trajectory_file(out / result.trajectory_file)
        truth, estimate = sync.associate_trajectories(truth, estimate)
        evo_result = ape(truth, estimate, PoseRelation.translation_part, align=True)
        assert evo_result.stats["rmse"] == pytest.approx(result.ate_m, abs=1e-6)
        assert evo_result.stats["max"] == pytest.approx(result.max_error_m, abs=1e-6)


def test_the_evo_ape_command_agrees(short_experiment):
    command = shutil.which("evo_ape")
    if command is None:
        pytest.skip("evo is not installed")
    out, outputs = short_experiment
    result = outputs.results[0]
    printed = subprocess.run(
        [command, "tum", out / result.truth_file, out / result.trajectory_file, "--align"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    rmse = next(float(line.split()[-1]) for line in printed.splitlines() if "rmse" in line)
    assert rmse == pytest.approx(result.ate_m, abs=1e-5)


def test_the_recording_holds_maps_trajectories_and_scans(short_experiment):
    from rerun.chunk import RrdReader

    out, outputs = short_experiment
    chunks = list(RrdReader(out / outputs.recordings[0]).stream().to_chunks())
    paths = {chunk.entity_path for chunk in chunks}
    for method in ("none", "pvf"):
        for leaf in ("map", "trajectory", "pose", "scan", "removed"):
            assert f"/world/slam/hector/{method}/{leaf}" in paths
    assert "/world/truth/trajectory" in paths
    assert "/world/house/walls" in paths


def test_bad_seeds_are_a_one_line_error(tmp_path, capsys):
    assert main(["slam", "--out", str(tmp_path), "--seeds", "-1", "--quiet"]) == 2
    assert "seeds" in capsys.readouterr().err
