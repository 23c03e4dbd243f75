"""One registry of filters: every filter by name, a user's own registered from Python."""

from __future__ import annotations

import dataclasses
from importlib import metadata

import numpy as np
import pytest

from pvfilter import (
    FilterEntry,
    FilterResult,
    ImprovedParams,
    ImprovedPitchVariationFilter,
    PitchVariationFilter,
    Scan,
    ScanFilter,
    filter_entry,
    filter_for,
    filter_names,
    load_params,
    make_filter,
    register_filter,
)
from pvfilter.cli import main as pvfilter_main
from pvfilter.io import arrays_from_scans
from pvfilter.registry import ENTRY_POINT_GROUP, unregister_filter
from pvfilter.synthetic import room_sequence


@dataclasses.dataclass(frozen=True)
class FarParams:
    """Parameters of a user's own filter."""

    beyond_m: float = 3.0


class FarFilter:
    """A user's filter: removes every return beyond ``beyond_m``."""

    def __init__(self, params: FarParams | None = None) -> None:
        self.params = params or FarParams()

    def process(self, scan: Scan, *, pitch_rad=None, roll_rad=None, pose_sensor_in_odom=None):
        removed = scan.valid_mask() & (scan.ranges > self.params.beyond_m)
        return FilterResult(scan.with_ranges(np.where(removed, np.nan, scan.ranges)), removed,
                            removed.astype(float))  # fmt: skip

    def reset(self) -> None:
        pass


@pytest.fixture
def far_filter():
    register_filter(FilterEntry("far", FarFilter, FarParams, "returns beyond a range"))
    yield
    unregister_filter("far")


def test_both_filters_and_the_baselines_are_registered():
    # the evaluation baselines come with the simulator's distribution (its entry points);
    # a robot install of pvfilter alone has its own three filters
    declared = {point.name for point in metadata.entry_points(group=ENTRY_POINT_GROUP)}
    assert {"paper", "improved", "none"} | declared <= set(filter_names())
    if "twsb-pvfilter" in {d.metadata["Name"] for d in metadata.distributions()}:
        assert {"datmo", "imu_gate"} <= declared, "the root distribution declares the baselines"
    assert isinstance(make_filter("paper"), PitchVariationFilter)
    assert isinstance(make_filter("improved"), ImprovedPitchVariationFilter)
    for name in filter_names():
        assert isinstance(make_filter(name), ScanFilter), name


def test_fields_and_robot_geometry_reach_the_parameters():
    improved = make_filter("improved", p_th=0.3, robot_geometry={"lidar_height_m": 0.4})
    assert improved.params == ImprovedParams(p_th=0.3, lidar_height_m=0.4)
    paper = make_filter("paper", robot_geometry={"lidar_height_m": 0.4})  # no such field
    assert paper.params.p_th == 0.8
    with pytest.raises(ValueError, match="paper: unknown parameter 'lidar_height'"):
        make_filter("paper", lidar_height=0.4)
    with pytest.raises(ValueError, match="improved: expects ImprovedParams, got FilterParams"):
        make_filter("improved", make_filter("paper").params)


def test_unknown_names_and_taken_names_are_refused():
    with pytest.raises(ValueError, match=r"unknown filter 'kalman' .*known: .*improved"):
        make_filter("kalman")
    with pytest.raises(ValueError, match="already registered"):
        register_filter(filter_entry("paper"))
    with pytest.raises(ValueError, match="name: must be a word"):
        register_filter(FilterEntry("two words", FarFilter))


def test_a_user_filter_is_known_everywhere(far_filter, tmp_path, capsys):
    assert "far" in filter_names()
    assert isinstance(make_filter("far", beyond_m=2.0), FarFilter)
    # parameter files name it
    path = tmp_path / "far.toml"
    path.write_text('filter = "far"\n[far]\nbeyond_m = 2.5\n')
    assert load_params(path) == FarParams(2.5)
    assert isinstance(filter_for(FarParams()), FarFilter)
    # the pvfilter command runs it
    scans = room_sequence(5).scans
    source, out = tmp_path / "scans.npz", tmp_path / "out.npz"
    np.savez(source, **arrays_from_scans(scans))
    assert pvfilter_main([str(source), str(out), "--filter", "far", "--set", "beyond_m=2.0"]) == 0
    with np.load(out) as data:
        expected = [s.valid_mask() & (s.ranges > 2.0) for s in scans]
        np.testing.assert_array_equal(data["removed"], expected)
    assert "far filter, 5 scans" in capsys.readouterr().out


def test_a_misspelled_robot_geometry_key_is_refused_not_dropped():
    with pytest.raises(ValueError, match="robot_geometry: unknown key 'lidar_height'"):
        make_filter("improved", robot_geometry={"lidar_height": 0.3})
    with pytest.raises(ValueError, match="robot_geometry: unknown key"):
        make_filter("paper", robot_geometry={"lidar_height": 0.3})  # whatever the filter
    # a geometry field the filter does not take is ignored, as before
    assert make_filter("paper", robot_geometry={"lidar_height_m": 0.3}) is not None
    improved = make_filter("improved", robot_geometry={"lidar_height_m": 0.3})
    assert improved.params.lidar_height_m == 0.3
