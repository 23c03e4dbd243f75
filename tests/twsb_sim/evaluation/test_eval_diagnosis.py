"""The miss diagnosis names the stage that lost a constructed miss, and what a false alarm hit."""

from __future__ import annotations

import numpy as np
import pytest

from pvfilter import (
    FilterParams,
    ImprovedParams,
    ImprovedPitchVariationFilter,
    PitchVariationFilter,
)
from pvfilter.synthetic import cross_line, room_segments
from twsb_sim.evaluation.diagnosis import (
    MISS_STAGES,
    NOT_MISSED,
    Queue,
    attribute_misses,
    describe_false_alarms,
    diagnose_run,
    surface_kind,
)
from twsb_sim.labels import is_pitch_variation

PARAMS = FilterParams()
ROOM = room_segments(4.0, 4.0, 2.0, 2.0)
GEOM_NAMES = ("wall_0", "floor", "door_frame_3_left", "table_2_top")


def stages_of_floor(frame, stages) -> set[str]:
    """The stages charged to the frame's pitch-variation beams."""
    pv = is_pitch_variation(frame.labels)
    assert (stages[pv] != NOT_MISSED).all(), "every floor beam is a miss here"
    return {list(MISS_STAGES)[s] for s in stages[pv]}


def first_result(frame):
    """The filter's result for a sequence's first frame: nothing can be detected."""
    return PitchVariationFilter(PARAMS).process(frame.scan)


def second_result(frame):
    """The filter's result for the second of two identical frames (P(L) = 1)."""
    f = PitchVariationFilter(PARAMS)
    f.process(frame.scan)
    return f.process(frame.scan)


def pv_track_at(x: float, y: float, size: int) -> Queue:
    """A previous queue holding one mostly pitch-variation cluster."""
    return Queue(np.array([[x, y]]), np.array([size]), np.array([True]))


def test_a_floor_line_in_the_first_frame_is_lost_by_the_score(make_frame):
    frame = make_frame(0, ROOM, cross_line(1.0, 0.6))
    stages = attribute_misses(frame, first_result(frame), Queue(), PARAMS)
    assert stages_of_floor(frame, stages) == {"score"}
    assert (stages[~is_pitch_variation(frame.labels)] == NOT_MISSED).all()


def test_a_floor_line_of_few_beams_is_never_clustered(make_frame):
    frame = make_frame(0, ROOM, cross_line(1.0, 0.03))  # ~4 beams < m_th
    stages = attribute_misses(frame, first_result(frame), Queue(), PARAMS)
    assert stages_of_floor(frame, stages) == {"small"}


def test_a_floor_line_along_the_direction_of_travel_fails_the_v_c_gate(make_frame):
    along = np.array([[[0.8, 0.6], [1.8, 0.6]]])
    frame = make_frame(0, ROOM, along)
    stages = attribute_misses(frame, first_result(frame), Queue(), PARAMS)
    assert stages_of_floor(frame, stages) == {"v_c"}


def test_a_floor_line_joined_to_the_walls_is_merged_into_structure(make_frame):
    frame = make_frame(0, ROOM, cross_line(1.5, 2.0))  # meets both side walls
    stages = attribute_misses(frame, first_result(frame), Queue(), PARAMS)
    assert stages_of_floor(frame, stages) == {"merged"}


@pytest.mark.parametrize(
    ("floor_x", "track", "stage"),
    [
        (1.0, pv_track_at(4.0, 3.0, 70), "track_distance"),
        (2.5, pv_track_at(2.4, 0.0, 70), "track_band"),
        (1.0, pv_track_at(1.1, 0.0, 1000), "track_size"),
        (1.0, pv_track_at(1.1, 0.0, 90), "unexplained"),  # passes every check
    ],
)
def test_a_tracked_floor_line_is_lost_by_the_first_failing_tracking_check(
    make_frame, floor_x, track, stage
):
    frame = make_frame(1, ROOM, cross_line(floor_x, 0.6))
    result = second_result(frame)
    assert not result.removed.any()
    stages = attribute_misses(frame, result, track, PARAMS)
    assert stages_of_floor(frame, stages) == {stage}


def test_without_a_pitch_variation_track_a_miss_is_the_detections(make_frame):
    frame = make_frame(1, ROOM, cross_line(1.0, 0.6))
    structure_only = Queue(np.array([[1.1, 0.0]]), np.array([70]), np.array([False]))
    stages = attribute_misses(frame, second_result(frame), structure_only, PARAMS)
    assert stages_of_floor(frame, stages) == {"score"}


def test_a_door_frame_seen_for_the_first_time_is_named_as_the_false_alarm(make_frame):
    before = make_frame(0, ROOM, structure_geom=0)
    # a wall piece (door frame) appears 1 m ahead, in front of the far wall
    after = make_frame(1, np.concatenate((ROOM, cross_line(1.0, 0.6))), structure_geom=2)
    f = PitchVariationFilter(PARAMS)
    f.process(before.scan)
    result = f.process(after.scan)
    assert result.removed.any(), "the new piece is detected"
    described = describe_false_alarms(after, before, result, GEOM_NAMES)
    assert set(described) == {("door frame", "first seen", "detected")}
    assert sum(described.values()) == int(result.removed.sum())
    again = describe_false_alarms(after, after, result, GEOM_NAMES)
    assert set(again) == {("door frame", "seen before", "detected")}


def test_a_new_return_removed_outside_every_cluster_is_named_so(make_frame):
    # the improved filter at a p_th below its new_return_score removes every new return:
    # here a door frame's side along the travel, which no line takes in (not across)
    before = make_frame(0, ROOM, structure_geom=0)
    side = np.array([[[0.8, 1.0], [1.6, 1.0]]])  # m: 1 m to the left, along the travel
    after = make_frame(1, np.concatenate((ROOM, side)), structure_geom=2)
    f = ImprovedPitchVariationFilter(ImprovedParams(p_th=0.005))
    f.process(before.scan)
    result = f.process(after.scan)
    assert result.removed.sum() >= 10
    assert not result.cluster_view().detected.any()
    described = describe_false_alarms(after, before, result, GEOM_NAMES)
    assert set(described) == {("door frame", "first seen", "new return")}
    assert sum(described.values()) == int(result.removed.sum())


def test_a_run_diagnosis_adds_up_the_frames_and_keeps_examples(make_frame):
    frames = (
        make_frame(0, ROOM, cross_line(1.0, 0.6)),
        make_frame(1, ROOM, cross_line(1.0, 0.6)),
        make_frame(2, np.concatenate((ROOM, cross_line(1.0, 0.6))), structure_geom=2),
    )
    f = PitchVariationFilter(PARAMS)
    results = tuple(f.process(frame.scan) for frame in frames)
    diagnosis = diagnose_run(frames, results, PARAMS, GEOM_NAMES, "synthetic")
    floor_beams = sum(int(is_pitch_variation(fr.labels).sum()) for fr in frames[:2])
    assert sum(diagnosis.misses.values()) == floor_beams
    assert "score" in diagnosis.examples
    assert diagnosis.examples["score"][1].run_id == "synthetic"
    assert diagnosis.scores, "the floor line's scores are kept"


@pytest.mark.parametrize(
    ("name", "kind"),
    [("wall_12", "wall"), ("door_frame_0_header", "door frame"),
     ("table_2_top", "furniture (table)"), ("", "other")],
)  # fmt: skip
def test_surface_kinds_follow_the_geom_names(name, kind):
    assert surface_kind(name) == kind
