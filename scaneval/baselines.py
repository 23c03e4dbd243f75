"""Baseline filters to compare with the Pitch Variation Filter: scan in, bool mask out.

Every baseline has ``process(scan, **context) -> removed`` (True = beam removed, one
value per beam, the scan's length kept) and ``reset()``; the context each one reads is
passed by keyword: ``pose_sensor_in_world`` (:class:`DatmoLikeFilter`), ``pitch_rad`` and
``roll_rad`` (:class:`ImuHeightGate`). Others are ignored, so a loop can pass all of them
to every baseline.
"""

from __future__ import annotations

import numpy as np

from pvfilter.scan import Scan
from scaneval.datmo import DatmoLikeFilter
from scaneval.imu_gate import ImuHeightGate


class NoFilter:
    """Removes nothing: the reference every other method is compared with."""

    def process(self, scan: Scan, **context: object) -> np.ndarray:
        """All False, one per beam."""
        return np.zeros(len(scan), dtype=bool)

    def reset(self) -> None:
        """Nothing to forget."""


__all__ = ["DatmoLikeFilter", "ImuHeightGate", "NoFilter"]
