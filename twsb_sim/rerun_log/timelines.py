"""The two timelines of a recording: ``sim_time`` (duration, s) and ``frame`` (sequence).

Frames are logged on both. Robot-state samples between frames are logged on ``sim_time``
only. Events fall between frames: they are logged at their exact ``sim_time`` and, on
``frame``, at the first frame that follows them.
"""

from __future__ import annotations

from collections.abc import Sequence

import rerun as rr

SIM_TIME = "sim_time"
FRAME = "frame"

Times = Sequence[rr.TimeColumn]  # the index columns of a batch, one row per sample


def frame_times(stamps_s: Sequence[float], indices: Sequence[int]) -> list[rr.TimeColumn]:
    """Both timelines, one row per frame."""
    return [rr.TimeColumn(SIM_TIME, duration=stamps_s), rr.TimeColumn(FRAME, sequence=indices)]


def sim_times(stamps_s: Sequence[float]) -> list[rr.TimeColumn]:
    """``sim_time`` only, one row per sample."""
    return [rr.TimeColumn(SIM_TIME, duration=stamps_s)]


def set_time(rec: rr.RecordingStream, t_s: float, frame_index: int) -> None:
    """Put the stream's clock (for ``rec.log``) at ``t_s`` and at a frame."""
    rec.set_time(SIM_TIME, duration=t_s)
    rec.set_time(FRAME, sequence=frame_index)
