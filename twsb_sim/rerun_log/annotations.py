"""Classes and colours: beam labels and filter decisions as annotation contexts.

Points carry class ids, not colours; the annotation context maps each id to a name
(shown on hover) and a colour, so the recording stays small and the legend is one place.
"""

from __future__ import annotations

import functools
from enum import IntEnum

import numpy as np
import rerun as rr

from twsb_sim.labels import LABEL_NAMES, PITCH_VARIATION_LABELS, BeamLabel

LABEL_COLORS: dict[BeamLabel, tuple[int, int, int]] = {
    BeamLabel.NO_RETURN: (90, 90, 90),
    BeamLabel.STATIC: (150, 170, 190),  # walls and furniture sides: quiet blue-grey
    BeamLabel.FLOOR: (255, 140, 0),  # the pitch-variation classes stand out
    BeamLabel.CEILING: (70, 150, 255),
    BeamLabel.HORIZONTAL: (255, 215, 0),
    BeamLabel.DYNAMIC: (0, 210, 210),
    BeamLabel.OCCLUDED: (60, 60, 60),
}


class BeamDecision(IntEnum):
    """The filter's decision on a beam against ground truth (positive = pitch-variation)."""

    TRUE_NEGATIVE = 0  # kept, and not a pitch-variation point
    TRUE_POSITIVE = 1  # removed, and a pitch-variation point
    FALSE_POSITIVE = 2  # removed, but not a pitch-variation point
    FALSE_NEGATIVE = 3  # kept, but a pitch-variation point


DECISION_COLORS: dict[BeamDecision, tuple[int, int, int]] = {
    BeamDecision.TRUE_NEGATIVE: (120, 130, 140),
    BeamDecision.TRUE_POSITIVE: (40, 200, 80),
    BeamDecision.FALSE_POSITIVE: (255, 50, 50),
    BeamDecision.FALSE_NEGATIVE: (255, 0, 255),
}


def packed_colors(colors: np.ndarray) -> np.ndarray:
    """RGB(A) uint8 rows as Rerun's packed ``0xRRGGBBAA`` uint32, which it takes ~20x faster."""
    colors = np.asarray(colors, dtype=np.uint32).reshape(-1, np.shape(colors)[-1])
    alpha = colors[:, 3] if colors.shape[1] == 4 else np.uint32(255)
    return (colors[:, 0] << 24) | (colors[:, 1] << 16) | (colors[:, 2] << 8) | alpha


# one colour per cluster id (cycled): distinct hues, none grey, and none of the
# decision colours (green, red, magenta) or the box colours (red, orange)
CLUSTER_PALETTE = np.array(
    [
        (31, 119, 180), (23, 190, 207), (148, 103, 189), (188, 189, 34), (227, 119, 194),
        (140, 86, 75), (174, 199, 232), (255, 230, 120), (120, 120, 220), (158, 218, 229),
    ],
    dtype=np.uint8,
)  # fmt: skip
DETECTED_COLOR = (255, 50, 50)  # a cluster detected in this scan (Algorithm 1)
TRACKED_COLOR = (255, 165, 0)  # a queued cluster followed from the last scan (Algorithm 2)
MAX_CLUSTER_CLASSES = 128  # cluster ids with a colour and a name (Table I's m_th allows 72)


@functools.cache  # annotation contexts take milliseconds to build: once per process
def label_annotation_context() -> rr.AnnotationContext:
    """Class id = :class:`BeamLabel` code, with its name and colour."""
    return rr.AnnotationContext(
        [(int(label), LABEL_NAMES[label], LABEL_COLORS[label]) for label in BeamLabel]
    )


@functools.cache
def cluster_annotation_context() -> rr.AnnotationContext:
    """Class id = cluster id within its scan: ``cluster #id``, palette colours cycled."""
    return rr.AnnotationContext(
        [
            (k, f"cluster #{k}", tuple(CLUSTER_PALETTE[k % len(CLUSTER_PALETTE)].tolist()))
            for k in range(MAX_CLUSTER_CLASSES)
        ]
    )


@functools.cache
def decision_annotation_context() -> rr.AnnotationContext:
    """Class id = :class:`BeamDecision`, named "true positive", ... ."""
    return rr.AnnotationContext(
        [(int(d), d.name.lower().replace("_", " "), DECISION_COLORS[d]) for d in BeamDecision]
    )


_PITCH_VARIATION = np.zeros(256, dtype=bool)  # label code -> is a pitch-variation point
_PITCH_VARIATION[list(PITCH_VARIATION_LABELS)] = True


def pitch_variation_mask(labels: np.ndarray) -> np.ndarray:
    """:func:`twsb_sim.labels.is_pitch_variation` by table lookup (for uint8 labels)."""
    return _PITCH_VARIATION[labels]


# index: removed + 2 * (decision wrong)
_DECISION_TABLE = np.array(
    [
        BeamDecision.TRUE_NEGATIVE,
        BeamDecision.TRUE_POSITIVE,
        BeamDecision.FALSE_NEGATIVE,
        BeamDecision.FALSE_POSITIVE,
    ],
    dtype=np.uint8,
)


def beam_decisions(labels: np.ndarray, removed: np.ndarray) -> np.ndarray:
    """:class:`BeamDecision` per beam (uint8), from ground-truth labels and the removed mask."""
    removed = np.asarray(removed, dtype=bool)
    wrong = pitch_variation_mask(labels) != removed
    return _DECISION_TABLE[removed.astype(np.intp) + 2 * wrong]


LEGEND = """\
**Decision**: *green* true positive (removed, pitch-variation point), *red* false
positive, *magenta* false negative (kept, pitch-variation point), *grey* true negative;
white halo: removed. **Boxes**: removed clusters, *red* detected in this scan, *orange*
tracked from the last one, labelled with id and score (the paper's P(C_pv), the improved
filter's claim score; the same in the *Beam score* plot). **Level view** (improved
filter): small *light blue* dots where the remembered level scans put the structure
along each beam; a return in front of it is new. **Clusters**: a colour each.
**3D**: hits by label: floor *orange*, ceiling *blue*, table tops *yellow*, walls
*grey-blue*; white line: trajectory; blue disc: scan plane; red arrow: shove.
Hover a point for its class.
"""


def legend() -> rr.TextDocument:
    """What the colours of the default views mean (a markdown document)."""
    return rr.TextDocument(LEGEND, media_type=rr.MediaType.MARKDOWN)
