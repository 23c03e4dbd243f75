"""The robot's own body in the scan: beams that return it now and then.

A body at the edge of ``range_min`` (a wheel, the frame in the blocked sector) reads now
nearer than any floor line can lie, now too close, and drivers that write too close as no
echo (``0.0``, ``+inf``) make those beams silent: space seen free, to the level view.
Freed, that space was carried by the turns onto the walls beside the sector, and they were
new (60 beams of one scan removed on a synthetic room). A silent beam that returned the
body within ``memory_timeout_s`` reads it again, out of range: it is unmeasured, not silent.

A body that returns (a mast, a handle, the frame a few decimetres behind a 360° scanner)
is fixed to the sensor, but the level view takes it for a surface of the world and
carries it with the ego-motion: driving forward, it slides back across the beams behind
the sensor, and there, decimetres away, it stood in front of everything. The floor line
of the next nose-up event behind the robot lay beyond that view, not in front of it, and
was kept (the eighth independent generator's office: its view behind the robot read
0.2-0.4 m for 2.5 s while the wall stood 4-7 m away). A return nearer than any floor line
that keeps its range on its beam while the sensor travels ``BODY_TRAVEL_M`` is the body,
and the view knows nothing there (:meth:`pvfilter.improved.memory.LevelMemory.forget`).
A surface of the world that near changes its range on a beam as the sensor passes it;
one that runs along the travel keeps it, and is taken for the body too, until the sensor
turns or leaves it: a floor line that settles in front of it is then not new there.
"""

from __future__ import annotations

import numpy as np

BODY_TRAVEL_M = 0.1  # m: a near return that keeps its range while the sensor travels this
# far is fixed to the sensor (a wall 0.3 m off, seen 30 deg off its normal, moves 5 cm)
BODY_TOLERANCE_M = 0.03  # m: a return keeps its range within this: three times a scanner's
# range noise near the sensor, where it is least (the noise the line distances follow,
# measured where most returns lie, is larger: as this tolerance it let walls a few
# decimetres off that the sensor passed keep their range, and forgotten, they were new
# when they came back: the eighth generator's kitchen, precision 0.71 to 0.35)


class BodyBeams:
    """How long ago each beam returned the robot's body (sensor frame: the body does not
    move with the robot, so no gap or ego-motion changes it; a new sequence does)."""

    def __init__(self) -> None:
        self._since_s: np.ndarray | None = None  # per beam, s; None: no body seen yet
        self._fixed = _SensorFixed()

    def reset(self) -> None:
        """Forget the beams: a new sequence, or another scanner."""
        self._since_s = None
        self._fixed = _SensorFixed()

    @property
    def tracking(self) -> bool:
        """Near returns have been seen: their beams are followed (else nothing is)."""
        return self._fixed.tracking

    def returning_body(
        self,
        near_m: np.ndarray,
        travel_m: float,
        dt: float,
        memory_s: float,
    ) -> np.ndarray | None:
        """The beams whose near return is the body: on a beam that kept a near return's
        range (within ``BODY_TOLERANCE_M``) while the sensor travelled ``BODY_TRAVEL_M``,
        within ``memory_s``; None: none.

        Args:
            near_m: per beam, its return where nearer than any floor line can lie, m
                (NaN elsewhere).
            travel_m: how far the sensor travelled since the previous scan, m.
            dt: time since the previous scan, s.
            memory_s: how long a beam found so is taken to return the body.
        """
        return self._fixed.update(near_m, travel_m, dt, memory_s)

    def silent_body(
        self, body: np.ndarray, no_echo: np.ndarray, dt: float, memory_s: float
    ) -> np.ndarray | None:
        """The silent beams that returned the body within ``memory_s``; None: none.

        Args:
            body: per beam, it returned the body in this scan (nearer than any floor line).
            no_echo: per beam, it returned nothing.
            dt: time since the previous scan, s.
            memory_s: how long a beam that returned the body is taken to show it.
        """
        since = self._since_s
        if since is None or since.shape != body.shape:
            if not np.count_nonzero(body):
                return None  # no body seen: nothing to track (the usual case)
            since = np.full(body.shape, np.inf)
        since += dt
        since[body] = 0.0
        self._since_s = since
        silent = no_echo & (since <= memory_s)
        return silent if np.count_nonzero(silent) else None


class _SensorFixed:
    """Per beam, the near range it keeps and how far the sensor travelled meanwhile, and
    how long ago it showed a range fixed to the sensor."""

    def __init__(self) -> None:
        self._kept_m: np.ndarray | None = None  # per beam, m; NaN: no near return
        self._travel_m: np.ndarray | None = None  # per beam, m travelled with it kept
        self._since_s: np.ndarray | None = None  # per beam, s since it showed the body

    @property
    def tracking(self) -> bool:
        """Near returns have been seen (see :attr:`BodyBeams.tracking`)."""
        return self._kept_m is not None

    def update(
        self, near_m: np.ndarray, travel_m: float, dt: float, memory_s: float
    ) -> np.ndarray | None:
        """Take one scan's near returns (see :meth:`BodyBeams.returning_body`)."""
        near = ~np.isnan(near_m)
        if self._kept_m is None or self._kept_m.shape != near_m.shape:
            if not np.count_nonzero(near):
                return None  # nothing near: nothing to track (the usual case)
            self._kept_m = np.full(near_m.shape, np.nan)
            self._travel_m = np.zeros(near_m.shape)
            self._since_s = np.full(near_m.shape, np.inf)
        kept, travel, since = self._kept_m, self._travel_m, self._since_s
        since += dt
        travel += travel_m
        # a near return that left the range it kept (NaN: none kept) starts again from it
        moved = ~(np.abs(near_m - kept) <= BODY_TOLERANCE_M)
        restart = near & moved
        kept[restart] = near_m[restart]
        travel[restart] = 0.0
        kept[~near] = np.nan
        since[near & (travel >= BODY_TRAVEL_M)] = 0.0
        body = near & (since <= memory_s)
        return body if np.count_nonzero(body) else None
