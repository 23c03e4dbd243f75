"""The Hough Scan Matcher (Censi, Iocchi and Grisetti 2005)."""

from __future__ import annotations

import math

from numpy.typing import ArrayLike

from scaneval.match_result import MatchResult


def hsm(
    source_xy: ArrayLike,
    target_xy: ArrayLike,
    angle_resolution_rad: float = math.radians(0.5),
    rho_resolution_m: float = 0.02,
    max_translation_m: float = 1.0,
    max_correspondence_m: float = 1.0,
) -> MatchResult:
    """Hough Scan Matcher (not implemented yet)."""
    raise NotImplementedError("hsm: coming next")
