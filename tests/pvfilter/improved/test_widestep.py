"""The wide-step match: a drive longer than the beam pairs reach, searched along x."""

import math

import numpy as np
import pytest

from pvfilter.improved import ImprovedParams, Motion
from pvfilter.improved.motion import STILL, estimate_motion
from pvfilter.improved.widestep import prior_doubt_m, wide_step
from pvfilter.synthetic import room_segments

from .conftest import prepared, tilted_scan

PARAMS = ImprovedParams()
# a corridor 10 m long and 2.4 m wide, with two door jambs: its long walls fit any drive
# along it, its ends and the jambs tell the drive
CORRIDOR = np.concatenate(
    (
        room_segments(5.0, 5.0, 1.2, 1.2),
        np.array([[[1.5, 1.2], [1.5, 0.9]], [[-2.0, -1.2], [-2.0, -0.9]]]),
    )
)


def seen(pose, walls=CORRIDOR):
    """Beams, points, ranges and line directions of a level scan from ``pose``."""
    layout, points, directions = prepared(tilted_scan(pose=pose, walls=walls)[0])
    return layout, points, np.hypot(points[:, 0], points[:, 1]), directions


def test_the_prior_may_be_off_by_half_the_hardest_acceleration_times_the_gap_squared():
    assert prior_doubt_m(0.1) < 0.03 < PARAMS.association_m  # 10 Hz: the pairs reach it
    assert prior_doubt_m(0.5) == pytest.approx(0.625)  # 2 Hz: they do not


def test_a_drive_beyond_the_pairs_reach_is_found_by_the_search():
    # 0.8 m driven and 6 deg turned between two scans; the prior says standing still
    layout, reference, _, _ = seen((0.0, 0.0, 0.0))
    _, points, ranges, directions = seen((0.8, 0.0, math.radians(6.0)))
    truth = Motion(math.radians(6.0), 0.8, 0.0).inverse()  # reference frame -> scan frame
    plain = estimate_motion(
        points, directions, reference, layout, round(math.radians(6.0) / layout.increment),
        PARAMS.association_m, STILL, (0.01, 0.03),
    )  # fmt: skip
    assert abs(plain.tx_m - truth.tx_m) > 0.5  # the long walls alone pair: "standing"
    found = wide_step(
        points, ranges, directions, reference, layout, math.radians(30.0), STILL, 2.0,
        PARAMS.association_m, 0.01, plain,
    )  # fmt: skip
    assert found is not None
    assert found.tx_m == pytest.approx(truth.tx_m, abs=0.02)
    assert found.ty_m == pytest.approx(truth.ty_m, abs=0.02)
    assert found.theta_rad == pytest.approx(truth.theta_rad, abs=math.radians(0.3))
    # the refit's support along its least constrained direction comes with it (without
    # it the step would count as seen in every direction): the corridor's long walls fix
    # y, fewer returns (its ends, the jambs) the drive along x
    assert math.isfinite(found.weak_rows) and found.weak_rows > 0.0
    assert abs(math.sin(found.weak_axis_rad)) < 0.2


def test_a_search_the_scan_does_not_confirm_is_not_taken():
    # the scan of another place pairs with little of the reference: no motion is taken
    layout, reference, _, _ = seen((0.0, 0.0, 0.0))
    _, points, ranges, directions = seen((0.0, 0.0, 0.0), room_segments(2.0, 1.0, 3.0, 0.5))
    found = wide_step(
        points, ranges, directions, reference, layout, math.radians(30.0), STILL, 2.0,
        PARAMS.association_m, 0.01, STILL,
    )  # fmt: skip
    assert found is None
