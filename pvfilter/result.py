"""What every filter returns for a scan: the filtered scan, the removed mask, the scores.

Filters keep the array length (as ROS ``laser_filters`` does): a removed beam becomes
NaN in the filtered scan, and the caller also gets the boolean mask. A filter's own
result type extends :class:`FilterResult` with what that filter computed
(:class:`pvfilter.paper.PaperResult`, :class:`pvfilter.improved.ImprovedResult`); each
says what its fields mean for that filter.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from pvfilter.clusters import ClusterView
from pvfilter.scan import Scan


@dataclasses.dataclass(frozen=True, eq=False)  # holds arrays: no field-wise ==
class FilterResult:
    """A filter's output for one scan.

    Attributes:
        scan: the input scan with removed beams set to NaN (same length).
        removed: bool per beam: True where the filter removed the beam.
        scores: float per beam: how strongly the filter holds the beam to be a
            pitch-variation point (its meaning is the filter's; 0 where it has no opinion).
    """

    scan: Scan
    removed: np.ndarray
    scores: np.ndarray

    def cluster_view(self) -> ClusterView | None:
        """The filter's clusters and decisions, for a viewer; None for filters without."""
        return None


def without_removed(scan: Scan, removed: np.ndarray) -> Scan:
    """``scan`` with the ``removed`` beams set to NaN (the scan itself when none is)."""
    # a scan is immutable, so one that loses no beam is its own filtered copy
    if not np.count_nonzero(removed):  # (count_nonzero: any() without Python layers)
        return scan
    return scan.with_ranges(np.where(removed, np.nan, scan.ranges))
