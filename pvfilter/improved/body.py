"""The robot's own body in the scan: beams that return it now and then.

A body at the edge of ``range_min`` (a wheel, the frame in the blocked sector) reads now
nearer than any floor line can lie, now too close, and drivers that write too close as no
echo (``0.0``, ``+inf``) make those beams silent: space seen free, to the level view.
Freed, that space was carried by the turns onto the walls beside the sector, and they were
new (60 beams of one scan removed on a synthetic room). A silent beam that returned the
body within ``memory_timeout_s`` reads it again, out of range: it is unmeasured, not silent.
"""

from __future__ import annotations

import numpy as np


class BodyBeams:
    """How long ago each beam returned the robot's body (sensor frame: the body does not
    move with the robot, so no gap or ego-motion changes it; a new sequence does)."""

    def __init__(self) -> None:
        self._since_s: np.ndarray | None = None  # per beam, s; None: no body seen yet

    def reset(self) -> None:
        """Forget the beams: a new sequence, or another scanner."""
        self._since_s = None

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
