"""The level view's doubt along what the scan matches could not see."""

import math

import numpy as np
import pytest

from pvfilter.improved import BeamLayout
from pvfilter.improved.doubt import WEAK_ROWS, ViewDoubt
from pvfilter.improved.egomotion import MAX_SPEED_MPS, SEEN
from pvfilter.improved.widestep import prior_doubt_m

from .conftest import room_scan

SCAN = room_scan()[0]
LAYOUT = BeamLayout.of(SCAN)
AHEAD = int(np.argmin(np.abs(SCAN.angles())))
LEFT = int(np.argmin(np.abs(SCAN.angles() - math.pi / 2)))
NO_VIEW = np.full(len(SCAN), np.nan)  # no surface known: taken across each beam
BLIND_ALONG_X = (WEAK_ROWS - 1.0, 0.0)  # a fit on walls along x only


def doubt_after(steps, dt=0.2, weak=BLIND_ALONG_X):
    doubt = ViewDoubt()
    for _ in range(steps):
        doubt.carry(0.0, weak, dt)
        doubt.settle(True, 0.0)
    return doubt


def test_weak_steps_of_an_event_add_their_prior_doubt_along_the_weak_axis_as_distances():
    # four 5 Hz steps of a pitch event blind along x: the constant-velocity prior errs the
    # same way each step (its velocity is the last weak step's), 10 cm a step
    doubt = doubt_after(4)
    along = doubt.along_beams(LAYOUT, NO_VIEW)
    assert along[AHEAD] == pytest.approx(4.0 * prior_doubt_m(0.2))
    assert along[LEFT] == pytest.approx(0.0, abs=1e-3)  # across the walls seen: none
    doubt.carry(0.0, SEEN, 0.2)  # a step that saw the drive (or the wheels) adds nothing
    assert doubt.along_beams(LAYOUT, NO_VIEW)[AHEAD] == pytest.approx(along[AHEAD])
    assert ViewDoubt().along_beams(LAYOUT, NO_VIEW) is None
    # a NaN direction adds nothing
    assert doubt_after(3, weak=(0.0, math.nan)).along_beams(LAYOUT, NO_VIEW) is None


def test_a_step_between_level_scans_adds_no_doubt_and_the_doubt_shrinks_as_the_view_catches_up():
    doubt = doubt_after(2)  # 0.2 m along x
    doubt.carry(0.0, BLIND_ALONG_X, 0.2)
    assert doubt.along_beams(LAYOUT, NO_VIEW)[AHEAD] == pytest.approx(0.3)  # this scan
    doubt.settle(False, 0.05)  # a level scan after a level one: the view was renewed
    assert doubt.along_beams(LAYOUT, NO_VIEW)[AHEAD] == pytest.approx(0.15)
    for _ in range(3):
        doubt.settle(False, 0.05)
    assert doubt.along_beams(LAYOUT, NO_VIEW) is None
    doubt = doubt_after(2)
    doubt.reset()
    assert doubt.along_beams(LAYOUT, NO_VIEW) is None


def test_the_doubt_turns_with_the_sensor():
    # doubt along x; the sensor turns 45 deg left: the old x axis now points 45 deg to
    # the right of the new one (a static point at q is at R(theta) q in the new frame,
    # theta = -45 deg for a left turn), so the beam at -45 deg carries all of it
    doubt = doubt_after(1, dt=0.1)
    doubt.carry(-math.pi / 4, SEEN, 0.1)
    right = int(np.argmin(np.abs(SCAN.angles() + math.pi / 4)))
    left = int(np.argmin(np.abs(SCAN.angles() - math.pi / 4)))
    along = doubt.along_beams(LAYOUT, NO_VIEW)
    assert along[right] == pytest.approx(prior_doubt_m(0.1), rel=1e-3)
    assert along[left] == pytest.approx(0.0, abs=1e-3)
    xx, xy, yy = doubt.grown
    assert xy < 0.0 and xx == pytest.approx(yy)


def test_surfaces_facing_the_doubt_confirm_the_view_and_others_do_not():
    doubt = doubt_after(2)  # along x
    on_view = np.zeros(len(SCAN), bool)
    on_view[AHEAD - 15 : AHEAD + 15] = True  # 30 returns on the view ahead
    across_x = np.full(len(SCAN), math.pi / 2)  # a wall across x: it shows where x lies
    along_x = np.zeros(len(SCAN))  # walls along x: they do not
    assert doubt.confirmed(on_view, across_x)
    assert not doubt.confirmed(on_view, along_x)
    assert not doubt.confirmed(on_view, np.full(len(SCAN), np.nan))
    on_view[AHEAD - 15 : AHEAD + 6] = False  # 9 left: too few
    assert not doubt.confirmed(on_view, across_x)


def test_a_step_longer_than_the_robot_can_brake_through_is_bounded_by_its_top_speed():
    doubt = ViewDoubt()
    doubt.carry(0.0, BLIND_ALONG_X, 2.2)  # a match resumed after a long coast
    along = doubt.along_beams(LAYOUT, NO_VIEW)[AHEAD]
    assert along == pytest.approx(min(prior_doubt_m(2.2), MAX_SPEED_MPS * 2.2))
    assert along < prior_doubt_m(2.2)


def line_view(normal_deg, distance_m=3.0):
    """The ranges of a view that holds one wall, its normal ``normal_deg`` off x."""
    off = np.cos(SCAN.angles() - math.radians(normal_deg))
    return np.where(off > 0.1, distance_m / np.where(off > 0.1, off, 1.0), np.nan)


def test_an_oblique_surface_moves_along_its_beam_by_the_shift_over_the_incidence():
    # the view off along x: a wall across x moves by the shift along its normal, and
    # along a beam 45 deg off it by the shift / cos 45 (the beam's own direction would
    # give shift * cos 45); a wall along x does not move; one seen at a grazing angle (80
    # deg), whose neighbouring points lie as far apart as across a jump, is taken across
    # the beam
    doubt = doubt_after(1)
    shift_m = prior_doubt_m(0.2)
    beam = int(np.argmin(np.abs(SCAN.angles() - math.pi / 4)))
    along = doubt.along_beams(LAYOUT, line_view(0.0))
    assert along[beam] == pytest.approx(shift_m / math.cos(math.pi / 4), rel=1e-3)
    assert along[AHEAD] == pytest.approx(shift_m, rel=1e-3)
    no_view = doubt.along_beams(LAYOUT, NO_VIEW)
    assert no_view[beam] == pytest.approx(shift_m * math.cos(math.pi / 4), rel=1e-3)
    assert doubt.along_beams(LAYOUT, line_view(90.0))[LEFT] == pytest.approx(0.0, abs=1e-3)
    assert doubt.along_beams(LAYOUT, line_view(80.0))[AHEAD] == pytest.approx(shift_m)


def test_a_view_that_comes_closer_at_once_keeps_no_doubt():
    # line_shrink_mps unbounded: after a level scan nothing is left, nor is it NaN
    for creep_m in (math.inf, math.nan):
        doubt = doubt_after(3)
        doubt.settle(False, creep_m)
        assert doubt.doubt == (0.0, 0.0, 0.0)
