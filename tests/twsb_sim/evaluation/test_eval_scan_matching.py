"""Events from ground truth, the true relative pose, and alignments under every condition."""

from __future__ import annotations

import numpy as np
import pytest

from pvfilter.synthetic import cross_line, room_segments
from scaneval.geometry import invert, transform_points
from twsb_sim.evaluation.scan_matching import (
    CONDITIONS,
    align,
    pitch_variation_runs,
    summarize,
    true_relative_pose,
)

ROOM = room_segments(4.0, 3.0, 2.0, 2.5)


def test_an_event_is_the_first_frame_of_a_run_with_its_peak(make_frame):
    floor = {2: 0.6, 3: 1.2, 4: 0.3, 7: 0.5}  # frame -> half width of a floor line
    frames = [
        make_frame(k, ROOM, cross_line(1.0, floor[k]) if k in floor else None) for k in range(9)
    ]
    assert pitch_variation_runs(frames) == [(2, 3), (7, 7)]


def test_a_run_from_the_first_frame_has_no_frame_before_it(make_frame):
    frames = [make_frame(k, ROOM, cross_line(1.0, 0.6) if k < 2 else None) for k in range(4)]
    assert pitch_variation_runs(frames) == []


def test_the_true_relative_pose_puts_the_source_sensor_in_the_target_frame(make_frame):
    target = make_frame(0, ROOM, pose=(1.0, 2.0, np.pi / 2))
    source = make_frame(1, ROOM, pose=(1.0, 2.5, np.pi / 2 + 0.1))
    assert true_relative_pose(target, source) == pytest.approx([0.5, 0.0, 0.1], abs=1e-12)


def test_every_matcher_and_condition_aligns_a_known_motion(make_frame):
    # the sensor moves and turns a little; the source sees a floor line the target does not
    motion = (0.05, 0.03, 0.03)
    seen = np.stack([transform_points(ROOM[:, end], invert(motion)) for end in (0, 1)], axis=1)
    target = make_frame(0, ROOM, pose=(0.0, 0.0, 0.0))
    source = make_frame(1, seen, cross_line(1.0, 0.8), pose=motion)
    removed = np.zeros((2, len(source.scan)), dtype=bool)
    rows = align([target, source], removed, "onset", 1, 0, ("icp", "ndt", "hsm"))
    assert {(a.matcher, a.condition) for a in rows} == {
        (m, c) for m in ("icp", "ndt", "hsm") for c in CONDITIONS
    }
    for a in rows:
        assert a.pv_beams > 0
        assert a.removed_pv_beams == (a.pv_beams if a.condition == "oracle" else 0)
        if a.condition == "oracle":  # nothing but the room: every matcher finds the motion
            assert a.translation_error_m < 0.02, a
            assert a.rotation_error_rad < 0.005, a
            assert a.chamfer_m2 == pytest.approx(a.chamfer_at_truth_m2, rel=0.02)
    summary = summarize(rows, ("icp", "ndt", "hsm"))
    for per in summary.values():
        assert per["normalized_mean_chamfer"]["without"] == 1.0
        assert per["chamfer_reduction_pct"] == pytest.approx(0.0)  # the filter removed nothing
        assert per["oracle"]["pv_beams_removed_share"] == 1.0
