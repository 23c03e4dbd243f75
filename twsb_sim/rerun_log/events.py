"""Scenario events: phases, shoves and falls as text logs; shoves as arrows in the world.

Events fall between frames: each is logged at its exact ``sim_time`` and, on ``frame``,
at the first frame that follows it.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numpy as np
import rerun as rr

from twsb_sim.frame import RobotTruth
from twsb_sim.rerun_log import paths
from twsb_sim.rerun_log.timelines import frame_times, set_time
from twsb_sim.timeline import Shove, heading_force_to_world

SHOVE_ARROW_M_PER_N = 0.02  # a 40 N push draws a 0.8 m arrow
SHOVE_ARROW_RADIUS_M = 0.02
SHOVE_COLOR = (255, 60, 60)


def event_level(text: str) -> str:
    """The text-log level of a run event ("phase: ...", "shove: ...", "fell: ...")."""
    if text.startswith("fell"):
        return rr.TextLogLevel.ERROR
    if text.startswith("shove"):
        return rr.TextLogLevel.WARN
    return rr.TextLogLevel.INFO


def log_events(
    rec: rr.RecordingStream, times_s: Sequence[float], frames: Sequence[int], texts: Sequence[str]
) -> None:
    """Lines of the ``events`` text log, each at its time and frame."""
    rec.send_columns(
        paths.EVENTS,
        indexes=frame_times(times_s, frames),
        columns=rr.TextLog.columns(text=texts, level=[event_level(text) for text in texts]),
    )


def shove_in_world(shove: Shove, truth: RobotTruth) -> tuple[np.ndarray, np.ndarray]:
    """Where a scenario's shove pushes (m) and with what force (N), world frame, now."""
    rotation = np.empty(9)
    mujoco.mju_quat2Mat(rotation, truth.quat_base_in_world)
    point = truth.position_base_in_world + rotation.reshape(3, 3) @ np.array(shove.point_m)
    return point, heading_force_to_world(shove.force_n, truth.yaw_rad)


def log_shove(
    rec: rr.RecordingStream,
    start: tuple[float, int],
    end: tuple[float, int],
    point_world_m: np.ndarray,
    force_world_n: np.ndarray,
    label: str,
) -> None:
    """An arrow at the pushed point along the force, shown while the shove acts.

    Args:
        rec: the recording.
        start: (sim time s, frame index) at which the shove starts.
        end: (sim time s, frame index) at which it ends; the frame index should be
            after the start's so that the arrow shows on the ``frame`` timeline too.
        point_world_m: where the force acts, world frame, m.
        force_world_n: the force, world frame, N.
        label: shown beside the arrow.
    """
    set_time(rec, *start)
    rec.log(
        paths.SHOVES,
        rr.Arrows3D(
            origins=[point_world_m - force_world_n * SHOVE_ARROW_M_PER_N],  # the arrow ends at it
            vectors=[force_world_n * SHOVE_ARROW_M_PER_N],
            colors=[SHOVE_COLOR],
            radii=[SHOVE_ARROW_RADIUS_M],
            labels=[label],
            show_labels=True,
        ),
    )
    set_time(rec, *end)
    rec.log(paths.SHOVES, rr.Clear(recursive=False))
