"""The level view's doubt along what the scan matches could not see."""

import math

import numpy as np
import pytest

from pvfilter.improved import BeamLayout
from pvfilter.improved.doubt import WEAK_ROWS, ViewDoubt
from pvfilter.improved.widestep import prior_doubt_m

from .conftest import room_scan

SCAN = room_scan()[0]
LAYOUT = BeamLayout.of(SCAN)
AHEAD = int(np.argmin(np.abs(SCAN.angles())))
LEFT = int(np.argmin(np.abs(SCAN.angles() - math.pi / 2)))


def test_weak_steps_add_their_prior_doubt_as_variances_along_the_weak_axis():
    doubt = ViewDoubt()
    assert doubt.along_beams(LAYOUT) is None
    for _ in range(4):  # four 5 Hz steps blind along x (the sensor's drive)
        doubt.carry(0.0, (WEAK_ROWS - 1.0, 0.0), 0.2)
    along = doubt.along_beams(LAYOUT)
    assert along[AHEAD] == pytest.approx(2.0 * prior_doubt_m(0.2))  # sqrt(4) x 10 cm
    assert along[LEFT] == pytest.approx(0.0, abs=1e-3)  # across the walls seen: none
    doubt.carry(0.0, (WEAK_ROWS, 0.0), 0.2)  # a step that saw the drive adds nothing
    assert doubt.along_beams(LAYOUT)[AHEAD] == pytest.approx(along[AHEAD])
    doubt.reset()
    assert doubt.along_beams(LAYOUT) is None


def test_the_doubt_turns_with_the_sensor():
    doubt = ViewDoubt()
    doubt.carry(0.0, (0.0, 0.0), 0.1)
    doubt.carry(math.pi / 2, (math.inf, 0.0), 0.1)  # a quarter turn: x is now y
    along = doubt.along_beams(LAYOUT)
    assert along[LEFT] == pytest.approx(prior_doubt_m(0.1))
    assert along[AHEAD] == pytest.approx(0.0, abs=1e-3)
