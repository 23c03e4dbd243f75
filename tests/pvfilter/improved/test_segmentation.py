"""Segmentation: a floor line is cut from the wall it runs into; line fits and implied tilt."""

import math

import numpy as np
import pytest

from pvfilter.improved import ImprovedParams, segment_scan
from pvfilter.improved.segmentation import local_directions

from .conftest import HEIGHT_M, room_scan


def segments_of(scan, params=None):
    params = params if params is not None else ImprovedParams()
    beams = np.flatnonzero(scan.valid_mask())
    return segment_scan(scan.points()[beams], beams, params), beams


def test_local_direction_of_a_straight_line_is_its_direction():
    points = np.column_stack((np.linspace(0.0, 2.0, 40), 0.5 * np.linspace(0.0, 2.0, 40)))
    directions = local_directions(points, 4)
    np.testing.assert_allclose(directions, math.atan(0.5), atol=1e-9)


def test_floor_line_and_the_side_walls_it_runs_into_are_different_segments():
    scan, on_floor = room_scan(pitch_rad=math.radians(8.0), noise_m=0.0)
    segments, beams = segments_of(scan)
    floor_labels = set(segments.labels[on_floor[beams]].tolist())
    # one segment holds (nearly) the whole floor line, and at most the corner of the wall
    main = max(floor_labels, key=lambda s: np.count_nonzero(segments.labels == s))
    members = segments.labels == main
    assert np.count_nonzero(on_floor[beams][members]) >= 0.9 * np.count_nonzero(on_floor)
    assert np.count_nonzero(~on_floor[beams][members]) <= 2
    assert segments.across[main]


def test_implied_tilt_of_the_floor_line_is_the_pitch():
    pitch = math.radians(6.0)
    scan, on_floor = room_scan(pitch_rad=pitch, noise_m=0.0)
    segments, beams = segments_of(scan)
    main = np.bincount(segments.labels[on_floor[beams]]).argmax()
    tilt, roll = segments.implied_tilt_roll(HEIGHT_M)
    assert tilt[main] == pytest.approx(pitch, abs=1e-6)
    assert roll[main] == pytest.approx(0.0, abs=1e-6)
    assert segments.distances[main] == pytest.approx(HEIGHT_M / math.sin(pitch), abs=1e-6)


def test_a_rolled_plane_leans_the_line_and_implies_the_roll():
    pitch, roll = math.radians(8.0), math.radians(2.0)
    # floor line of a plane with pitch and roll: x sin p - y cos p sin r = h
    y = np.linspace(-1.0, 1.0, 60)
    x = (HEIGHT_M + y * math.cos(pitch) * math.sin(roll)) / math.sin(pitch)
    points = np.column_stack((x, y))
    segments = segment_scan(points, np.arange(60), ImprovedParams())
    tilt, implied_roll = segments.implied_tilt_roll(HEIGHT_M)
    assert len(segments) == 1
    assert implied_roll[0] == pytest.approx(roll, abs=2e-3)
    assert tilt[0] == pytest.approx(math.hypot(pitch, roll), abs=2e-3)


def test_range_jumps_split_segments():
    points = np.array([[1.0, y] for y in np.linspace(-0.3, 0.3, 10)]
                      + [[3.0, y] for y in np.linspace(0.4, 1.0, 10)])  # fmt: skip
    segments = segment_scan(points, np.arange(20), ImprovedParams())
    assert len(segments) == 2 and segments.sizes.tolist() == [10, 10]


def test_no_points_give_no_segments():
    segments = segment_scan(np.zeros((0, 2)), np.zeros(0, dtype=int), ImprovedParams())
    assert len(segments) == 0
