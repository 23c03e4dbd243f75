"""The beam layout of a scan, with its trigonometry computed once per layout."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from pvfilter.scan import Scan

FIT_TOLERANCE_BEAMS = 2.0  # beams: how far a scan's beams may lie from a layout's and
# still be taken for them (a driver's angle_min jitters by a fraction of a beam)


def indices(mask: np.ndarray) -> np.ndarray:
    """Indices where a 1-D mask is true (``np.flatnonzero`` without its Python layers)."""
    return mask.nonzero()[0]


def row_norms(points: np.ndarray) -> np.ndarray:
    """Distance of each point of ``points`` (rows ``x, y``, m, ``(k, 2)``) from the origin, m.

    The rows of a C-ordered float array are complex numbers ``x + iy`` in memory, and
    numpy's complex absolute value gives their distances at a third of ``np.hypot``'s
    cost on a scan's points, within two units in the last place of the exact distance
    (``np.hypot``: one; about 1e-15 m at 10 m), without overflow. Other arrays (a column
    slice, another dtype) take ``np.hypot``.
    """
    if points.dtype == np.float64 and points.flags.c_contiguous:
        return np.abs(points.view(np.complex128)).reshape(len(points))
    return np.hypot(points[:, 0], points[:, 1])


@dataclasses.dataclass(frozen=True, eq=False)
class BeamLayout:
    """Angles of a scan's beams and what every stage needs from them.

    Attributes:
        count: beams per scan.
        angle_min: angle of beam 0, rad.
        increment: angle between beams, rad.
        cos: cosine of every beam angle, ``(count,)``.
        sin: sine of every beam angle, ``(count,)``.
        ring: the beams cover a full turn (within two increments), so beam ``count - 1``
            neighbours beam 0 and turns wrap around.
    """

    count: int
    angle_min: float
    increment: float
    cos: np.ndarray
    sin: np.ndarray
    ring: bool
    _tables: dict = dataclasses.field(default_factory=dict, repr=False)

    @classmethod
    def of(cls, scan: Scan) -> BeamLayout:
        """The layout of ``scan``'s beams."""
        angles = scan.angles()
        ring = (len(scan) + 1) * scan.angle_increment >= 2.0 * math.pi
        return cls(
            len(scan), scan.angle_min, scan.angle_increment, np.cos(angles), np.sin(angles), ring
        )

    def fits(self, scan: Scan) -> bool:
        """``scan``'s beams are this layout's, each within ``FIT_TOLERANCE_BEAMS`` beams.

        Drivers that take ``angle_min`` from the first sample of each turn move it by a
        fraction of a beam from scan to scan. Taken for a new layout, every scan started
        the filter afresh, and it found nothing. Within the tolerance the filter works in
        this layout's frame, turned by that fraction from the scan's: its scan match takes
        the turn for the sensor's, as the level view's move does. (An ``angle_min`` that
        drifts on, rather than jitters, passes the tolerance now and then, and the filter
        starts afresh there.)
        """
        if len(scan) != self.count:
            return False
        if scan.angle_min == self.angle_min and scan.angle_increment == self.increment:
            return True
        last = self.count - 1
        shift = scan.angle_min - self.angle_min
        if self.ring:  # a full turn may start near -pi one scan and near +pi the next
            shift = math.remainder(shift, 2.0 * math.pi)
        last_off = abs(shift + last * (scan.angle_increment - self.increment))
        return max(abs(shift), last_off) <= FIT_TOLERANCE_BEAMS * self.increment

    def points(self, ranges: np.ndarray) -> np.ndarray:
        """Sensor-frame points of per-beam ranges, m, ``(count, 2)`` (NaN stays NaN)."""
        points = np.empty((self.count, 2))
        np.multiply(ranges, self.cos, out=points[:, 0])
        np.multiply(ranges, self.sin, out=points[:, 1])
        return points

    def beam_of(self, points: np.ndarray) -> np.ndarray:
        """The beam each point lies on, ``(k,)``; -1 where outside the scan's angles."""
        return self.beam_at(points[:, 0], points[:, 1])

    def beam_at(self, x: np.ndarray, y: np.ndarray, finite: bool = False) -> np.ndarray:
        """The beam each point ``(x, y)`` lies on, ``(k,)``; -1 where outside the scan's
        angles (a non-finite point: -1 off a ring, some beam on a ring).

        ``finite``: the caller vouches that every coordinate is finite (the level view's
        moved points are), and a ring's beams wrap through one gather from the table of
        beams, at a third of the cost of an integer remainder. numpy's "wrap" gather
        steps an index back into range one turn at a time, and a NaN's index (the
        smallest integer) would take it some 1e16 steps: other points take the remainder.
        """
        bearing = np.arctan2(y, x)
        bearing -= self.angle_min  # in place: this runs on every beam of every scan
        bearing /= self.increment
        beams = np.rint(bearing, out=bearing).astype(np.intp)
        if self.ring:
            if finite:
                return self.every_beam().take(beams, mode="wrap")
            return np.remainder(beams, self.count, out=beams)
        # off a ring the table has -1 on either side of the beams, and "clip" maps every
        # index past them onto one of those (one gather, a third of the cost of three masks)
        beams += 1  # (the table's first beam)
        return self._beams_or_outside().take(beams, mode="clip")

    def hits_along_x(
        self, points: np.ndarray, ranges: np.ndarray, shifts_m: np.ndarray, tolerance_m: float
    ) -> np.ndarray:
        """Per shift of ``shifts_m`` along x: how many of ``points`` (``(k, 2)``, m), so
        shifted, land within ``tolerance_m`` of the range that ``ranges`` (per beam, m; NaN:
        none) holds on their beam. All shifts in one pass over the points."""
        x = points[:, 0] + shifts_m[:, None]  # (shifts, points)
        y = np.broadcast_to(points[:, 1], x.shape)
        beams = self.beam_at(x.ravel(), y.ravel()).reshape(x.shape)
        seen = np.append(ranges, np.nan).take(beams)  # beam -1 (outside the scan): NaN
        on = np.abs(seen - np.hypot(x, y)) <= tolerance_m  # NaN compares False
        return np.count_nonzero(on, axis=1)

    def every_beam(self) -> np.ndarray:
        """The beam indices ``0 .. count - 1`` (cached; not to be changed)."""
        if "every" not in self._tables:
            every = np.arange(self.count)
            every.flags.writeable = False
            self._remember("every", every)
        return self._tables["every"]

    def beam_numbers(self) -> np.ndarray:
        """:meth:`every_beam` as floats (cached; not to be changed): sums with a fraction
        of a beam give the same floats, without converting the integers every scan."""
        if "numbers" not in self._tables:
            numbers = np.arange(self.count, dtype=float)
            numbers.flags.writeable = False
            self._remember("numbers", numbers)
        return self._tables["numbers"]

    def neighbours(self) -> np.ndarray:
        """Per beam, the beams on either side, ``(count, 2)``: ``i - 1`` and ``i + 1``,
        wrapping on a ring (cached; not to be changed). Off a ring the first and the last
        beam stand for themselves on the side beyond the field of view: asked about a beam
        without a value (NaN), that side has none either."""
        if "neighbours" not in self._tables:
            beams = np.arange(self.count)
            table = np.stack((beams - 1, beams + 1), axis=1)
            if self.ring:
                table[0, 0], table[-1, 1] = self.count - 1, 0
            else:
                table[0, 0], table[-1, 1] = 0, self.count - 1
            table.flags.writeable = False
            self._remember("neighbours", table)
        return self._tables["neighbours"]

    def _beams_or_outside(self) -> np.ndarray:
        """``-1, 0, 1, .., count - 1, -1`` (cached; not to be changed): beam ``i`` at
        ``i + 1``, outside the scan's angles at either end."""
        if "outside" not in self._tables:
            table = np.arange(-1, self.count + 1)
            table[-1] = -1
            table.flags.writeable = False
            self._remember("outside", table)
        return self._tables["outside"]

    def mid_scan_offsets(self) -> np.ndarray:
        """Each beam's index less the middle one's, ``i - (count - 1) / 2`` (cached): times
        the time increment, when it is measured relative to mid-scan."""
        if "mid" not in self._tables:
            self._remember("mid", np.arange(self.count) - 0.5 * (self.count - 1))
        return self._tables["mid"]

    def mid_scan_times(self, time_increment: float) -> np.ndarray:
        """Each beam's time after mid-scan, s: :meth:`mid_scan_offsets` times
        ``time_increment`` (cached: a LiDAR keeps its timing scan after scan; not to be
        changed)."""
        key = ("times", time_increment)
        if key not in self._tables:
            times = self.mid_scan_offsets() * time_increment
            times.flags.writeable = False
            self._remember(key, times)
        return self._tables[key]

    def shift_table(self, first: int, count: int, stride: int) -> tuple[np.ndarray, np.ndarray]:
        """Beams ``0, stride, 2 stride, ...`` and, for each of the shifts ``first`` ..
        ``first + count - 1``, the beam each of them came from (a ring wraps around;
        otherwise a source outside the scan is the extra index ``count``, to be NaN).

        Cached: the turn search asks for the same few tables scan after scan.
        """
        key = (first, count, stride)
        if key not in self._tables:
            beams = np.arange(0, self.count, stride)
            source = beams[None, :] - np.arange(first, first + count)[:, None]
            if self.ring:
                source %= self.count
            else:
                source[(source < 0) | (source >= self.count)] = -1  # the NaN appended
            self._remember(key, (beams, source))
        return self._tables[key]

    def _remember(self, key: tuple, value: object) -> None:
        """Cache ``value`` for this layout (bounded: cleared when it grows past 256)."""
        if len(self._tables) > 256:
            self._tables.clear()
        self._tables[key] = value

    def shifted(self, values: np.ndarray, shift: int) -> np.ndarray:
        """``values`` per beam moved by ``shift`` beams (element ``i`` to ``i + shift``).

        On a ring the beams wrap around; otherwise vacated beams are NaN. A shift of 0 (a
        sensor that did not turn) gives ``values`` itself, not a copy: not to be changed.
        """
        if shift == 0:
            return values
        if self.ring:  # np.roll, as a cached gather (take() is cheaper than roll's copies)
            key = ("roll", shift)
            if key not in self._tables:
                self._remember(key, (np.arange(self.count) - shift) % self.count)
            return values.take(self._tables[key], axis=0)
        moved = np.full(values.shape, np.nan)
        if abs(shift) >= len(values):  # turned past every beam: none is seen again
            return moved
        if shift >= 0:
            moved[shift:] = values[: len(values) - shift]
        else:
            moved[:shift] = values[-shift:]
        return moved
