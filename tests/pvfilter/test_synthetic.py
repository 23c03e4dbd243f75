"""Synthetic scans: the ray caster against hand-computed ranges."""

import math

import numpy as np

from pvfilter.synthetic import BLOCKED_SECTOR, cross_line, ray_cast, room_sequence, segment_scan


def test_ray_cast_hits_the_nearest_segment_along_each_beam():
    segments = np.concatenate((cross_line(2.0, 5.0), cross_line(1.0, 0.1)))
    angles = np.array([0.0, math.pi / 4, math.pi, math.pi / 2])
    # the short line at 1 m ahead; 45 degrees misses it and meets x = 2 at 2 sqrt(2) m;
    # behind and to the left there is nothing
    expected = [1.0, 2.0 * math.sqrt(2.0), np.inf, np.inf]
    np.testing.assert_allclose(ray_cast(segments, angles), expected)


def test_segment_scan_is_a_full_turn_from_minus_pi_with_a_blocked_sector():
    scan = segment_scan(cross_line(1.0, 0.5), blocked=BLOCKED_SECTOR)
    assert len(scan) == 720 and scan.angle_min == -math.pi
    assert scan.angles()[360] == 0.0 and scan.ranges[360] == 1.0
    blocked = (scan.angles() >= BLOCKED_SECTOR[0]) & (scan.angles() <= BLOCKED_SECTOR[1])
    assert np.isnan(scan.ranges[blocked]).all()
    assert abs(blocked.sum() - 240) <= 1  # 120 degrees at 2 beams per degree


def test_room_sequence_marks_floor_line_beams_in_three_scans_of_twenty():
    sequence = room_sequence(40)
    with_line = [k for k, truth in enumerate(sequence.truth) if truth.any()]
    assert with_line == [10, 11, 12, 30, 31, 32]
    assert [s.stamp for s in sequence.scans[:3]] == [0.0, 0.1, 0.2]
