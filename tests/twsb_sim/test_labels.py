"""Beam labels (twsb_sim.labels): the masks numpy computes from them."""

import numpy as np

from twsb_sim.labels import BeamLabel, is_pitch_variation, with_label

LABELS = np.array([1, 5, 2, 6, 5, 3, 4, 0], dtype=np.uint8)


def test_label_masks_pick_their_beams():
    assert with_label(LABELS, BeamLabel.DYNAMIC).tolist() == [0, 1, 0, 0, 1, 0, 0, 0]
    assert is_pitch_variation(LABELS).tolist() == [0, 0, 1, 0, 0, 1, 1, 0]


def test_a_stop_raised_while_numpy_asks_the_enum_is_not_lost(monkeypatch):
    # numpy, handed an enum member, asks its class for __array_ufunc__; the enum answers
    # in Python, and numpy drops what that raises: a Ctrl-C landing there was lost
    asked = []
    member_map = type(BeamLabel).__getattr__

    def answer(cls, name):
        if name.startswith("__") and name.endswith("__"):
            asked.append(name)
            raise KeyboardInterrupt
        return member_map(cls, name)

    monkeypatch.setattr(type(BeamLabel), "__getattr__", answer)
    LABELS == BeamLabel.DYNAMIC  # noqa: B015 (what numpy does with a member)
    assert asked  # the stop raised there went nowhere
    asked.clear()
    assert with_label(LABELS, BeamLabel.DYNAMIC).tolist() == [0, 1, 0, 0, 1, 0, 0, 0]
    assert is_pitch_variation(LABELS).sum() == 3
    assert not asked
