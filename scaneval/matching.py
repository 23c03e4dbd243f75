"""Scan matchers: point-to-point ICP, 2D NDT and the Hough Scan Matcher.

Every matcher aligns ``source`` onto ``target`` (both ``(n, 2)`` point sets, m) and returns
a :class:`MatchResult` whose pose ``T`` puts ``transform_points(source, T)`` on ``target``.
For two scans of a moving sensor with the earlier scan as target, ``T`` is the later
sensor pose in the earlier sensor frame. Non-finite rows of either set are ignored. All
three report the same fitness (see :mod:`scaneval.match_result`), so results compare
across matchers.
"""

from __future__ import annotations

from collections.abc import Callable

from scaneval.hsm import hsm
from scaneval.icp import icp, rigid_fit
from scaneval.match_result import MatchResult, finite_points
from scaneval.ndt import ndt

MATCHERS: dict[str, Callable[..., MatchResult]] = {"icp": icp, "ndt": ndt, "hsm": hsm}

__all__ = ["MATCHERS", "MatchResult", "finite_points", "hsm", "icp", "ndt", "rigid_fit"]
