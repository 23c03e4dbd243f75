"""Rerun recordings of runs: the 3D world, the labelled scans, the filter's decisions, plots.

``RerunLogger`` is the run sink (its twin is :class:`twsb_sim.sinks.NullSink`); the
``log_<thing>`` functions log one kind of data each; ``default_blueprint`` is the layout
the viewer opens with; ``add_recording_args`` and ``rerun_sink`` wire the ``twsb run``
flags (``--rrd`` and Rerun's own). Entity paths are in :mod:`twsb_sim.rerun_log.paths`.
"""

from twsb_sim.rerun_log import paths
from twsb_sim.rerun_log.annotations import (
    BeamDecision,
    beam_decisions,
    decision_annotation_context,
    label_annotation_context,
)
from twsb_sim.rerun_log.blueprint import default_blueprint
from twsb_sim.rerun_log.events import log_events, log_shove
from twsb_sim.rerun_log.geometry import log_house, log_robot_body, log_sensor_view_frame
from twsb_sim.rerun_log.logger import RerunLogger
from twsb_sim.rerun_log.plots import log_filter_series, log_robot_series, log_series_styles
from twsb_sim.rerun_log.recording import (
    APPLICATION_ID,
    add_recording_args,
    open_recording,
    rerun_sink,
    wants_recording,
)
from twsb_sim.rerun_log.robot import log_robot_poses, log_trajectory
from twsb_sim.rerun_log.scans import (
    log_clusters,
    log_filter_decisions,
    log_lidar_hits,
    log_sensor_labels,
)

__all__ = [
    "APPLICATION_ID",
    "BeamDecision",
    "RerunLogger",
    "add_recording_args",
    "beam_decisions",
    "decision_annotation_context",
    "default_blueprint",
    "label_annotation_context",
    "log_clusters",
    "log_events",
    "log_filter_decisions",
    "log_filter_series",
    "log_house",
    "log_lidar_hits",
    "log_robot_body",
    "log_robot_poses",
    "log_robot_series",
    "log_sensor_labels",
    "log_sensor_view_frame",
    "log_series_styles",
    "log_shove",
    "log_trajectory",
    "open_recording",
    "paths",
    "rerun_sink",
    "wants_recording",
]
