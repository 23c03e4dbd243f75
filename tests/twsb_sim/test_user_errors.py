"""What a new user gets wrong: each mistake is one line naming the file and key, exit 2."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from twsb_sim.cli import EXIT_USAGE, main
from twsb_sim.house import make_house
from twsb_sim.house.standing import STANDING_RADIUS_M, why_cannot_stand
from twsb_sim.scenario import load_scenario

TINY = "duration_s = 0.3\n"
ZERO_WEIGHTS = "".join(
    f"{name} = 0\n"
    for name in (
        "pitch_weight",
        "pitch_rate_weight",
        "velocity_weight",
        "velocity_integral_weight",
        "yaw_rate_weight",
        "yaw_integral_weight",
    )
)


def _one_line_error(capsys: pytest.CaptureFixture[str]) -> str:
    captured = capsys.readouterr()
    error = captured.err.strip()
    assert error.startswith("twsb: error: "), error
    assert error.count("\n") == 0 and "Traceback" not in error
    return error


@pytest.mark.parametrize(
    ("body", "key", "words"),
    [
        ('[house]\nname = "house3"\n', "house.name", "house1"),
        ('[house]\nname = ""\n', "house.name", "house1"),
        ("[house]\nstart = [5, 2, inf]\n", "house.start", "finite"),
        ("[house]\nstart = [5, nan, 0]\n", "house.start", "finite"),
        ("[house]\nstart = [5, 2, 1e300]\n", "house.start", "yaw"),
        ("[lidar]\nrate_hz = 1e9\n", "lidar.rate_hz", "Hz"),
        ("[lidar]\nrate_hz = 1e-9\n", "lidar.rate_hz", "Hz"),
        ("[lidar]\nbeams_per_revolution = 100000000\n", "lidar.beams_per_revolution", "7200"),
        ("[lidar]\nrange_noise_std_m = 1e9\n", "lidar.range_noise_std_m", "m"),
        ("[lidar]\nrange_max_m = 1e300\n", "lidar.range_max_m", "m"),
        ("[lidar]\nrange_min_m = 5.0\n", "lidar.range_min_m", "m"),
        ("[lidar]\nblocked_sector_center_deg = 1e9\n", "lidar.blocked_sector_center_deg", "deg"),
        ("[controller]\naggressiveness = 1e30\n", "controller.aggressiveness", "100"),
        ("[controller]\naggressiveness = 1e-30\n", "controller.aggressiveness", "0.01"),
        ("[controller]\ntorque_weight = 1e300\n", "controller.torque_weight", "1e+06"),
        ("[controller]\n" + ZERO_WEIGHTS, "controller", "do not stabilize"),
        (
            "[[shoves]]\nt_s = 0.1\nforce_n = [10.0, 0.0, 0.0]\npoint_m = [0.0, 0.0, nan]\n",
            "shoves[0].point_m",
            "body frame",
        ),
        (
            "[[shoves]]\nt_s = 0.1\nforce_n = [10.0, 0.0, 0.0]\npoint_m = [0.0, inf, 0.3]\n",
            "shoves[0].point_m",
            "body frame",
        ),
        (
            "[[shoves]]\nt_s = 0.1\nforce_n = [10.0, 0.0, 0.0]\npoint_m = [0.0, 0.0, 1e12]\n",
            "shoves[0].point_m",
            "body frame",
        ),
        ("[[shoves]]\nt_s = 0.1\nforce_n = [nan, 0.0, 0.0]\n", "shoves[0].force_n", "N"),
        ("[house]\nstart = [100.0, 100.0, 0.0]\n", "house.start", "outside house1"),
        ("[house]\nstart = [-3.0, 2.0, 0.0]\n", "house.start", "outside house1"),
        ("[house]\nstart = [5.0, 0.1, 0.0]\n", "house.start", "wall"),  # against the south wall
        ("[house]\nstart = [3.05, 0.52, 0.0]\n", "house.start", "sofa"),  # on the sofa
    ],
)
def test_a_bad_value_is_one_line_naming_file_and_key(tmp_path, capsys, body, key, words):
    scenario = tmp_path / "bad.toml"
    scenario.write_text(TINY + body)
    assert main(["run", str(scenario), "--quiet"]) == EXIT_USAGE
    error = _one_line_error(capsys)
    assert f"{scenario}: {key}:" in error and words in error


def test_a_start_in_free_floor_is_accepted_and_used(tmp_path):
    spawn = make_house("house1").spawn_poses[0]
    scenario = tmp_path / "start.toml"
    scenario.write_text(TINY + f"[house]\nstart = [{spawn.x_m}, {spawn.y_m}, 90.0]\n")
    assert main(["run", str(scenario), "--quiet", "--out", str(tmp_path / "run")]) == 0
    with np.load(tmp_path / "run" / "frames.npz") as frames:
        x, y, _ = frames["truth_position_base_in_world"][0]
        assert abs(x - spawn.x_m) < 0.02 and abs(y - spawn.y_m) < 0.02
        assert abs(frames["truth_yaw_rad"][0] - np.pi / 2) < 0.02


def test_every_spawn_pose_is_a_place_to_stand_and_walls_are_not():
    for name in ("house1", "house2"):
        house = make_house(name)
        for pose in house.spawn_poses:
            assert why_cannot_stand(house, pose.x_m, pose.y_m) is None
        for wall in house.walls:
            if wall.shape == "box" and wall.z_min_m < 0.5:
                assert why_cannot_stand(house, wall.pos[0], wall.pos[1]) is not None
    # just clear of the living room's west wall (centreline x = 0, 0.1 m thick) in house1
    house = make_house("house1")
    clear = 0.05 + STANDING_RADIUS_M + 0.01
    assert why_cannot_stand(house, clear, 2.2) is None
    assert "wall" in why_cannot_stand(house, clear - 0.03, 2.2)
    # under the dining table's top (0.71 m up), between its legs: room for the robot,
    # but not under the coffee table (0.38 m) nor for a robot 1 m tall
    assert why_cannot_stand(house, 8.6, 1.3) is None
    assert "table_1_top" in why_cannot_stand(house, 8.6, 1.3, height_m=1.0)
    assert "table_0_top" in why_cannot_stand(house, 3.05, 1.55)


def test_a_scenario_file_that_is_not_utf8_is_one_line(tmp_path, capsys):
    scenario = tmp_path / "latin1.toml"
    scenario.write_bytes("duration_s = 1.0\nname = 'caf\u00e9'\n".encode("latin-1"))
    assert main(["run", str(scenario)]) == EXIT_USAGE
    error = _one_line_error(capsys)
    assert str(scenario) in error and "UTF-8" in error


def test_a_scenario_path_that_is_a_folder_is_one_line(tmp_path, capsys):
    with pytest.raises(ValueError, match="is a folder"):
        load_scenario(tmp_path)


def test_rrd_creates_its_folders_as_out_does(tmp_path, capsys):
    scenario = tmp_path / "tiny.toml"
    scenario.write_text(TINY)
    rrd = tmp_path / "runs" / "deeper" / "tiny.rrd"
    out = tmp_path / "runs" / "tiny"
    assert main(["run", str(scenario), "--quiet", "--rrd", str(rrd), "--out", str(out)]) == 0
    assert rrd.stat().st_size > 0 and (out / "frames.npz").is_file()


@pytest.mark.parametrize(
    ("flags", "words"),
    [
        (["--out", "{file}"], "is a file"),
        (["--out", "{file}/run"], "is a file, not a folder"),
        (["--rrd", "{folder}"], "is a folder"),
        (["--rrd", "{file}/x.rrd"], "is a file, not a folder"),
    ],
)
def test_an_output_path_that_cannot_be_written_fails_before_the_run(tmp_path, capsys, flags, words):
    scenario = tmp_path / "tiny.toml"
    scenario.write_text(TINY)
    (tmp_path / "a_file").write_text("x")
    (tmp_path / "a_folder").mkdir()
    paths = {"file": tmp_path / "a_file", "folder": tmp_path / "a_folder"}
    argv = ["run", str(scenario), "--quiet", *(f.format(**paths) for f in flags)]
    assert main(argv) == EXIT_USAGE
    error = _one_line_error(capsys)
    assert flags[0] in error and words in error
    assert (tmp_path / "a_file").read_text() == "x"


@pytest.mark.parametrize("command", ["generate", "eval", "slam"])
def test_commands_writing_a_folder_refuse_an_existing_file(tmp_path, capsys, command):
    target = tmp_path / "taken"
    target.write_text("keep me")
    assert main([command, "--out", str(target), "--quiet"]) == EXIT_USAGE
    error = _one_line_error(capsys)
    assert str(target) in error and "is a file" in error
    assert target.read_text() == "keep me"


def test_tune_refuses_a_folder_as_its_parameter_file(tmp_path, capsys):
    target = tmp_path / "params.toml"
    target.mkdir()
    assert main(["tune", "--quick", "--out", str(target), "--quiet"]) == EXIT_USAGE
    assert "is a folder" in _one_line_error(capsys)


def test_generate_refuses_a_ranges_file_that_is_not_utf8(tmp_path, capsys):
    ranges = tmp_path / "ranges.toml"
    ranges.write_bytes(b"[robot]\n\xff\xfe = 1\n")
    assert main(["generate", "--ranges", str(ranges), "--show-ranges"]) == EXIT_USAGE
    assert "UTF-8" in _one_line_error(capsys)


def test_a_diverging_simulation_stops_before_writing_reset_frames(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # MuJoCo writes its warning to MUJOCO_LOG.TXT here
    from twsb_sim.frame_writer import FrameWriter
    from twsb_sim.runner import SimulationDiverged, run_scenario
    from twsb_sim.scenario import Scenario
    from twsb_sim.timeline import Shove

    # built in code: a scenario file could not hold this push (its point is 1e12 m up)
    shove = Shove(t_s=0.5, force_n=(60.0, 0.0, 0.0), point_m=(0.0, 0.0, 1e12))
    scenario = Scenario(name="diverges", duration_s=2.0, shoves=(shove,))
    writer = FrameWriter(tmp_path / "run")
    with pytest.raises(SimulationDiverged, match="MuJoCo met a NaN"):
        run_scenario(scenario, sinks=[writer])
    with np.load(tmp_path / "run" / "frames.npz") as frames:
        stamps = frames["stamps"]
        assert np.all(np.diff(stamps) > 0) and stamps[-1] <= 0.5 + 1e-9
        step_m = np.linalg.norm(np.diff(frames["truth_position_base_in_world"], axis=0), axis=1)
        assert step_m.max() < 0.1  # no jump to the model's origin
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert summary["end_reason"].startswith("diverged")


def test_eval_reads_its_parameter_file_before_simulating(tmp_path, capsys):
    params = tmp_path / "tuned.toml"
    params.write_bytes(b"\xff\xfe[improved]\n")
    argv = ["eval", "--quick", "--quiet", "--out", str(tmp_path / "report")]
    assert main([*argv, "--improved-params", str(params)]) == EXIT_USAGE
    assert str(params) in _one_line_error(capsys)
    assert not (tmp_path / "report").exists()


def test_a_data_set_with_garbled_metadata_is_one_line(tmp_path, capsys):
    root = tmp_path / "data"
    (root / "meta").mkdir(parents=True)
    (root / "meta" / "info.json").write_text('{"sett')
    assert main(["generate", "--out", str(root), "--episodes", "1", "--quiet"]) == EXIT_USAGE
    assert "meta/info.json" in _one_line_error(capsys)
    assert main(["export-bag", str(root), "--out", str(tmp_path / "bag")]) == EXIT_USAGE
    assert "not JSON" in _one_line_error(capsys)


def test_a_filter_parameter_file_that_is_not_text_is_named_once(tmp_path, capsys):
    scenario, params = tmp_path / "tiny.toml", tmp_path / "frames.npz"
    scenario.write_text(TINY)
    np.savez(params, ranges=np.ones((1, 4)))  # a scan file given where parameters belong
    assert main(["run", str(scenario), "--filter-params", str(params)]) == EXIT_USAGE
    error = _one_line_error(capsys)
    assert error.count(str(params)) == 1 and "not a text file" in error


def test_a_missing_filter_parameter_file_is_named_once(tmp_path, capsys):
    scenario, missing = tmp_path / "tiny.toml", tmp_path / "nope.toml"
    scenario.write_text(TINY)
    assert main(["run", str(scenario), "--filter-params", str(missing)]) == EXIT_USAGE
    error = _one_line_error(capsys)
    assert error.count(str(missing)) == 1 and "No such file or directory" in error


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="needs a folder no file can be made in")
def test_a_recording_that_cannot_be_made_is_one_line(tmp_path, capsys):
    scenario = tmp_path / "tiny.toml"
    scenario.write_text(TINY)
    assert main(["run", str(scenario), "--rrd", "/proc/run.rrd", "--quiet"]) == EXIT_USAGE
    error = _one_line_error(capsys)
    assert error.startswith("twsb: error: --rrd: cannot write the recording") and "/proc" in error
