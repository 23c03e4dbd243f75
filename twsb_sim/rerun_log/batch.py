"""A batch of consecutive frames as stacked arrays, so each logger works on all at once.

The frames of a batch have the same number of beams (the logger starts a new batch when
it changes), so per-beam quantities stack into ``(frames, beams)`` arrays and every
``log_<thing>`` is a few array operations, not a loop over frames.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import rerun as rr

from pvfilter import Scan
from twsb_sim.frame import Frame
from twsb_sim.rerun_log.timelines import frame_times


@functools.lru_cache(maxsize=8)
def _unit_vectors(angle_min: float, angle_increment: float, n: int) -> np.ndarray:
    angles = angle_min + np.arange(n, dtype=np.float64) * angle_increment
    return np.column_stack((np.cos(angles), np.sin(angles)))


def _sensor_points(scans: list[Scan], ranges: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``Scan.points()`` and ``Scan.valid_mask()`` of every scan, ``(K, n, 2)`` and ``(K, n)``.

    Scans of a batch share their beam geometry, so the beam directions are computed once.
    """
    first = scans[0]
    same = all(
        (s.angle_min, s.angle_increment, s.range_min, s.range_max)
        == (first.angle_min, first.angle_increment, first.range_min, first.range_max)
        for s in scans
    )
    if not same:  # beam geometry changed within the batch: scan by scan
        points = np.stack([s.points() for s in scans]).astype(np.float32)
        return points, ~np.isnan(points[:, :, 0])
    with np.errstate(invalid="ignore"):
        valid = (ranges >= first.range_min) & (ranges <= first.range_max)
    directions = _unit_vectors(first.angle_min, first.angle_increment, ranges.shape[1])
    points = np.where(valid, ranges, np.nan)[:, :, None] * directions
    return points.astype(np.float32), valid  # Rerun stores float32: convert once, here


@dataclass(frozen=True, eq=False)
class FrameBatch:
    """Consecutive frames and their filter results, placed on the timelines.

    Attributes:
        stamps_s: ``(K,)`` each frame's time on ``sim_time`` (s).
        indices: ``(K,)`` each frame's index on ``frame``.
        frames: the frames.
        results: the filter's result per frame, None where no filter ran.
        ranges: ``(K, n)`` the scans' ranges (m, REP-117).
        labels: ``(K, n)`` ground-truth labels.
        points: ``(K, n, 2)`` float32, every beam's sensor-frame point (m), NaN where invalid.
        valid: ``(K, n)`` the beams with a valid return (what the sensor view shows).
    """

    stamps_s: np.ndarray
    indices: np.ndarray
    frames: list[Frame]
    results: list[Any | None]
    ranges: np.ndarray
    labels: np.ndarray
    points: np.ndarray
    valid: np.ndarray

    @classmethod
    def of(
        cls,
        frames: Sequence[Frame],
        results: Sequence[Any | None],
        t0_s: float = 0.0,
        frame0: int = 0,
    ) -> FrameBatch:
        """A batch whose frames sit at ``t0_s + stamp`` and ``frame0 + index``."""
        ranges = np.stack([f.scan.ranges for f in frames])
        points, valid = _sensor_points([f.scan for f in frames], ranges)
        return cls(
            stamps_s=t0_s + np.array([f.stamp_s for f in frames]),
            indices=frame0 + np.array([f.index for f in frames], dtype=np.int64),
            frames=list(frames),
            results=list(results),
            ranges=ranges,
            labels=np.stack([f.labels for f in frames]),
            points=points,
            valid=valid,
        )

    def __len__(self) -> int:
        return len(self.frames)

    @functools.cached_property
    def times(self) -> list[rr.TimeColumn]:
        """Both timelines, one row per frame."""
        return frame_times(self.stamps_s, self.indices)

    def directions(self) -> np.ndarray:
        """``(K, n, 2)``: each beam's unit vector in the sensor frame (cached per beam
        geometry: the scans of a run share theirs)."""
        scans = [frame.scan for frame in self.frames]
        return np.stack([_unit_vectors(s.angle_min, s.angle_increment, len(s)) for s in scans])

    def stack(self, name: str, dtype: type | None = None) -> np.ndarray:
        """One attribute of every filter result, stacked (e.g. ``removed``: ``(K, n)``)."""
        stacks = self.__dict__.setdefault("_stacks", {})  # several loggers ask for the same
        if (name, dtype) not in stacks:
            stacks[name, dtype] = np.stack(
                [np.asarray(getattr(r, name), dtype=dtype) for r in self.results]
            )
        return stacks[name, dtype]

    def subset(self, keep: list[int]) -> FrameBatch:
        """The frames at positions ``keep``."""
        if len(keep) == len(self):  # positions are ascending: all of them
            return self
        return FrameBatch(
            stamps_s=self.stamps_s[keep],
            indices=self.indices[keep],
            frames=[self.frames[i] for i in keep],
            results=[self.results[i] for i in keep],
            ranges=self.ranges[keep],
            labels=self.labels[keep],
            points=self.points[keep],
            valid=self.valid[keep],
        )

    def with_results(self, has: str = "removed") -> FrameBatch:
        """The frames whose filter result has the attribute ``has``."""
        return self.subset([i for i, r in enumerate(self.results) if hasattr(r, has)])

    def with_clusters(self) -> FrameBatch:
        """The frames whose filter result has clusters (``result.cluster_view()``)."""
        views = [getattr(r, "cluster_view", lambda: None)() for r in self.results]
        return self.subset([i for i, view in enumerate(views) if view is not None])

    def without_results(self, has: str = "removed") -> FrameBatch:
        """The other frames."""
        return self.subset([i for i, r in enumerate(self.results) if not hasattr(r, has)])
