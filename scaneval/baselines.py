"""Baseline filters to compare with the pitch-variation filters, registered by name.

Each is a :class:`pvfilter.ScanFilter` (``process(scan, *, robot inputs) -> FilterResult``
and ``reset()``); each takes the robot inputs it needs by keyword and ignores the others:

- ``none`` (:class:`NoFilter`, :mod:`pvfilter.pass_through`, registered by pvfilter itself
  so that a robot install has it): removes nothing;
- ``datmo`` (:class:`DatmoLikeFilter`): a DATMO-like moving-object tracker, needs
  ``pose_sensor_in_odom``;
- ``imu_gate`` (:class:`ImuHeightGate`): an IMU height gate, needs ``pitch_rad`` (and
  ``roll_rad``).

The ``FilterEntry`` objects of ``datmo`` and ``imu_gate`` below are what this package
declares in the ``pvfilter.filters`` entry-point group, so :func:`pvfilter.make_filter`
knows them.
"""

from __future__ import annotations

from pvfilter.pass_through import NoFilter
from pvfilter.registry import FilterEntry
from scaneval.datmo import DatmoLikeFilter, DatmoParams
from scaneval.imu_gate import ImuGateParams, ImuHeightGate

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
    "DatmoLikeFilter",
    "DatmoParams",
    "ImuGateParams",
    "ImuHeightGate",
    "NoFilter",
]
