"""The pvfilter command: a scan file in, a filtered scan file out."""

import numpy as np
import pytest

from pvfilter import PitchVariationFilter
from pvfilter.cli import main
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
