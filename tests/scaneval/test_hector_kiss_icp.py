"""KISS-ICP, the established system the Hector-style SLAM is compared with, on 2D scans."""

import sys

import numpy as np
import pytest

from scaneval.slam import KissIcp2D, score_trajectory
from scaneval.slam.kiss import INSTALL_HINT
from scaneval.synthetic import cluttered_room, scan_from_pose


def test_tracks_a_sensor_moving_through_the_room():
    pytest.importorskip("kiss_icp")
    room = cluttered_room()
    truth = np.column_stack(
        (np.linspace(-1.0, 2.0, 60), np.linspace(-0.5, 0.0, 60), np.linspace(0.0, 0.6, 60))
    )
    rng = np.random.default_rng(4)
    kiss = KissIcp2D(max_range_m=12.0)
    estimate = np.array([kiss.process_scan(scan_from_pose(room, p, rng=rng)) for p in truth])
    score = score_trajectory(estimate, truth)
    assert not score.failed, score.failure
    assert score.rmse_m < 0.05
    assert kiss.max_out_of_plane_m < 1e-3 and not kiss.lost


def test_empty_scans_keep_the_pose():
    pytest.importorskip("kiss_icp")
    kiss = KissIcp2D()
    for points in (np.zeros((0, 2)), np.full((10, 2), np.nan)):
        np.testing.assert_array_equal(kiss.process(points), np.zeros(3))


def test_without_the_package_the_error_says_how_to_install_it(monkeypatch):
    monkeypatch.setitem(sys.modules, "kiss_icp", None)
    monkeypatch.setitem(sys.modules, "kiss_icp.config", None)
    with pytest.raises(ImportError, match="twsb-pvfilter\\[slam\\]"):
        KissIcp2D()
    assert "kiss-icp" in INSTALL_HINT
