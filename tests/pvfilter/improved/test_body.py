"""BodyBeams: the silent beams that returned the robot's own body lately."""

import numpy as np

from pvfilter.improved.body import BodyBeams

BODY = np.array([True, False, False, False])
NONE = np.zeros(4, bool)
SILENT = np.array([True, True, False, False])


def test_nothing_is_tracked_until_a_body_is_seen():
    beams = BodyBeams()
    assert beams.silent_body(NONE, SILENT, 0.1, 1.5) is None


def test_a_beam_that_returned_the_body_is_the_body_again_while_silent_for_a_while():
    beams = BodyBeams()
    assert beams.silent_body(BODY, NONE, 0.1, 1.5) is None  # a return: nothing silent
    for _ in range(14):  # 1.4 s of silence
        assert beams.silent_body(NONE, SILENT, 0.1, 1.5).tolist() == [True, False, False, False]
    assert beams.silent_body(NONE, SILENT, 0.2, 1.5) is None  # 1.6 s: silence again


def test_a_new_sequence_forgets_the_body():
    beams = BodyBeams()
    beams.silent_body(BODY, NONE, 0.1, 1.5)
    beams.reset()
    assert beams.silent_body(NONE, SILENT, 0.1, 1.5) is None
