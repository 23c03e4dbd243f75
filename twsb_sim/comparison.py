"""Other filters on the same frames as the one in the loop, for the run's summary.

A run shows the filter in the loop; a reader also wants to see how another filter does
on exactly the same scans (``twsb run`` puts the paper's filter beside the improved one).
:class:`FilterComparison` is a sink that runs each compared filter on every frame and,
when the run ends, hands its counts to the run's summary.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from twsb_sim.frame import Frame
from twsb_sim.frame_filter import FrameFilter
from twsb_sim.sinks import NullSink
from twsb_sim.summary import FilterCounts, FilterTally, RunSummary


class FilterComparison(NullSink):
    """Runs filters beside the one in the loop, on the same frames.

    Args:
        filters: label -> filter; each is reset before the run's first frame.
    """

    def __init__(self, filters: Mapping[str, FrameFilter]) -> None:
        self.filters = dict(filters)
        self.tallies = {label: FilterTally(label, FilterCounts()) for label in self.filters}
        for frame_filter in self.filters.values():
            frame_filter.reset()

    def on_frame(self, frame: Frame, filter_result: Any | None) -> None:
        for label, frame_filter in self.filters.items():
            removed = frame_filter.process(frame).removed
            tally = self.tallies[label]
            tally.counts.add(frame.scan.ranges, frame.labels, removed)
            tally.removed_beams += int(np.count_nonzero(removed))

    def close(self, summary: RunSummary) -> None:
        summary.compared = list(self.tallies.values())
