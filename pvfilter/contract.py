"""The contract every scan filter keeps: :class:`ScanFilter`, and its robot inputs.

A filter takes one scan per call, in time order, and returns a :class:`FilterResult`
of the same length. What else a robot has comes as optional keyword arguments, with
these frames and units (a filter that does not use an input ignores it):

==========================  ============================================================
keyword                     meaning
==========================  ============================================================
``pitch_rad``               the attitude as the robot's estimator gives it: pitch, rad,
                            positive nose down (rotation about the body's y axis)
``roll_rad``                roll, rad, positive left side up (0 when only a pitch is given)
``pose_sensor_in_odom``     the LiDAR's pose in the odom frame (REP-105) from wheel
                            odometry: ``(x m, y m, yaw rad)``, at the scan's stamp
==========================  ============================================================

The robot inputs are estimates: noisy, lagging, drifting. Filters that use them must
hold up when they are.
"""

from __future__ import annotations

import math
import numbers
from typing import Any, Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike

from pvfilter.result import FilterResult
from pvfilter.scan import Scan

ROBOT_INPUTS: tuple[str, ...] = ("pitch_rad", "roll_rad", "pose_sensor_in_odom")


@runtime_checkable
class ScanFilter(Protocol):
    """A scan filter: one scan in, one :class:`FilterResult` out; ``reset`` between runs."""

    def process(
        self,
        scan: Scan,
        *,
        pitch_rad: float | None = None,
        roll_rad: float | None = None,
        pose_sensor_in_odom: ArrayLike | None = None,
    ) -> FilterResult:
        """Filter one scan; call once per scan, in time order (see the module docstring)."""
        ...

    def reset(self) -> None:
        """Forget the history: the next scan starts a new sequence."""
        ...


def check_attitude(pitch_rad: float | None, roll_rad: float | None) -> tuple[float, float] | None:
    """``(pitch, roll)`` as floats, or None when no pitch is given (roll defaults to 0).

    Raises:
        ValueError: a roll without a pitch, a value that is not a finite number, or one
            beyond +/- pi (degrees given as radians, an angle not wrapped).
    """
    if pitch_rad is None:
        if roll_rad is not None:
            raise ValueError("roll_rad: given without pitch_rad")
        return None
    values = (pitch_rad, 0.0 if roll_rad is None else roll_rad)
    for name, value in zip(("pitch_rad", "roll_rad"), values, strict=True):
        real = isinstance(value, numbers.Real) and not isinstance(value, bool)
        if not real or not math.isfinite(value):
            raise ValueError(f"{name}: must be a finite number of radians, got {value!r}")
        if abs(value) > math.pi:  # (an angle is within half a turn either way)
            raise ValueError(
                f"{name}: must be within +/- pi rad, got {value!r}: degrees, or an angle "
                "not wrapped?"
            )
    return float(values[0]), float(values[1])


def check_pose(pose_sensor_in_odom: ArrayLike | None) -> np.ndarray | None:
    """The odometry pose as a float array ``(x, y, yaw)``, or None when not given.

    Raises:
        ValueError: a pose that is not three finite numbers.
    """
    if pose_sensor_in_odom is None:
        return None
    try:
        pose = np.array(pose_sensor_in_odom, dtype=np.float64)
    except (TypeError, ValueError):
        pose = np.zeros(0)
    if pose.shape != (3,) or not np.isfinite(pose).all():
        raise ValueError(
            "pose_sensor_in_odom: must be three finite numbers (x m, y m, yaw rad), "
            f"got {pose_sensor_in_odom!r}"
        )
    return pose


def check_scan(scan: object) -> None:
    """Refuse what is not a :class:`~pvfilter.scan.Scan` with a message that says so (an
    array of ranges given as the scan would fail deep inside, naming an attribute).

    Raises:
        TypeError: ``scan`` is not a Scan.
    """
    if not isinstance(scan, Scan):
        raise TypeError(
            f"scan: must be a pvfilter.Scan, got {type(scan).__name__} (build one with "
            "Scan(ranges=..., angle_min=..., angle_increment=..., range_min=..., "
            "range_max=..., stamp=...))"
        )


def params_or_defaults(params: object, expected: type, filter_name: str) -> Any:
    """``params``, or the defaults (``expected()``) when None; parameters of another
    filter are refused with a message that names both.

    Raises:
        TypeError: ``params`` is neither None nor an ``expected``.
    """
    if params is None:
        return expected()
    if not isinstance(params, expected):
        raise TypeError(f"{filter_name}: expects {expected.__name__}, got {type(params).__name__}")
    return params
