"""The two timelines of a recording: ``sim_time`` (duration, s) and ``frame`` (sequence).

Frames are logged on both. Robot-state samples between frames are logged on ``sim_time``
only. Events fall between frames: they are logged at their exact ``sim_time`` and, on
``frame``, at the first frame that follows them.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import rerun as rr

SIM_TIME = "sim_time"
FRAME = "frame"

Times = Sequence[rr.TimeColumn]  # the index columns of a batch, one row per sample


def nanoseconds(stamps_s: Sequence[float] | np.ndarray) -> np.ndarray:
    """Seconds as ``timedelta64[ns]``, rounded: the same instant gets the same time everywhere."""
    return np.round(np.asarray(stamps_s, dtype=np.float64) * 1e9).astype("timedelta64[ns]")


def frame_times(stamps_s: Sequence[float], indices: Sequence[int]) -> list[rr.TimeColumn]:
    """Both timelines, one row per frame."""
    return [
        rr.TimeColumn(SIM_TIME, duration=nanoseconds(stamps_s)),
        rr.TimeColumn(FRAME, sequence=np.asarray(indices, dtype=np.int64)),
    ]


def sim_times(stamps_s: Sequence[float]) -> list[rr.TimeColumn]:
    """``sim_time`` only, one row per sample."""
    return [rr.TimeColumn(SIM_TIME, duration=nanoseconds(stamps_s))]


def set_time(rec: rr.RecordingStream, t_s: float, frame_index: int) -> None:
    """Put the stream's clock (for ``rec.log``) at ``t_s`` and at a frame."""
    rec.set_time(SIM_TIME, duration=nanoseconds([t_s])[0])
    rec.set_time(FRAME, sequence=frame_index)
