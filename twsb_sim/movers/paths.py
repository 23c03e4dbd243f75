"""Where a walker is at any time: a polyline walked at one speed, with stops and turns.

A :class:`WalkPath` starts at its first waypoint and stands there until ``start_s``; then
it walks from waypoint to waypoint at ``speed_mps``, and at every waypoint it reaches it
stands for ``stand_s``, turning on the spot towards the next leg at ``turn_rate_rad_s``
(it stands as long as the turn takes, if that is longer). With ``back_and_forth`` it walks
the path back again at the end, forever; otherwise it stays at the last waypoint.
:meth:`WalkPath.at` is evaluated once per LiDAR scan, so it is plain scalar arithmetic
over a precomputed timeline.
"""

from __future__ import annotations

import bisect
import itertools
import math
from dataclasses import dataclass, field
from typing import NamedTuple

MIN_LEG_M = 1e-6  # m, legs shorter than this are dropped


class WalkState(NamedTuple):
    """A walker at one instant (world frame)."""

    x_m: float
    y_m: float
    heading_rad: float  # direction the walker faces, CCW from world x
    walked_m: float  # distance walked since the start (drives the gait)
    speed_mps: float  # 0 while standing or turning


def _turn(start: float, goal: float, rate: float, t: float) -> float:
    """Heading ``t`` s into a turn on the spot from ``start`` towards ``goal`` at ``rate``."""
    delta = math.remainder(goal - start, math.tau)
    turn_s = abs(delta) / rate
    if turn_s <= 0.0 or t >= turn_s:
        return start + delta
    return start + delta * t / turn_s


@dataclass(frozen=True)
class WalkPath:
    """A polyline walked at one speed (world frame, m, s).

    Attributes:
        waypoints: at least two ``(x_m, y_m)`` points.
        speed_mps: walking speed.
        start_s: when the walker leaves the first waypoint (it stands there until then).
        stand_s: how long it stands (and turns) at each waypoint it reaches.
        back_and_forth: walk the path back at the end, forever.
        turn_rate_rad_s: how fast it turns on the spot.
    """

    waypoints: tuple[tuple[float, float], ...]
    speed_mps: float
    start_s: float = 0.0
    stand_s: float = 0.0
    back_and_forth: bool = True
    turn_rate_rad_s: float = 2.0
    _legs: tuple = field(init=False, repr=False, compare=False)
    _starts: tuple = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if len(self.waypoints) < 2:
            raise ValueError(f"waypoints: expected at least 2 points, got {len(self.waypoints)}")
        if not 0.0 < self.speed_mps <= 5.0:
            raise ValueError(f"speed_mps: expected 0 to 5 m/s, got {self.speed_mps}")
        if self.start_s < 0.0 or self.stand_s < 0.0:
            raise ValueError("start_s, stand_s: expected times >= 0 s")
        if self.turn_rate_rad_s <= 0.0:
            raise ValueError(f"turn_rate_rad_s: expected > 0 rad/s, got {self.turn_rate_rad_s}")
        points = list(self.waypoints)
        if self.back_and_forth:
            points += points[-2::-1]
        legs = []  # (t0, walk_s, x0, y0, dx, dy, heading, walked0, stand_s, next_heading)
        t, walked = 0.0, 0.0
        pairs = [(a, b) for a, b in itertools.pairwise(points) if math.dist(a, b) > MIN_LEG_M]
        if not pairs:
            raise ValueError("waypoints: the path has no length")
        headings = [math.atan2(b[1] - a[1], b[0] - a[0]) for a, b in pairs]
        for k, (a, b) in enumerate(pairs):
            length = math.dist(a, b)
            walk_s = length / self.speed_mps
            if k + 1 < len(pairs):
                following = headings[k + 1]
            else:  # the end: turn round to walk it again, or stay facing on
                following = headings[0] if self.back_and_forth else headings[k]
            # it stands long enough to turn towards the next leg at its turn rate
            turn_s = abs(math.remainder(following - headings[k], math.tau)) / self.turn_rate_rad_s
            stand_s = max(self.stand_s, turn_s)
            legs.append((t, walk_s, a[0], a[1], b[0] - a[0], b[1] - a[1], headings[k], walked,
                         stand_s, following))  # fmt: skip
            t += walk_s + stand_s
            walked += length
        object.__setattr__(self, "_legs", tuple(legs))
        object.__setattr__(self, "_starts", tuple(leg[0] for leg in legs))

    @property
    def cycle_s(self) -> float:
        """Duration of one pass over the legs (s): forth and back with ``back_and_forth``."""
        last = self._legs[-1]
        return last[0] + last[1] + last[8]

    @property
    def cycle_m(self) -> float:
        """Distance walked in one cycle (m)."""
        last = self._legs[-1]
        return last[7] + math.hypot(last[4], last[5])

    def at(self, t_s: float) -> WalkState:
        """Where the walker is at time ``t_s`` (s of simulated time)."""
        legs = self._legs
        if t_s <= self.start_s:
            x0, y0, heading = legs[0][2], legs[0][3], legs[0][6]
            return WalkState(x0, y0, heading, 0.0, 0.0)
        t = t_s - self.start_s
        laps = 0
        if self.back_and_forth:
            laps, t = divmod(t, self.cycle_s)
        elif t >= self.cycle_s:
            last = legs[-1]
            return WalkState(last[2] + last[4], last[3] + last[5], last[6], self.cycle_m, 0.0)
        k = max(bisect.bisect_right(self._starts, t) - 1, 0)
        t0, walk_s, x0, y0, dx, dy, heading, walked0, _, following = legs[k]
        base = laps * self.cycle_m + walked0
        u = t - t0
        if u < walk_s:
            f = u / walk_s
            return WalkState(x0 + f * dx, y0 + f * dy, heading, base + f * walk_s * self.speed_mps,
                             self.speed_mps)  # fmt: skip
        turned = _turn(heading, following, self.turn_rate_rad_s, u - walk_s)
        return WalkState(x0 + dx, y0 + dy, turned, base + math.hypot(dx, dy), 0.0)
