"""One 2D LiDAR scan: the fields of ``sensor_msgs/LaserScan`` plus a stamp.

Beam ``i`` points at ``angle_min + i * angle_increment`` (rad, counter-clockwise positive,
0 = straight ahead along the sensor's x axis). Ranges follow REP-117:

- ``+inf``: no return within ``range_max``;
- ``-inf``: an object closer than ``range_min``;
- ``NaN``: an invalid measurement, or a beam a filter removed.

Any finite range outside ``[range_min, range_max]`` is also treated as invalid (as the
ROS message documentation asks of consumers). A range of ``range_max`` itself is a return
by REP-117, but drivers and simulators that clamp write it for no echo, as many low-cost
scanners' drivers write ``0.0``: :meth:`Scan.no_echo_mask` counts both as no echo.
Invalid beams keep their slot in the array: filters never change the array length.
"""

from __future__ import annotations

import copy
import dataclasses
import math

import numpy as np

# Bounds no real scanner comes near, that keep every beam's angle and point finite: the
# finest 2D LiDARs space beams about 1e-3 rad apart; drivers give angle_min in [-2 pi, 2 pi]
MIN_ANGLE_INCREMENT = 1e-9  # rad
MAX_ABS_ANGLE_MIN = 4.0 * math.pi  # rad
MAX_RANGE_MAX = 1e5  # m: the longest 2D LiDARs reach a few hundred metres
# a range this close to range_max (relative) is range_max itself, rounded to float32 as a
# LaserScan carries it (float32 rounds by up to 6e-8)
RANGE_LIMIT_RTOL = 1e-6


def _read_only_float_array(name: str, values: object) -> np.ndarray:
    try:
        array = np.array(values, dtype=np.float64)  # always a copy: callers may reuse theirs
    except (TypeError, ValueError) as error:
        raise ValueError(f"{name}: must be numbers, got {type(values).__name__}") from error
    if array.ndim != 1:
        raise ValueError(f"{name}: must be a 1-D array, got shape {array.shape}")
    array.flags.writeable = False
    return array


def _check_finite(name: str, value: float) -> float:
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f"{name}: must be finite, got {value}")
    return value


@dataclasses.dataclass(frozen=True, eq=False, kw_only=True)
class Scan:
    """A 2D LiDAR scan in the sensor frame (REP-103 axes, REP-117 range encoding).

    The arrays are copied into read-only float64 arrays, so a ``Scan`` never changes
    after construction and can be shared between threads.

    Attributes:
        ranges: range of every beam, m (``+inf``, ``-inf``, ``NaN`` as in REP-117).
        angle_min: angle of beam 0, rad, within +/- 4 pi.
        angle_increment: angle between consecutive beams, rad, in [1e-9, 2 pi]
            (counter-clockwise).
        range_min: smallest valid range, m, >= 0.
        range_max: largest valid range, m, > ``range_min`` and <= 1e5.
        stamp: acquisition time of beam 0, s.
        time_increment: time between consecutive beams, s.
        scan_time: time between scans, s, >= 0.
        intensities: optional per-beam intensities (device units), same length as
            ``ranges``; ``None`` when the device gives none.

    Raises:
        ValueError: naming the field, for a non-1-D ``ranges`` or ``intensities``, a length
            mismatch, an ``angle_increment`` or ``angle_min`` out of bounds, a negative
            ``range_min``, ``range_min >= range_max``, or any non-finite scalar.
    """

    ranges: np.ndarray
    angle_min: float
    angle_increment: float
    range_min: float
    range_max: float
    stamp: float = 0.0
    time_increment: float = 0.0
    scan_time: float = 0.0
    intensities: np.ndarray | None = None

    def __post_init__(self) -> None:
        # frozen: validated, normalised values are written with object.__setattr__
        put = object.__setattr__
        put(self, "ranges", _read_only_float_array("ranges", self.ranges))
        for name in ("angle_min", "angle_increment", "range_min", "range_max", "stamp"):
            put(self, name, _check_finite(name, getattr(self, name)))
        put(self, "time_increment", _check_finite("time_increment", self.time_increment))
        put(self, "scan_time", _check_finite("scan_time", self.scan_time))
        if not MIN_ANGLE_INCREMENT <= self.angle_increment <= math.tau:
            raise ValueError(
                f"angle_increment: must be in [{MIN_ANGLE_INCREMENT:g}, 2 pi] rad, "
                f"got {self.angle_increment}"
            )
        if abs(self.angle_min) > MAX_ABS_ANGLE_MIN:
            raise ValueError(f"angle_min: must be within +/- 4 pi rad, got {self.angle_min}")
        if self.range_min < 0.0:
            raise ValueError(f"range_min: must be >= 0 m, got {self.range_min}")
        if self.range_max > MAX_RANGE_MAX:
            raise ValueError(f"range_max: must be <= {MAX_RANGE_MAX:g} m, got {self.range_max}")
        if self.range_min >= self.range_max:
            raise ValueError(
                f"range_max: must be > range_min ({self.range_min} m), got {self.range_max}"
            )
        if self.scan_time < 0.0:
            raise ValueError(f"scan_time: must be >= 0 s, got {self.scan_time}")
        if self.intensities is not None:
            intensities = _read_only_float_array("intensities", self.intensities)
            if intensities.shape != self.ranges.shape:
                raise ValueError(
                    f"intensities: must have one value per beam ({self.ranges.size}), "
                    f"got {intensities.size}"
                )
            put(self, "intensities", intensities)

    def __len__(self) -> int:
        return int(self.ranges.size)

    @classmethod
    def counter_clockwise(
        cls,
        *,
        ranges: object,
        angle_min: float,
        angle_increment: float,
        range_min: float,
        range_max: float,
        stamp: float = 0.0,
        time_increment: float = 0.0,
        scan_time: float = 0.0,
        intensities: object | None = None,
    ) -> tuple[Scan, bool]:
        """A scan from ``LaserScan`` fields whose beams may run clockwise.

        ROS allows a negative ``angle_increment``: beam ``i + 1`` clockwise of beam ``i``,
        as some drivers publish a scanner mounted upside down. A ``Scan`` orders its beams
        counter-clockwise, so such a scan is reversed: its beam ``i`` is the message's
        beam ``n - 1 - i``, at the same angle and measured at the same time (``angle_min``
        becomes the message's last angle, ``stamp`` the time of the message's last beam,
        and ``time_increment`` changes sign with the order). Per-beam results of the
        reversed scan, ``removed`` say, map back to the message's order with ``[::-1]``.

        Returns:
            The scan, and whether its beams are the message's reversed.

        Raises:
            ValueError: as the constructor, for any field out of bounds.
        """
        fields = {"range_min": range_min, "range_max": range_max, "scan_time": scan_time}
        if not angle_increment < 0.0:  # (NaN and 0 go to the constructor, which names them)
            return cls(
                ranges=ranges, angle_min=angle_min, angle_increment=angle_increment,
                stamp=stamp, time_increment=time_increment, intensities=intensities,
                **fields,
            ), False  # fmt: skip
        ranges = _read_only_float_array("ranges", ranges)[::-1]
        last = max(ranges.size - 1, 0)
        if intensities is not None:
            intensities = _read_only_float_array("intensities", intensities)[::-1]
        reversed_scan = cls(
            ranges=ranges,
            angle_min=angle_min + last * angle_increment,
            angle_increment=-angle_increment,
            stamp=stamp + last * time_increment,
            time_increment=-time_increment,
            intensities=intensities,
            **fields,
        )
        return reversed_scan, True

    @property
    def angle_max(self) -> float:
        """Angle of the last beam, rad (``angle_min`` for an empty scan)."""
        return self.angle_min + max(len(self) - 1, 0) * self.angle_increment

    def angles(self) -> np.ndarray:
        """Angle of every beam, rad, shape ``(n,)``."""
        return self.angle_min + np.arange(len(self), dtype=np.float64) * self.angle_increment

    def valid_mask(self) -> np.ndarray:
        """True where the beam holds a usable return: finite and in ``[range_min, range_max]``."""
        with np.errstate(invalid="ignore"):
            return (self.ranges >= self.range_min) & (self.ranges <= self.range_max)

    def no_echo_mask(self) -> np.ndarray:
        """True where the beam returned nothing within ``range_max``: ``+inf``; ``range_max``
        itself (to float32 rounding), which drivers and simulators that clamp write for no
        echo (a return at the very limit says no more: nothing nearer along the beam); and
        ``0.0``, which many low-cost scanners' drivers write for it (no return comes from
        the sensor itself). Other ranges outside ``[range_min, range_max]`` are invalid."""
        ranges, tolerance = self.ranges, RANGE_LIMIT_RTOL * self.range_max
        at_limit = (ranges >= self.range_max - tolerance) & (ranges <= self.range_max + tolerance)
        return at_limit | (ranges == np.inf) | (ranges == 0.0)  # NaN compares False

    def points(self) -> np.ndarray:
        """Beam end points in the sensor frame, m, shape ``(n, 2)`` as columns x, y.

        Rows of invalid beams (see :meth:`valid_mask`) are ``NaN``, so row ``i`` always
        belongs to beam ``i``; take ``scan.points()[scan.valid_mask()]`` for valid points only.
        """
        angles = self.angles()
        ranges = np.where(self.valid_mask(), self.ranges, np.nan)
        return np.column_stack((ranges * np.cos(angles), ranges * np.sin(angles)))

    def with_ranges(self, ranges: np.ndarray) -> Scan:
        """A copy of this scan with other ranges (same length), e.g. a filtered scan.

        Raises:
            ValueError: if ``ranges`` does not have one value per beam.
        """
        ranges = _read_only_float_array("ranges", ranges)
        if ranges.shape != self.ranges.shape:
            raise ValueError(
                f"ranges: must keep the scan's length ({len(self)}), got {ranges.size}"
            )
        # the other fields are this scan's, checked already: a shallow copy instead of a
        # new scan checked (and its arrays copied) field by field again
        scan = copy.copy(self)
        object.__setattr__(scan, "ranges", ranges)
        return scan
