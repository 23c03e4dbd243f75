"""The robot in the 3D world over time: the pose of its base and its trajectory.

Samples come from the frames (10 Hz, logged on both timelines) and, when the run loop
provides them, from the state hook (e.g. 50 Hz, logged on ``sim_time`` only).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import rerun as rr

from twsb_sim.frame import RobotTruth
from twsb_sim.rerun_log import paths
from twsb_sim.rerun_log.timelines import Times

TRAJECTORY_COLOR = (255, 255, 255)
TRAJECTORY_RADIUS_UI = -1.5


def log_robot_poses(rec: rr.RecordingStream, times: Times, truths: Sequence[RobotTruth]) -> None:
    """The base frame's pose in the world (``world/robot``), one row per sample."""
    quats_wxyz = np.array([t.quat_base_in_world for t in truths])
    rec.send_columns(
        paths.ROBOT,
        indexes=times,
        columns=rr.Transform3D.columns(
            translation=np.array([t.position_base_in_world for t in truths]),
            quaternion=np.roll(quats_wxyz, -1, axis=1),  # to xyzw
        ),
    )


def log_trajectory_style(rec: rr.RecordingStream) -> None:
    """The trajectory's colour and width, once (static)."""
    rec.log(
        paths.TRAJECTORY,
        rr.LineStrips3D.from_fields(colors=[TRAJECTORY_COLOR], radii=TRAJECTORY_RADIUS_UI),
        static=True,
    )


def log_trajectory(rec: rr.RecordingStream, times: Times, segments: np.ndarray) -> None:
    """Trajectory segments on the floor, one per sample (the blueprint shows all so far).

    Args:
        rec: the recording.
        times: one time per segment.
        segments: ``(k, 2, 3)`` start and end points, m, world frame.
    """
    rec.send_columns(
        paths.TRAJECTORY,
        indexes=times,
        columns=rr.LineStrips3D.columns(strips=segments),
    )
