"""Parameter files: TOML and JSON round trips, mistakes named, the pvfilter command's --params."""

import numpy as np
import pytest

from pvfilter import (
    FilterParams,
    ImprovedParams,
    ImprovedPitchVariationFilter,
    load_params,
    save_params,
)
from pvfilter.cli import main
from pvfilter.io import arrays_from_scans, load_scans
from pvfilter.params_file import params_from_table
from pvfilter.registry import filter_for
from pvfilter.synthetic import room_sequence


@pytest.mark.parametrize("suffix", [".toml", ".json"])
@pytest.mark.parametrize(
    "params",
    [ImprovedParams(p_th=0.35, memory_shrink_mps=float("inf"), spread=False),
     FilterParams(p_th=0.6, clustering="radius")],
    ids=["improved", "paper"],
)  # fmt: skip
def test_saved_parameters_load_back_equal(tmp_path, suffix, params):
    path = tmp_path / f"params{suffix}"
    save_params(path, params, {"objective": "auc", "houses": ["random:3"], "auc": 0.9})
    assert load_params(path) == params


def test_a_file_may_hold_some_parameters_only(tmp_path):
    path = tmp_path / "robot.toml"
    path.write_text('filter = "improved"\n[improved]\nlidar_height_m = 0.3\nmin_points = 8.0\n')
    assert load_params(path) == ImprovedParams(lidar_height_m=0.3, min_points=8)


@pytest.mark.parametrize(
    ("table", "message"),
    [
        ({"filter": "kalman"}, "filter: must be one of .*improved, .*paper"),
        ({"filter": "improved", "improved": {"bogus": 1}}, r"improved.bogus: unknown parameter"),
        ({"filter": "improved", "improved": {"p_th": 2.0}}, r"improved.p_th: must be <= 1"),
        ({"filter": "improved", "improved": 3}, "improved: must be a table"),
        ({}, "empty: a parameter file names its filter"),
        ({"improved": {"p_th": 0.5}}, "filter: missing"),
        ({"filter": "paper", "improved": {"p_th": 0.5}}, "improved: does not belong"),
        ({"filter": "improved", "p_th": 0.5}, "p_th: does not belong"),
        ({"filter": "improved", "name": "hard_stop", "commands": []}, "name: does not belong"),
    ],
)
def test_mistakes_name_the_file_and_the_key(table, message):
    with pytest.raises(ValueError, match=f"robot.toml: {message}"):
        params_from_table(table, "robot.toml")


def test_a_broken_file_is_named(tmp_path):
    path = tmp_path / "broken.json"
    path.write_text("{not json")
    with pytest.raises(ValueError, match=r"broken\.json: not a valid parameter file"):
        load_params(path)


def test_filter_for_builds_the_filter_the_parameters_are_for():
    assert isinstance(filter_for(ImprovedParams()), ImprovedPitchVariationFilter)
    assert filter_for(FilterParams()).params == FilterParams()


@pytest.fixture
def scan_file(tmp_path):
    path = tmp_path / "scans.npz"
    np.savez(path, **arrays_from_scans(room_sequence(40).scans))
    return path


def test_pvfilter_params_runs_the_file_s_filter(scan_file, tmp_path, capsys):
    params = ImprovedParams(p_th=0.4)
    save_params(tmp_path / "tuned.toml", params)
    out = tmp_path / "out.npz"
    assert main([str(scan_file), str(out), "--params", str(tmp_path / "tuned.toml")]) == 0
    pvf = ImprovedPitchVariationFilter(params)
    expected = np.array([pvf.process(s).removed for s in load_scans(scan_file)])
    with np.load(out) as data:
        np.testing.assert_array_equal(data["removed"], expected)
    assert "removed" in capsys.readouterr().out


def test_pvfilter_improved_takes_p_th_and_rejects_the_paper_s_symbols(scan_file, tmp_path, capsys):
    out = tmp_path / "o.npz"
    assert main([str(scan_file), str(out), "--improved", "--p-th", "1.0"]) == 0
    with np.load(out) as data:
        assert not data["removed"].any()  # no score exceeds 1
    assert main([str(scan_file), str(out), "--improved", "--d-th", "0.5"]) == 2
    assert "--d-th: filter 'improved' has no parameter d_th" in capsys.readouterr().err
    assert main([str(scan_file), str(out), "--improved", "--set", "pth=0.3"]) == 2
    assert "--set pth=0.3: filter 'improved' has no parameter pth" in capsys.readouterr().err
    assert main([str(scan_file), str(out), "--improved", "--detection-only"]) == 2
    assert "--detection-only: filter 'improved' has no parameter tracking" in (
        capsys.readouterr().err
    )
