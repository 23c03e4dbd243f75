"""A scan filter run on simulated frames: each scan given the robot inputs the filter gets.

The simulation loop, the Gym env, the evaluation and the SLAM experiment all run filters
this way. By default a registered filter gets the robot inputs it needs, as the paper
fed its baselines: the DATMO-like tracker the sensor's true pose (the paper gave DATMO
SLAM poses), the IMU height gate the pitch and roll of the robot's IMU; the paper's and
the improved filter see the scans alone unless asked otherwise.
"""

from __future__ import annotations

import dataclasses
from typing import Any

from pvfilter import FilterResult, ScanFilter, filter_entry
from twsb_sim.frame import Frame
from twsb_sim.robot_inputs import robot_inputs


@dataclasses.dataclass(frozen=True, eq=False)
class FrameFilter:
    """A scan filter run on simulated frames.

    Attributes:
        label: the name reports show.
        scan_filter: the filter.
        inputs: the robot inputs it is given (:data:`pvfilter.ROBOT_INPUTS` names).
        truth_inputs: give them noise-free, from the truth, instead of from the robot's
            sensors (:func:`twsb_sim.robot_inputs.robot_inputs`).
    """

    label: str
    scan_filter: ScanFilter
    inputs: tuple[str, ...] = ()
    truth_inputs: bool = False

    def reset(self) -> None:
        """Forget the history (a new sequence starts)."""
        self.scan_filter.reset()

    def process(self, frame: Frame) -> FilterResult:
        """Filter the frame's scan, with the frame's robot inputs."""
        inputs = robot_inputs(frame, self.inputs, self.truth_inputs)
        return self.scan_filter.process(frame.scan, **inputs)


def as_frame_filter(scan_filter: ScanFilter | FrameFilter) -> FrameFilter:
    """A filter object as a :class:`FrameFilter` (scans only, unless it is one already)."""
    if isinstance(scan_filter, FrameFilter):
        return scan_filter
    return FrameFilter(type(scan_filter).__name__, scan_filter)


def frame_filter(
    name: str,
    label: str,
    params: Any = None,
    geometry: dict[str, float] | None = None,
    inputs: tuple[str, ...] | None = None,
    truth_inputs: bool = False,
    **fields: Any,
) -> FrameFilter:
    """A registered filter, ready for frames.

    Args:
        name: the registry name (``paper``, ``improved``, ``datmo``, ...).
        label: the name reports show.
        params: its parameters (defaults when None).
        geometry: the robot's ``lidar_height_m``, ``axle_height_m`` and ``lidar_ahead_m``, m.
        inputs: the robot inputs it is given; by default those it needs.
        truth_inputs: give them noise-free (see :class:`FrameFilter`).
        **fields: parameter values that replace those of ``params``.
    """
    entry = filter_entry(name)
    scan_filter = entry.make(params, robot_geometry=geometry, **fields)
    inputs = entry.needs if inputs is None else inputs
    return FrameFilter(label, scan_filter, inputs, truth_inputs)
