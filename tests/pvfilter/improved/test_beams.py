"""BeamLayout: which scans share a layout (a jittering angle_min does; another scanner not)."""

import dataclasses
import math
import subprocess
import sys

import numpy as np
import pytest

from pvfilter import Scan
from pvfilter.improved.beams import FIT_TOLERANCE_BEAMS, BeamLayout, row_norms

BEAMS = 720
INCREMENT = 2.0 * math.pi / BEAMS


def ring_scan(angle_min=-math.pi, increment=INCREMENT, beams=BEAMS):
    return Scan(ranges=np.ones(beams), angle_min=angle_min, angle_increment=increment,
                range_min=0.05, range_max=12.0)  # fmt: skip


@pytest.mark.parametrize(("shift_beams", "fits"), [(0.0, True), (0.5, True), (-1.9, True),
                                                   (FIT_TOLERANCE_BEAMS + 0.1, False)])  # fmt: skip
def test_a_scan_whose_angle_min_moved_within_the_tolerance_keeps_the_layout(shift_beams, fits):
    layout = BeamLayout.of(ring_scan())
    assert layout.fits(ring_scan(-math.pi + shift_beams * INCREMENT)) == fits


def test_a_full_turn_that_starts_across_the_seam_keeps_the_layout():
    # a driver that takes angle_min from each turn's first sample, near -pi and near +pi
    layout = BeamLayout.of(ring_scan(-math.pi + 0.3 * INCREMENT))
    assert layout.fits(ring_scan(math.pi - 0.3 * INCREMENT))
    part = Scan(ranges=np.ones(480), angle_min=-2.0, angle_increment=INCREMENT,
                range_min=0.05, range_max=12.0)  # fmt: skip
    moved = dataclasses.replace(part, angle_min=-2.0 + 2.0 * math.pi)
    assert not BeamLayout.of(part).fits(moved)  # not a full turn: those are other beams


def test_an_increment_that_moves_the_last_beam_beyond_the_tolerance_is_another_layout():
    layout = BeamLayout.of(ring_scan())
    within = INCREMENT * (1.0 + 1.5 / (BEAMS - 1))  # the last beam 1.5 beams on
    beyond = INCREMENT * (1.0 + 2.5 / (BEAMS - 1))
    assert layout.fits(ring_scan(increment=within))
    assert not layout.fits(ring_scan(increment=beyond))
    assert not layout.fits(ring_scan(beams=BEAMS - 1))


def test_row_norms_are_the_exact_distances_within_two_ulps():
    rng = np.random.default_rng(3)
    points = rng.normal(scale=5.0, size=(2000, 2))
    points[::7] *= 1e-3  # near the sensor too
    exact = np.array([math.hypot(x, y) for x, y in points.tolist()])  # correctly rounded
    norms = row_norms(points)
    assert norms.shape == (2000,)
    assert np.all(np.abs(norms - exact) <= 2.0 * np.spacing(exact))


def test_row_norms_take_any_array_of_points_and_keep_missing_points_missing():
    points = np.array([[3.0, 4.0], [np.nan, np.nan], [np.inf, 0.0], [0.0, -2.0]])
    expected = [5.0, np.nan, np.inf, 2.0]
    np.testing.assert_array_equal(row_norms(points), expected)
    np.testing.assert_array_equal(row_norms(np.asfortranarray(points)), expected)  # not C-ordered
    np.testing.assert_array_equal(row_norms(points[::-1]), expected[::-1])  # a view
    np.testing.assert_array_equal(row_norms(points.astype(np.float32)), expected)
    assert row_norms(np.zeros((0, 2))).shape == (0,)


def partial_scan(beams=240):
    return Scan(ranges=np.ones(beams), angle_min=-math.pi / 3, angle_increment=INCREMENT,
                range_min=0.05, range_max=12.0)  # fmt: skip


def test_beam_at_wraps_on_a_ring_and_is_minus_one_outside_a_partial_field_of_view():
    ring, partial = BeamLayout.of(ring_scan()), BeamLayout.of(partial_scan())
    angles = np.array([-math.pi, -math.pi + 1.4 * INCREMENT, math.pi - 0.4 * INCREMENT, 0.0])
    x, y = np.cos(angles), np.sin(angles)
    expected_ring = [0, 1, 0, BEAMS // 2]  # the last beam's neighbour across the seam is 0
    np.testing.assert_array_equal(ring.beam_at(x, y), expected_ring)
    np.testing.assert_array_equal(ring.beam_at(x, y, finite=True), expected_ring)
    np.testing.assert_array_equal(partial.beam_at(x, y), [-1, -1, -1, 120])


def test_beam_at_answers_at_once_for_points_that_are_not_finite():
    # numpy's wrapping gather steps a NaN's index (the smallest integer) back one turn at a
    # time: run in a child process, so that a regression fails instead of hanging the suite
    code = (
        "import math, numpy as np\n"
        "from pvfilter import Scan\n"
        "from pvfilter.improved.beams import BeamLayout\n"
        "ring = BeamLayout.of(Scan(ranges=np.ones(8), angle_min=-math.pi,"
        " angle_increment=math.pi / 4, range_min=0.05, range_max=12.0))\n"
        "beams = ring.beam_at(np.array([np.nan, np.inf, 1.0]), np.array([1.0, np.nan, 0.0]))\n"
        "assert beams.shape == (3,) and ((beams >= 0) & (beams < 8)).all() and beams[2] == 4\n"
    )
    subprocess.run([sys.executable, "-W", "ignore", "-c", code], check=True, timeout=30)
    partial = BeamLayout.of(partial_scan())
    with np.errstate(invalid="ignore"):  # (a NaN's index is no integer: numpy says so)
        beams = partial.beam_at(np.array([np.nan, np.inf]), np.array([0.0, np.nan]))
    np.testing.assert_array_equal(beams, [-1, -1])
