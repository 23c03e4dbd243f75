"""2D Normal Distributions Transform scan matching (Biber and Strasser 2003)."""

from __future__ import annotations

from numpy.typing import ArrayLike

from scaneval.match_result import MatchResult


def ndt(
    source_xy: ArrayLike,
    target_xy: ArrayLike,
    initial_pose: ArrayLike = (0.0, 0.0, 0.0),
    cell_size_m: float = 0.5,
    max_iterations: int = 50,
    tolerance: float = 1e-6,
    max_correspondence_m: float = 1.0,
) -> MatchResult:
    """2D NDT (not implemented yet)."""
    raise NotImplementedError("ndt: coming next")
