"""The ``none`` filter: removes nothing.

The reference every other filter is compared with, and what a robot runs to pass its
scans through unchanged (``pvfilter bag --filter none`` copies a bag and adds an empty
removed mask). It lives here rather than beside the evaluation baselines so that a robot
install of this package alone has it.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from pvfilter.result import FilterResult
from pvfilter.scan import Scan


class NoFilter:
    """Removes nothing: the reference every other method is compared with."""

    def process(
        self,
        scan: Scan,
        *,
        pitch_rad: float | None = None,
        roll_rad: float | None = None,
        pose_sensor_in_odom: ArrayLike | None = None,
    ) -> FilterResult:
        """The scan as it is; nothing removed, every score 0."""
        return FilterResult(scan, np.zeros(len(scan), dtype=bool), np.zeros(len(scan)))

    def reset(self) -> None:
        """Nothing to forget."""
