"""The improved filter: segment -> ego-motion -> level view -> detect -> remove.

A :class:`pvfilter.ScanFilter` like the paper's filter (``process(scan)``, ``reset()``; its
result an :class:`~pvfilter.improved.ImprovedResult`), built on the physics of a tilted scan
plane instead of the paper's per-scan heuristics. ``process`` also takes the robot's
pitch and roll where an IMU gives them (optional).

Robustness, as the paper's filter: empty and all-invalid scans give an empty result of
the same length; a stamp earlier than the previous one resets the history with a
:class:`pvfilter.StampWentBackWarning`; a change of beam count or angles starts the
level-view memory afresh (it is kept per beam).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from pvfilter.contract import check_attitude
from pvfilter.improved.beams import BeamLayout, indices
from pvfilter.improved.detection import detect_lines
from pvfilter.improved.imu import floor_points
from pvfilter.improved.memory import LevelMemory, free_space_gaps, new_points
from pvfilter.improved.motion import Motion, estimate_motion
from pvfilter.improved.params import ImprovedParams
from pvfilter.improved.result import ImprovedResult, removal
from pvfilter.improved.segmentation import segment_scan
from pvfilter.scan import Scan
from pvfilter.stamps import stamp_went_back


class ImprovedPitchVariationFilter:
    """A pitch-variation filter that holds up over whole pitch events, one scan per call.

    Args:
        params: the parameters; :class:`ImprovedParams` defaults when omitted.
    """

    def __init__(self, params: ImprovedParams | None = None) -> None:
        self.params = params if params is not None else ImprovedParams()
        self._memory = LevelMemory()
        self._layout: BeamLayout | None = None
        self._previous_points: np.ndarray | None = None  # for the next ego-motion fit
        self._previous_stamp: float | None = None
        self._motion = Motion()  # the last ego-motion: the next one's prior
        self._new_sequence = True

    def reset(self) -> None:
        """Forget the history: the next scan starts a new sequence."""
        self._new_sequence = True
        self._previous_stamp = None

    def process(
        self,
        scan: Scan,
        *,
        pitch_rad: float | None = None,
        roll_rad: float | None = None,
        pose_sensor_in_odom: ArrayLike | None = None,
    ) -> ImprovedResult:
        """Filter one scan; call once per scan, in time order.

        Args:
            scan: the scan at time t.
            pitch_rad: the robot's pitch from an IMU, rad, positive nose down (optional).
            roll_rad: its roll, rad, positive left side up (optional, 0 with a pitch).
            pose_sensor_in_odom: ignored for now (the ego-motion comes from the scans).

        Returns:
            The filtered scan, the removed-beam mask, per-beam scores, per-cluster records.
        """
        attitude = check_attitude(pitch_rad, roll_rad)
        params = self.params
        new_sequence, dt = self._start(scan)
        layout = self._layout
        # scan.valid_mask(), without its errstate guard: comparisons with NaN never warn
        valid = (scan.ranges >= scan.range_min) & (scan.ranges <= scan.range_max)
        ranges = np.where(valid, scan.ranges, np.nan)
        points = layout.points(ranges)
        beams = indices(valid)
        # segment: split lines across the direction of travel from what they touch
        segments = segment_scan(points.take(beams, axis=0), beams, params)
        # ego-motion, then the level view moved into this scan's frame
        motion, view = Motion(), None
        if not new_sequence:
            directions = np.full(len(scan), np.nan)
            directions[beams] = segments.directions
            motion = self._ego_motion(layout, points, directions, dt)
            view = self._memory.view(layout, scan.range_max, motion, params)
        # evidence: returns in previously free space, and the IMU's floor
        if view is not None:
            gaps = free_space_gaps(ranges, view.ranges, layout, params)
            new = new_points(gaps, ranges, params.free_margin_m, params.free_margin_rel)
        else:
            gaps, new = np.full(len(scan), np.nan), np.zeros(len(scan), dtype=bool)
        floor = None
        if attitude is not None:
            # near the predicted floor, and not where the level view saw structure (a
            # wall far ahead is hit just above the floor when the tilt is small)
            floor = np.zeros(len(scan), dtype=bool)
            floor[beams] = floor_points(segments.points, *attitude, params)
            floor &= ~(gaps <= params.imu_floor_tolerance_m)  # NaN (unknown) compares False
        # detect: score segments, check the tilted-plane geometry, extend the lines
        detection = detect_lines(scan, points, segments, new, floor, params, motion, new_sequence)
        # remember: the level view, and the points the next ego-motion fit may use
        hold = detection.candidates if params.hold_behind_lines else None
        self._memory.update(ranges, scan.ranges == np.inf, view, dt, params, hold)
        # the next ego-motion fit leaves out what may move; a copy, since the detection's
        # clusters hold ``points``
        moving = new | detection.floor_points | detection.candidates
        self._previous_points = np.where(moving[:, None], np.nan, points)
        self._motion = motion
        # remove: the beams of every detected segment become NaN
        return removal(detection)

    def _ego_motion(
        self, layout: BeamLayout, points: np.ndarray, directions: np.ndarray, dt: float
    ) -> Motion:
        if not self.params.ego_motion:
            return Motion()
        # a turn over half a revolution is no larger a search (and a long gap stays finite)
        turn = min(self.params.max_yaw_rate_rad_s * dt, math.pi)
        max_shift = min(math.ceil(turn / layout.increment) + 1, layout.count // 4)
        return estimate_motion(
            points,
            directions,
            self._previous_points,
            layout,
            max_shift,
            self.params.association_m,
            prior=self._motion,
        )

    def _start(self, scan: Scan) -> tuple[bool, float]:
        """Check stamp and beams: does the scan start a sequence, and the time step, s."""
        previous = self._previous_stamp
        if stamp_went_back(scan.stamp, previous, stacklevel=3):
            self._new_sequence = True
        self._previous_stamp = scan.stamp
        new_sequence = self._new_sequence or self._layout is None or not self._layout.fits(scan)
        self._new_sequence = False
        if self._layout is None or not self._layout.fits(scan):
            self._layout = BeamLayout.of(scan)
        if new_sequence:
            self._memory.reset()
            self._motion = Motion()
            return True, 0.0
        return False, scan.stamp - previous
