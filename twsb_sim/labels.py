"""Ground-truth beam labels (the table users rely on; see docs/conventions.md).

Every simulated beam carries one of these ``uint8`` codes. A beam is a
*pitch-variation point* when its label is FLOOR, CEILING or HORIZONTAL: a level
scanner at the same place would not have hit that surface.
"""

from __future__ import annotations

from enum import IntEnum

import numpy as np


class BeamLabel(IntEnum):
    """Ground-truth class of one LiDAR beam."""

    NO_RETURN = 0  # nothing within range_max
    STATIC = 1  # a vertical surface: wall, door frame, furniture side
    FLOOR = 2  # pitch-variation point on the floor
    CEILING = 3  # pitch-variation point on the ceiling
    HORIZONTAL = 4  # pitch-variation point on another horizontal surface (table top, shelf)
    DYNAMIC = 5  # a moving object (reserved)
    OCCLUDED = 6  # blocked by the robot's own body (outside the useful field of view)


PITCH_VARIATION_LABELS: tuple[BeamLabel, ...] = (
    BeamLabel.FLOOR,
    BeamLabel.CEILING,
    BeamLabel.HORIZONTAL,
)

LABEL_NAMES: dict[int, str] = {int(label): label.name for label in BeamLabel}


def with_label(labels: np.ndarray, label: BeamLabel) -> np.ndarray:
    """Boolean mask of the beams labelled ``label``, any shape.

    Compares with the label's plain code. Given the enum member itself, numpy looks up
    ``__array_ufunc__`` on its class, which runs the enum's Python ``__getattr__``, and
    drops whatever that raises: a Ctrl-C landing there was lost, and the command ran on
    to the end and exited 0. (The same holds for ``np.full`` with a member as its value.)
    """
    return labels == int(label)


def is_pitch_variation(labels: np.ndarray) -> np.ndarray:
    """Boolean mask of the beams whose label marks a pitch-variation point.

    Args:
        labels: uint8 label codes, any shape.

    Returns:
        bool array of the same shape.
    """
    return np.isin(labels, np.array(PITCH_VARIATION_LABELS, dtype=np.uint8))
