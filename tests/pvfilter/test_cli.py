"""The pvfilter command: a scan file in, a filtered scan file out."""

import numpy as np
import pytest

from pvfilter import PitchVariationFilter
from pvfilter.cli import main
from pvfilter.improved import ImprovedPitchVariationFilter
from pvfilter.io import arrays_from_scans
from pvfilter.synthetic import room_sequence


@pytest.fixture
def scan_file(tmp_path):
    path = tmp_path / "scans.npz"
    np.savez(path, **arrays_from_scans(room_sequence(30).scans))
    return path


@pytest.mark.parametrize("extra", [[], ["--threaded"]])
def test_output_matches_the_library(scan_file, tmp_path, capsys, extra):
    assert main([str(scan_file), str(tmp_path / "out.npz"), *extra]) == 0
    assert "30 scans" in capsys.readouterr().out
    pvf = PitchVariationFilter()
    expected = np.array([pvf.process(s).removed for s in room_sequence(30).scans])
    with np.load(tmp_path / "out.npz") as out:
        np.testing.assert_array_equal(out["removed"], expected)


def test_options_set_the_parameters(scan_file, tmp_path):
    out = tmp_path / "out.npz"
    assert main([str(scan_file), str(out), "--p-th", "1.0", "--clustering", "radius"]) == 0
    with np.load(out) as data:
        assert not data["removed"].any()


def test_invalid_parameter_exits_with_the_field_message(scan_file, tmp_path, capsys):
    assert main([str(scan_file), str(tmp_path / "out.npz"), "--d-th", "-1"]) == 2
    assert "d_th: must be > 0 m, got -1.0" in capsys.readouterr().err


def test_unreadable_file_is_an_error_not_a_traceback(tmp_path, capsys):
    np.savez(tmp_path / "bad.npz", ranges=np.ones((2, 3)))
    assert main([str(tmp_path / "bad.npz"), str(tmp_path / "out.npz")]) == 2
    assert "stamps: missing" in capsys.readouterr().err
    assert main([str(tmp_path / "absent.npz"), str(tmp_path / "out.npz")]) == 2


def test_a_clockwise_file_is_filtered_and_scored_as_its_scans_and_written_in_its_order(
    tmp_path, capsys
):
    sequence = room_sequence(30)
    arrays = arrays_from_scans(sequence.scans)
    arrays["labels"] = np.where(np.array(sequence.truth), 2, 1).astype(np.uint8)  # FLOOR, STATIC
    last = arrays["ranges"].shape[1] - 1
    written = arrays | {
        "ranges": arrays["ranges"][:, ::-1],
        "labels": arrays["labels"][:, ::-1],
        "angle_min": arrays["angle_min"] + last * arrays["angle_increment"],
        "angle_increment": -arrays["angle_increment"],
    }
    lines = {}
    for name, file_arrays in (("ccw", arrays), ("cw", written)):
        np.savez(tmp_path / f"{name}.npz", **file_arrays)
        assert main([str(tmp_path / f"{name}.npz"), str(tmp_path / f"{name}_out.npz")]) == 0
        lines[name] = [line for line in capsys.readouterr().out.splitlines() if "labels" in line]
    assert lines["cw"] == lines["ccw"] and "precision" in lines["cw"][0]
    with np.load(tmp_path / "ccw_out.npz") as ccw, np.load(tmp_path / "cw_out.npz") as cw:
        assert ccw["removed"].any()
        np.testing.assert_array_equal(cw["removed"], ccw["removed"][:, ::-1])
        np.testing.assert_array_equal(cw["ranges"], ccw["ranges"][:, ::-1])


def test_bad_labels_end_the_command_before_the_output_is_written(scan_file, tmp_path, capsys):
    arrays = dict(np.load(scan_file))
    arrays["labels"] = np.full(arrays["ranges"].shape, 255, np.uint8)  # codes are 0..6
    np.savez(tmp_path / "bad.npz", **arrays)
    assert main([str(tmp_path / "bad.npz"), str(tmp_path / "out.npz")]) == 2
    assert "labels: codes are 0..6" in capsys.readouterr().err
    assert not (tmp_path / "out.npz").exists()


def test_a_labelled_file_without_scans_is_filtered_without_a_score(scan_file, tmp_path, capsys):
    arrays = {k: v[:0] if np.ndim(v) else v for k, v in np.load(scan_file).items()}
    arrays["labels"] = np.zeros(arrays["ranges"].shape, np.uint8)
    np.savez(tmp_path / "empty.npz", **arrays)
    assert main([str(tmp_path / "empty.npz"), str(tmp_path / "out.npz")]) == 0
    out = capsys.readouterr().out
    assert "0 scans" in out and "labels" not in out
    assert (tmp_path / "out.npz").exists()


@pytest.fixture
def told_heights(monkeypatch):
    """The (lidar, axle, ahead) geometry each improved filter the command builds is given."""
    told = []
    build = ImprovedPitchVariationFilter.__init__

    def spy(self, params=None, *args, **kwargs):
        build(self, params, *args, **kwargs)
        told.append((self.params.lidar_height_m, self.params.axle_height_m,
                     self.params.lidar_ahead_m))  # fmt: skip

    monkeypatch.setattr(ImprovedPitchVariationFilter, "__init__", spy)
    return told


@pytest.fixture
def tall_robot_file(tmp_path):
    """Scans from a robot that states its geometry: LiDAR 0.5 m up, axle 0.1 m, 0.02 m ahead."""
    arrays = arrays_from_scans(room_sequence(10).scans)
    arrays.update(lidar_height_m=np.array(0.5), axle_height_m=0.1, lidar_ahead_m=0.02)
    path = tmp_path / "tall.npz"
    np.savez(path, **arrays)
    return path


def test_the_geometry_a_file_states_is_told_to_the_filter(tall_robot_file, tmp_path, capsys,
                                                          told_heights):  # fmt: skip
    assert main([str(tall_robot_file), str(tmp_path / "out.npz"), "--improved"]) == 0
    assert told_heights == [(0.5, 0.1, 0.02)]
    printed = capsys.readouterr().out
    assert "geometry (m) from the file: lidar_height_m 0.500, axle_height_m 0.100" in printed


def test_the_options_win_over_the_files_geometry(tall_robot_file, tmp_path, told_heights):
    argv = [str(tall_robot_file), str(tmp_path / "out.npz"), "--improved"]
    assert main([*argv, "--lidar-height", "0.4", "--set", "axle_height_m=0.05"]) == 0
    # a value checked against another is checked against the one the filter runs with: an
    # axle 0.3 m up is above the default LiDAR height (0.25 m), below the file's (0.5 m)
    assert main([*argv, "--set", "axle_height_m=0.3"]) == 0
    assert told_heights == [(0.4, 0.05, 0.02), (0.5, 0.3, 0.02)]


def test_a_parameter_file_gives_the_geometry_the_scan_file_does_not(scan_file, tmp_path, capsys,
                                                                    told_heights):  # fmt: skip
    params = tmp_path / "robot.toml"
    params.write_text('filter = "improved"\n[improved]\nlidar_height_m = 0.4\n')
    assert main([str(scan_file), str(tmp_path / "out.npz"), "--params", str(params)]) == 0
    printed = capsys.readouterr().out
    assert "from the parameter file: lidar_height_m 0.400; defaults: axle_height_m 0.080" in printed
    params.write_text('filter = "improved"\n[improved]\np_th = 0.6\n')  # no geometry in it
    assert main([str(scan_file), str(tmp_path / "out.npz"), "--params", str(params)]) == 0
    assert "no robot geometry given" in capsys.readouterr().out
    assert told_heights == [(0.4, 0.08, 0.0), (0.25, 0.08, 0.0)]


def test_geometry_a_file_states_that_cannot_be_is_an_error_naming_the_file(
    tall_robot_file, tmp_path, capsys
):
    out = tmp_path / "out.npz"
    argv = [str(tall_robot_file), str(out), "--improved", "--lidar-height", "0.05"]
    assert main(argv) == 2  # below the axle the file states (0.1 m)
    assert (
        "tall.npz: with the robot geometry it states (axle_height_m 0.1" in capsys.readouterr().err
    )
    arrays = dict(np.load(tall_robot_file))
    np.savez(tall_robot_file, **{**arrays, "lidar_height_m": np.array("high")})
    assert main([str(tall_robot_file), str(out), "--improved"]) == 2
    assert "tall.npz: lidar_height_m: must be one finite number, m" in capsys.readouterr().err
    assert not out.exists()


def test_a_file_without_geometry_says_the_filter_took_its_defaults(scan_file, tmp_path, capsys,
                                                                   told_heights):  # fmt: skip
    assert main([str(scan_file), str(tmp_path / "out.npz"), "--improved"]) == 0
    assert told_heights == [(0.25, 0.08, 0.0)]
    printed = capsys.readouterr().out
    assert "no robot geometry given: the filter took its defaults, lidar_height_m 0.250" in printed
    assert main([str(scan_file), str(tmp_path / "out.npz"), "--improved", "--set",
                 "lidar_height_m=0.3"]) == 0  # fmt: skip
    printed = capsys.readouterr().out  # set by hand, and where the rest came from
    assert "from the options: lidar_height_m 0.300; defaults: axle_height_m 0.080" in printed


def test_a_filter_without_geometry_runs_on_a_file_that_states_it(tall_robot_file, tmp_path, capsys):
    assert main([str(tall_robot_file), str(tmp_path / "out.npz")]) == 0  # the paper's filter
    printed = capsys.readouterr().out
    assert "robot geometry" not in printed and "robot's geometry" not in printed


def test_a_file_without_a_valid_beam_is_noted_not_passed_as_clean(tmp_path, capsys):
    arrays = arrays_from_scans(room_sequence(3).scans)
    millimetres = tmp_path / "mm.npz"
    np.savez(millimetres, **dict(arrays, ranges=1000.0 * arrays["ranges"]))
    assert main([str(millimetres), str(tmp_path / "out.npz"), "--improved"]) == 0
    printed = capsys.readouterr().out
    assert "removed 0 of 0 valid beams" in printed
    assert (
        "mm.npz: no beam lies within [range_min, range_max]: are the ranges in metres?" in printed
    )
    np.savez(tmp_path / "m.npz", **arrays)
    assert main([str(tmp_path / "m.npz"), str(tmp_path / "out.npz"), "--improved"]) == 0
    assert "no beam lies within" not in capsys.readouterr().out


def test_the_paper_filter_run_by_default_says_so(scan_file, tmp_path, capsys):
    out = tmp_path / "out.npz"
    assert main([str(scan_file), str(out)]) == 0
    assert "the paper's filter ran, the default; --improved runs" in capsys.readouterr().out
    for chosen in (["--improved"], ["--filter", "paper"], ["--filter", "improved"]):
        assert main([str(scan_file), str(out), *chosen]) == 0
        assert "the default" not in capsys.readouterr().out
