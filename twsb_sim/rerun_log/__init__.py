"""Rerun recordings of runs: the 3D world, the labelled scans, the filter's decisions, plots.

``RerunLogger`` is the run sink (its twin is :class:`twsb_sim.sinks.NullSink`); the
``log_<thing>`` functions log one kind of data each; ``default_blueprint`` is the layout
the viewer opens with; ``add_recording_args`` and ``rerun_sink`` wire the ``twsb run``
flags (``--rrd`` and Rerun's own). Entity paths are in :mod:`twsb_sim.rerun_log.paths`.
Names load on first use, so the ``twsb`` command line starts without importing Rerun.
"""

from __future__ import annotations

from twsb_sim.lazy_exports import lazy_exports

_HOMES = {  # public name -> the module that holds it
    "paths": "paths",
    "BeamDecision": "annotations",
    "beam_decisions": "annotations",
    "decision_annotation_context": "annotations",
    "label_annotation_context": "annotations",
    "default_blueprint": "blueprint",
    "log_events": "events",
    "log_shove": "events",
    "log_house": "geometry",
    "log_robot_body": "geometry",
    "log_sensor_view_frame": "geometry",
    "RerunLogger": "logger",
    "log_filter_series": "plots",
    "log_robot_series": "plots",
    "log_series_styles": "plots",
    "APPLICATION_ID": "recording",
    "add_recording_args": "recording",
    "open_recording": "recording",
    "rerun_sink": "recording",
    "wants_recording": "recording",
    "log_robot_poses": "robot",
    "log_trajectory": "robot",
    "log_clusters": "scans",
    "log_filter_decisions": "scans",
    "log_level_view": "scans",
    "log_lidar_hits": "scans",
    "log_sensor_labels": "scans",
}
__getattr__, __all__ = lazy_exports(__name__, _HOMES)
