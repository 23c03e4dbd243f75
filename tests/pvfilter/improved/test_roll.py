"""The scan plane's roll, measured on confident floor lines, widens the lean gates."""

import dataclasses
import math

import numpy as np
import pytest

from pvfilter.improved import ImprovedParams, ImprovedPitchVariationFilter
from pvfilter.improved.geometry import implied_tilt
from pvfilter.improved.roll import (
    ROLL_LINES,
    ROLL_MARGIN_DEG,
    ROLL_MIN_LINES,
    RollBound,
    line_roll_deg,
)
from pvfilter.synthetic import room_segments

from .conftest import HEIGHT_M, tilted_scan

# a scanner that stays at its height as it tilts, as tilted_scan casts it
LEVEL_HEIGHT = ImprovedParams(lidar_height_m=HEIGHT_M, axle_height_m=HEIGHT_M)


@pytest.mark.parametrize("pitch_deg", [-12.0, -4.0, 3.0, 8.0, 20.0])
@pytest.mark.parametrize("roll_deg", [0.0, 1.5, -4.0, 6.0])
def test_the_roll_of_the_plane_is_read_back_from_its_floor_line(pitch_deg, roll_deg):
    # x sin p - y cos p sin r = h: normal (sin p, -cos p sin r) / N, distance h / N
    p, r = math.radians(pitch_deg), math.radians(roll_deg)
    along_x, across_x = math.sin(p), -math.cos(p) * math.sin(r)
    norm = math.hypot(along_x, across_x)
    tilt = float(implied_tilt(np.array([HEIGHT_M / norm]), LEVEL_HEIGHT)[0])
    normal = np.array([along_x, across_x]) / norm
    assert line_roll_deg(normal, tilt) == pytest.approx(abs(roll_deg), abs=1e-9)


def test_the_roll_is_read_back_from_a_floor_line_cast_in_3d():
    scan, hit = tilted_scan(
        pitch_rad=math.radians(10.0), roll_rad=math.radians(4.0), walls=room_segments(6, 6, 3, 3)
    )
    points = scan.points()[hit == 2]
    centroid = points.mean(axis=0)
    normal = np.linalg.svd(points - centroid)[2][1]  # the direction of least spread
    distance = abs(float(centroid @ normal))
    tilt = float(implied_tilt(np.array([distance]), LEVEL_HEIGHT)[0])
    assert line_roll_deg(normal, tilt) == pytest.approx(4.0, abs=0.01)


def lines_at(roll_deg: float, count: int, tilt_deg: float = 10.0):
    """``count`` (normal, tilt) of floor lines of a plane rolled ``roll_deg``."""
    p, r = math.radians(tilt_deg), math.radians(roll_deg)
    normal = np.array([math.sin(p), -math.cos(p) * math.sin(r)])
    norm = float(np.hypot(*normal))
    return [(normal / norm, math.asin(norm))] * count


def test_the_bound_widens_to_the_measured_roll_and_never_narrows():
    params = ImprovedParams()
    bound = RollBound(params)
    for normal, tilt in lines_at(4.0, ROLL_MIN_LINES - 1):
        bound.learn(normal, tilt)
    assert bound.bound_deg == params.max_roll_deg  # too few lines yet
    bound.learn(*lines_at(4.0, 1)[0])
    assert bound.bound_deg == pytest.approx(4.0 + ROLL_MARGIN_DEG)
    level = RollBound(params)
    for normal, tilt in lines_at(0.3, ROLL_LINES):
        level.learn(normal, tilt)
    assert level.bound_deg == params.max_roll_deg  # a level plane keeps the given bound
    bound.reset()
    assert bound.bound_deg == params.max_roll_deg


def test_a_minority_of_walls_taken_for_the_floor_does_not_move_the_bound():
    bound = RollBound(ImprovedParams())
    for normal, tilt in lines_at(4.0, ROLL_LINES // 2 + 1) + lines_at(20.0, ROLL_LINES // 2):
        bound.learn(normal, tilt)
    assert bound.bound_deg == pytest.approx(4.0 + ROLL_MARGIN_DEG)


def test_the_gates_and_the_segmentation_take_the_widened_bound():
    params = ImprovedParams()
    bound = RollBound(params)
    assert bound.applied(params) is params and bound.segmenting(params) is params
    for normal, tilt in lines_at(5.0, ROLL_MIN_LINES):
        bound.learn(normal, tilt)
    assert bound.applied(params).max_roll_deg == pytest.approx(6.0)
    # tan(line angle) grows with sin(roll): the floor line as far out as before passes
    widened = bound.segmenting(params).line_angle_deg
    expected = (
        math.tan(math.radians(40.0)) * math.sin(math.radians(6.0)) / math.sin(math.radians(3.0))
    )
    assert math.tan(math.radians(widened)) == pytest.approx(expected)
    assert bound.segmenting(params).max_roll_deg == params.max_roll_deg


def pitch_at(k: int) -> float:
    """Three pitch events of 11 deg, then one of 4 deg (rad, per scan)."""
    for start, peak_deg in ((10, 11.0), (30, 11.0), (50, 11.0), (70, 4.0)):
        phase = (k - start) / 9
        if 0.0 <= phase <= 1.0:
            return math.radians(peak_deg) * math.sin(math.pi * phase)
    return 0.0


def run_rolled(roll_deg: float, learn_roll: bool, noise_m: float = 0.01):
    """A standing robot whose plane is rolled ``roll_deg``, through the events of
    :func:`pitch_at`, ``noise_m`` of range noise, a rotating sweep: the filter, and per
    scan of the last (shallow) event its floor beams and how many of them and of the rest
    it removed."""
    pvf = ImprovedPitchVariationFilter(dataclasses.replace(LEVEL_HEIGHT, learn_roll=learn_roll))
    rng = np.random.default_rng(0)
    shallow = []
    for k in range(85):
        scan, hit = tilted_scan(
            pitch_rad=pitch_at(k),
            roll_rad=math.radians(roll_deg),
            stamp=0.1 * k,
            walls=room_segments(6, 6, 2.5, 2.5),
        )
        returns = np.isfinite(scan.ranges) & (scan.ranges > 0.0)
        noisy = np.where(returns, scan.ranges + rng.normal(0.0, noise_m, len(scan)), scan.ranges)
        scan = dataclasses.replace(scan.with_ranges(noisy), time_increment=0.1 / len(scan))
        removed = pvf.process(scan).removed
        if k >= 70 and np.count_nonzero(hit == 2):
            floor = hit == 2
            shallow.append((np.count_nonzero(floor), np.count_nonzero(removed & floor),
                            np.count_nonzero(removed & ~floor)))  # fmt: skip
    return pvf, np.array(shallow)


def test_a_rolled_plane_s_shallow_floor_line_is_found_once_its_roll_is_measured():
    # rolled 4 deg, the floor line at 3.9 deg of pitch leans 46 deg from the y axis: past
    # the 40 deg of "across" and the lean a 3 deg roll explains. The 11 deg events' lines
    # lean 20 deg, pass, and tell the roll.
    learned, found = run_rolled(4.0, learn_roll=True)
    assert learned.roll_bound_deg == pytest.approx(4.0 + ROLL_MARGIN_DEG, abs=0.2)
    steepest = found[np.argmax(found[:, 0])]
    assert steepest[1] >= 0.9 * steepest[0]
    assert found[:, 2].max() <= 5
    fixed, missed = run_rolled(4.0, learn_roll=False)
    assert fixed.roll_bound_deg == ImprovedParams().max_roll_deg
    assert missed[:, 1].sum() == 0


def test_a_level_plane_keeps_the_given_bound():
    pvf, _ = run_rolled(0.0, learn_roll=True)
    assert pvf.roll_bound_deg == ImprovedParams().max_roll_deg
    pvf.reset()
    assert pvf.roll_bound_deg == ImprovedParams().max_roll_deg


def test_a_learnt_roll_and_the_measured_noise_widen_the_parameters_together():
    # the lean gates widened to the roll the lines measured, and the line distances to the
    # noise the scans show: each stage's parameters carry both, whichever came last
    pvf, _ = run_rolled(4.0, learn_roll=True, noise_m=0.05)
    assert pvf.roll_bound_deg == pytest.approx(4.0 + ROLL_MARGIN_DEG, abs=0.2)
    assert pvf.range_noise_m == pytest.approx(0.05, rel=0.25)
    widened = ImprovedParams().for_range_noise(pvf.range_noise_m)
    for stage in (pvf._line_params, pvf._segment_params):  # (the lines', the segmentation's)
        assert stage.break_distance_m == widened.break_distance_m > 0.15
        assert stage.extend_tolerance_m == widened.extend_tolerance_m > 0.03
    assert pvf._line_params.max_roll_deg == pvf.roll_bound_deg
    assert pvf._segment_params.line_angle_deg > ImprovedParams().line_angle_deg
