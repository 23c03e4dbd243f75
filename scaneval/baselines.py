"""Baseline filters to compare with the pitch-variation filters, registered by name.

Each is a :class:`pvfilter.ScanFilter` (``process(scan, *, robot inputs) -> FilterResult``
and ``reset()``); each takes the robot inputs it needs by keyword and ignores the others:

- ``none`` (:class:`NoFilter`): removes nothing;
- ``datmo`` (:class:`DatmoLikeFilter`): a DATMO-like moving-object tracker, needs
  ``pose_sensor_in_odom``;
- ``imu_gate`` (:class:`ImuHeightGate`): an IMU height gate, needs ``pitch_rad`` (and
  ``roll_rad``).

The ``FilterEntry`` objects below are what this package declares in the
``pvfilter.filters`` entry-point group, so :func:`pvfilter.make_filter` knows them.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from pvfilter.registry import FilterEntry
from pvfilter.result import FilterResult
from pvfilter.scan import Scan
from scaneval.datmo import DatmoLikeFilter, DatmoParams
from scaneval.imu_gate import ImuGateParams, ImuHeightGate


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


NO_FILTER = FilterEntry("none", NoFilter, None, "removes nothing (the reference)")
DATMO = FilterEntry(
    "datmo",
    DatmoLikeFilter,
    DatmoParams,
    "a DATMO-like moving-object tracker (needs the sensor's pose)",
    needs=("pose_sensor_in_odom",),
    threshold="speed_threshold_mps",
    one_pass=True,
)
IMU_GATE = FilterEntry(
    "imu_gate",
    ImuHeightGate,
    ImuGateParams,
    "an IMU height gate: beams ending outside a height band (needs the attitude)",
    needs=("pitch_rad", "roll_rad"),
)

__all__ = [
    "DATMO",
    "IMU_GATE",
    "NO_FILTER",
    "DatmoLikeFilter",
    "DatmoParams",
    "ImuGateParams",
    "ImuHeightGate",
    "NoFilter",
]
