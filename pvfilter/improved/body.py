"""The robot's own body in the scan: beams that return it now and then.

A body at the edge of ``range_min`` (a wheel, the frame in the blocked sector) reads now
nearer than any floor line can lie, now too close, and drivers that write too close as no
echo (``0.0``, ``+inf``) make those beams silent: space seen free, to the level view.
Freed, that space was carried by the turns onto the walls beside the sector, and they were
new (60 beams of one scan removed on a synthetic room). A silent beam that returned the
body within ``memory_timeout_s`` reads it again, out of range: it is unmeasured, not silent.

A body that returns (a mast, a handle, the frame a few decimetres behind a 360° scanner)
is fixed to the sensor, but the level view took it for a surface of the world and carried
it with the ego-motion: driving forward, it slid back across the beams behind the sensor
and stood there, decimetres away, in front of everything. The floor line of the next
nose-up event behind the robot lay beyond that view, not in front of it, and was kept.

A return nearer than any floor line can lie (``min_line_distance_m``) that keeps its range
on its beam while the sensor moves ``BODY_TRAVEL_M`` is the body, and the view knows
nothing there (:meth:`pvfilter.improved.memory.LevelMemory.forget`). The sensor moves a
near point across the beams by its own displacement (from where the run of the beam's
range began, not the sum of the steps: a standing robot's matches jitter by millimetres
a scan) plus the point's range times the turn. A surface of the world that near changes
its range on a beam as the sensor passes it or turns; one that runs along the travel
keeps it, and is taken for the body too while the sensor drives along it. No line can
be scored there (none lies nearer than ``min_line_distance_m``), but where the sensor
turns or drives off it, the view knows nothing of it until a level scan teaches it
again: a floor line that then settles in front of it is not new. A body farther out
than that (a mast 0.3 m behind a sensor whose nearest floor line lies 0.28 m off) is
carried as before: a floor line held through a turn in place keeps its range on its
beams too, and is no body.

Where a beam has returned the body scan after scan for ``BODY_HELD_SCANS`` scans and
``memory_timeout_s``, a part of the robot stands there for good (a mast, a frame), and
the view keeps what it knew of the world behind it: the body's returns teach it nothing
and are never new, and as the robot turns, the view's knowledge there turns with it onto
the beams beside it. Forgetting it, a mast whose two posts block the sectors 140-165
degrees either side behind a spinning 360° scanner wiped the view of every direction it
passed, and the floor line of a pitch event in the window between the posts fell where
the view knew nothing: it was never new. A surface of the world that is taken for the
body while the sensor drives along it lasts a scan or two there, or some tenths of a
second, and is forgotten as before: kept, the view held the world of before while the
wall stood in front of it, and the wall was new when the body left it.
"""

from __future__ import annotations

import numpy as np

from pvfilter.improved.motion import STILL, Motion

BODY_TRAVEL_M = 0.1  # m: a near return that keeps its range while the sensor moves this far
# is fixed to the sensor (a wall seen 60 deg off its normal changes its range by half the
# drive along the beam: 5 cm)
BODY_TOLERANCE_M = 0.03  # m: a return keeps its range within this of where its run began:
# about twice a scanner's range noise near the sensor, where the noise is least. The noise
# the line distances follow is measured where most returns lie, and is larger: taken as
# this tolerance, it let walls a few decimetres off keep their range as the sensor passed
# them, and those walls, forgotten, were new when they came back
BODY_HELD_SCANS = 3  # scans: a beam that returned the body in this many scans in a row,
# and for memory_timeout_s, is a part of the robot that stays there; a wall taken for the
# body as the sensor drove along it stayed two scans (5 beams of a wall 0.45 m off, a 2 Hz
# scanner)


class BodyBeams:
    """How long ago each beam returned the robot's body (sensor frame: the body does not
    move with the robot, so no gap or ego-motion changes it; a new sequence does)."""

    def __init__(self) -> None:
        self._since_s: np.ndarray | None = None  # per beam, s; None: no body seen yet
        self._fixed = _SensorFixed()
        self._runs: tuple[np.ndarray, np.ndarray] | None = None  # per beam: scans, s
        self.held_beams: np.ndarray | None = None  # what held() last gave

    def reset(self) -> None:
        """Forget the beams: a new sequence, or another scanner."""
        self._since_s = None
        self._fixed.clear()
        self._runs = None
        self.held_beams = None

    def held(self, body: np.ndarray | None, dt: float, hold_s: float) -> np.ndarray | None:
        """Take one scan's body beams (what :meth:`returning_body` gave; None: none), and
        give those that have returned the body scan after scan for ``BODY_HELD_SCANS``
        scans and ``hold_s`` seconds: a part of the robot that stays there (None: none;
        kept as :attr:`held_beams` until the next scan). ``dt``: time since the previous
        scan, s."""
        self.held_beams = None
        runs = self._runs
        if body is None or runs is None or runs[0].shape != body.shape:
            if body is None or not np.count_nonzero(body):
                self._runs = None  # no body: every run ends (the usual case)
                return None
            runs = self._runs = (np.zeros(body.shape, np.intp), np.zeros(body.shape))
        scans, seconds = runs
        scans += 1
        seconds += dt
        scans[~body] = 0
        seconds[~body] = 0.0
        held = (scans >= BODY_HELD_SCANS) & (seconds >= hold_s)
        if np.count_nonzero(held):
            self.held_beams = held
        return self.held_beams

    @property
    def tracking(self) -> bool:
        """Near returns have been seen: their beams are followed (else nothing is)."""
        return self._fixed.tracking

    def returning_body(
        self, near_m: np.ndarray, step: Motion, dt: float, memory_s: float
    ) -> np.ndarray | None:
        """The beams whose near return is the body: on a beam that kept a near return's
        range (within ``BODY_TOLERANCE_M``) while the sensor moved it by
        ``BODY_TRAVEL_M``, within ``memory_s``; None: none.

        Args:
            near_m: per beam, its return where nearer than any floor line can lie, m
                (NaN elsewhere).
            step: the sensor's motion since the previous scan.
            dt: time since the previous scan, s.
            memory_s: how long a beam found so is taken to return the body.
        """
        return self._fixed.update(near_m, step, dt, memory_s)

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
    """Per beam, the near range it keeps, and where the sensor stood (position and
    heading, in the frame of the first scan followed) when that run began; how long ago
    it showed a range fixed to the sensor."""

    def __init__(self) -> None:
        self.clear()

    def clear(self) -> None:
        """Follow nothing."""
        self._moved = STILL  # the first scan's frame -> the current one
        self._kept_m: np.ndarray | None = None  # per beam, m; NaN: no near return
        self._start: np.ndarray | None = None  # per beam, (x m, y m, heading rad)
        self._since_s: np.ndarray | None = None  # per beam, s since it showed the body

    @property
    def tracking(self) -> bool:
        """Near returns have been seen lately (see :attr:`BodyBeams.tracking`)."""
        return self._kept_m is not None

    def update(
        self, near_m: np.ndarray, step: Motion, dt: float, memory_s: float
    ) -> np.ndarray | None:
        """Take one scan's near returns (see :meth:`BodyBeams.returning_body`)."""
        near = ~np.isnan(near_m)
        if self._kept_m is None or self._kept_m.shape != near_m.shape:
            if not np.count_nonzero(near):
                return None  # nothing near: nothing to follow (the usual case)
            self._moved = STILL
            self._kept_m = np.full(near_m.shape, np.nan)
            self._start = np.zeros((len(near_m), 3))
            self._since_s = np.full(near_m.shape, np.inf)
        self._moved = self._moved.then(step)
        back = self._moved.inverse()  # the sensor's pose in the first scan's frame
        pose = np.array([back.tx_m, back.ty_m, back.theta_rad])
        kept, start, since = self._kept_m, self._start, self._since_s
        since += dt
        # a near return that left the range its run began with (NaN: no run) starts one
        restart = near & ~(np.abs(near_m - kept) <= BODY_TOLERANCE_M)
        kept[restart] = near_m[restart]
        start[restart] = pose
        kept[~near] = np.nan
        # how far the sensor moved a point at the beam's range since its run began
        moved_m = np.hypot(pose[0] - start[:, 0], pose[1] - start[:, 1])
        moved_m += near_m * np.abs(pose[2] - start[:, 2])  # NaN off the near beams
        since[moved_m >= BODY_TRAVEL_M] = 0.0  # (NaN compares False)
        body = near & (since <= memory_s)
        if not np.count_nonzero(body):
            if not np.count_nonzero(near) and not np.count_nonzero(since <= memory_s):
                self.clear()  # nothing near, no body lately: follow nothing
            return None
        return body
