"""The improved filter: segment -> ego-motion -> level view (re-anchored) -> detect -> remove.

A :class:`pvfilter.ScanFilter` like the paper's filter (``process(scan)``, ``reset()``; its
result an :class:`~pvfilter.improved.ImprovedResult`), built on the physics of a tilted scan
plane instead of the paper's per-scan heuristics. ``process`` also takes what a TWSB robot
has anyway, each optional: the attitude from its IMU estimator, and the LiDAR's pose from
wheel odometry (the ego-motion's prior).

Robustness: empty and all-invalid scans give an empty result of the same length; a stamp
earlier than the previous one resets the history with a
:class:`pvfilter.StampWentBackWarning`; a change of beam count or angles, a time gap over
``max_gap_s`` and a motion the filter cannot trust start the level view afresh
(**re-baseline**), and the scan that does so loses no beam.
"""

from __future__ import annotations

import dataclasses
import math
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from pvfilter.contract import check_attitude, check_pose, check_scan, params_or_defaults
from pvfilter.improved.anchor import (
    REFINE_ASSOCIATION_M,
    explains_both_ends,
    explains_view_error,
    offset_along_x,
    register_view,
    within_margin,
)
from pvfilter.improved.beams import BeamLayout, indices, row_norms
from pvfilter.improved.body import BodyBeams
from pvfilter.improved.detection import LineDetection, detect_lines
from pvfilter.improved.doubt import WEAK_ROWS, ViewDoubt
from pvfilter.improved.egomotion import MAX_SPEED_MPS, SEEN, EgoMotion, Match
from pvfilter.improved.evidence import (
    STATIC_FAR_BASELINE_S,
    STATIC_TOLERANCE_M,
    Earlier,
    RecentScans,
    WorldStatic,
    free_space_evidence,
    free_space_gaps,
)
from pvfilter.improved.follow import FloorFollower, LinePlace, travelling_line
from pvfilter.improved.imu import Attitude, AttitudeTrack
from pvfilter.improved.memory import LevelMemory, LevelView
from pvfilter.improved.motion import MIN_PAIRS, Motion
from pvfilter.improved.noise import RangeNoise
from pvfilter.improved.params import ImprovedParams
from pvfilter.improved.result import ImprovedResult, removal
from pvfilter.improved.roll import RollBound
from pvfilter.improved.scoring import line_pitch, strongest_confident
from pvfilter.improved.segmentation import Segments, segment_scan
from pvfilter.improved.sweep import deskew, unstretch
from pvfilter.scan import Scan
from pvfilter.stamps import GapWatch, stamp_went_back

STATIC_BASELINE_S = 0.3  # s: the world-static test compares with the scan this long ago
SAME_INSTANT_S = 1e-9  # s: stamps closer than this are one instant (no scanner stamps
# scans a nanosecond apart; a rate over a shorter step overflows)


def blind_margin_m(coasted_s: float) -> float:
    """How far the level view can be off after coasting ``coasted_s`` seconds on the
    constant-velocity guess, m: the robot drove anywhere from standing to flat out
    (``MAX_SPEED_MPS``) meanwhile. A return is new in a blind scan only this much (plus
    the usual margin) in front of the view: a floor line of a hard stop lies metres in
    front of the wall behind it, and a wall the guess left off stays within it."""
    return MAX_SPEED_MPS * coasted_s


class _Prepared(NamedTuple):
    """One scan as the stages take it (a named tuple, as :class:`_Found`: made every
    scan, for a quarter of a frozen dataclass's cost).

    Attributes:
        scan: the scan.
        ranges: its ranges, NaN where invalid, m.
        near: per beam, its return lies nearer than any floor line can: the robot's own
            body, or something touching it.
        no_echo: per beam, it returned nothing within range (``+inf``).
        points: its points per beam, sensor frame, m, ``(n, 2)`` (NaN where invalid).
        segments: its segments.
        directions: each return's local line direction, rad (NaN: none).
        mid_points: its points in the mid-scan frame (deskewed with ``velocity``), m.
        velocity: the prior's motion per second.
        dt: the time since the previous scan, s.
        pose: the odometry pose, the prior's (None: no odometry, no pose at the scan
            before, or the wheels slipped: :meth:`EgoMotion.plausible_pose`).
        wheel_pose: the odometry pose as given (None: no odometry): the next scan's step
            starts from it, slipped or not.
        slipped: the odometry's step to this scan is one no robot of this class makes.
        attitude: the IMU's attitude (None: no IMU).
    """

    scan: Scan
    ranges: np.ndarray
    near: np.ndarray
    no_echo: np.ndarray
    points: np.ndarray
    segments: Segments
    directions: np.ndarray
    mid_points: np.ndarray
    velocity: Motion
    dt: float
    pose: np.ndarray | None
    wheel_pose: np.ndarray | None
    slipped: bool
    attitude: Attitude | None


@dataclasses.dataclass(frozen=True)
class _MatchOutcome:
    """How a scan's motion was found.

    Attributes:
        match: the ego-motion (its step the prior's where the scan coasts).
        fresh: the filter starts afresh at this scan (a re-baseline).
        coast: the match failed and the prior carries the motion.
        onset: the match failed on a level scan (without odometry, or on odometry that
            has proven itself): the scan coasts if it shows a pitch event (a strong
            candidate line), else the filter re-baselines.
        travel_seen: the step's drive was measured in every direction: by the wheels, or
            by a trusted match with support along all of them (not a guess coasted on).
        wheels_slipped: the odometry's step disagreed with both the match made without
            it and the velocity before; the match carries the motion
            (:meth:`~pvfilter.improved.egomotion.EgoMotion.wheels_slipped`).
        wheels: the wheel odometry measured the motion since the reference, every
            coasted step included (a step without a pose, or before the first, was a
            guess).
    """

    match: Match
    fresh: bool = False
    coast: bool = False
    onset: bool = False
    travel_seen: bool = True
    wheels_slipped: bool = False
    wheels: bool = False


_AFRESH = _MatchOutcome(Match(Motion(), True), fresh=True)


class _Found(NamedTuple):
    """What comparing a scan with the level view and detecting its lines found."""

    detection: LineDetection
    new: np.ndarray  # bool per beam: in front of the level view
    view: LevelView | None  # the level view in this scan's frame
    level_ranges: np.ndarray  # the scan's ranges, mid-scan and unstretched, m
    back: np.ndarray | None  # bool per beam: a surface the view gave up is back (None: none)
    static: WorldStatic | None  # the world-static test against an earlier scan (None: none)


class ImprovedPitchVariationFilter:
    """A pitch-variation filter that holds up over whole pitch events, one scan per call.

    Args:
        params: the parameters; :class:`ImprovedParams` defaults when omitted.
    """

    def __init__(self, params: ImprovedParams | None = None) -> None:
        self.params = params_or_defaults(params, ImprovedParams, "ImprovedPitchVariationFilter")
        self._memory = LevelMemory()
        self._ego = EgoMotion(self.params)
        self._layout: BeamLayout | None = None
        self._noise = RangeNoise()  # the scanner's range noise, measured on its scans
        self._spacing_params = self.params  # the point counts for the scan's beam spacing,
        # and the line distances for the scanner's range noise
        self._roll = RollBound(self.params)
        self._line_params = self.params  # and the roll its confident lines measured
        self._segment_params = self.params  # and the lean that roll gives a floor line
        self._previous_stamp: float | None = None
        self._recent = RecentScans(STATIC_BASELINE_S, STATIC_FAR_BASELINE_S)
        self._attitude = AttitudeTrack(self.params)
        self._follower = FloorFollower(self.params)
        self._travelled: LinePlace | None = None  # the floor line last found travelling
        self._body = BodyBeams()
        self._doubt = ViewDoubt()
        self._tilted_s = 0.0  # how long the scans have been tilted without a break
        self._gaps = GapWatch()  # scans too far apart, in a row
        self._new_sequence = True

    @property
    def roll_bound_deg(self) -> float:
        """The roll the lean gates allow now, deg: ``max_roll_deg``, or more where the
        scans' confident floor lines measured more (``learn_roll``,
        :mod:`pvfilter.improved.roll`)."""
        return self._line_params.max_roll_deg

    @property
    def range_noise_m(self) -> float:
        """The scanner's range noise the line distances follow now, m (NaN: not measured
        yet; :class:`~pvfilter.improved.noise.RangeNoise`,
        :meth:`ImprovedParams.for_range_noise`)."""
        return self._noise.noise_m

    def reset(self) -> None:
        """Forget the history, the scanner's measured range noise too: the next scan starts
        a new sequence, as for a new filter."""
        self._new_sequence = True
        self._previous_stamp = None
        self._gaps.reset()
        self._attitude.reset()
        self._roll.reset()
        self._body.reset()
        self._noise.reset()
        self._scanner_params()

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
            pitch_rad: the robot's pitch from its IMU estimator, rad, positive nose down
                (optional; noisy, lagging and biased estimates are expected).
            roll_rad: its roll, rad, positive left side up (optional, 0 with a pitch).
            pose_sensor_in_odom: the LiDAR's pose ``(x m, y m, yaw rad)`` in the odom frame
                from wheel odometry, at the scan's stamp (optional; it may slip).

        Returns:
            The filtered scan, the removed-beam mask, per-beam scores, the line detection.
        """
        check_scan(scan)
        checked = check_attitude(pitch_rad, roll_rad)
        pose = check_pose(pose_sensor_in_odom)
        fresh, dt = self._start(scan)
        attitude = self._attitude.update(checked, scan.stamp)
        prepared, prior = self._prepare(scan, dt, pose, attitude)
        odometry_prior = prepared.pose is not None  # the prior is the wheels' step
        outcome, prepared = self._match(prepared, prior, fresh, odometry_prior)
        if not outcome.fresh:  # the view's doubt along what the match could not see
            weak = SEEN if outcome.wheels else outcome.match.weak  # the wheels measure it
            span_s = prepared.dt + (0.0 if outcome.coast else self._ego.coasted_s)
            self._doubt.carry(outcome.match.step.theta_rad, weak, span_s)
        found = self._detect(prepared, outcome)
        if outcome.onset and not found.detection.tilted:
            # the match failed on a scan that shows no pitch event: start afresh after all
            self._rebaseline()
            outcome = _AFRESH
            found = self._detect(prepared, outcome)
        detection, line_params = found.detection, self._line_params
        # check the IMU's estimate against the scan's confident floor line, if any
        if attitude is not None:
            scores = detection.segment_scores
            guessed = outcome.fresh or (outcome.coast and not outcome.wheels)  # no view to trust
            confident = None if guessed else line_pitch(detection.segments, scores, line_params)
            self._attitude.check(confident, scores.imu_contradicted, scores.scan_down_side)
        self._learn_roll(detection, outcome)
        # remember: the level view (from level scans only), the scans to match and compare
        self._remember(prepared, found, outcome.coast)
        tilt = self._tilt(detection, attitude)
        if outcome.coast:
            self._ego.coasted_tilt(tilt)
        else:
            new_or_line = found.new | detection.candidates
            level = not _shows_tilt(detection.tilted, attitude)
            slipped = (
                prepared.slipped
                or outcome.wheels_slipped
                or self._ego.still_slipping(prepared.wheel_pose, dt, outcome.match)
            )
            self._ego.commit(
                prepared.mid_points, new_or_line, outcome.match, tilt, dt, pose, level, slipped
            )
        # remove: the beams whose claim score exceeds p_th become NaN
        return removal(detection)

    def _learn_roll(self, detection: LineDetection, outcome: _MatchOutcome) -> None:
        """Measure the plane's roll on the scan's confident floor line, if it has one."""
        if outcome.fresh or not self.params.learn_roll:
            return
        segments, scores = detection.segments, detection.segment_scores
        strongest = strongest_confident(segments, scores, self._line_params)
        if strongest is None:
            return
        self._roll.learn(segments.normals[strongest], float(scores.tilt_rad[strongest]))
        if self._roll.bound_deg != self._line_params.max_roll_deg:
            self._line_params = self._roll.applied(self._spacing_params)
            self._segment_params = self._roll.segmenting(self._spacing_params)

    def _prepare(
        self, scan: Scan, dt: float, pose: np.ndarray | None, attitude: Attitude | None
    ) -> tuple[_Prepared, tuple[Motion, tuple[float, float]]]:
        """The scan's valid returns, segments (in its own frame: a floor line moves with
        the sensor) and mid-scan points; and the ego-motion's prior."""
        layout = self._layout
        # beams that returned nothing (bridged in lines, free space in the level view):
        # a clamping scanner's range_max is no echo too, not a ring of points that turns
        # and drives with the sensor and pins the scan match to a robot standing still;
        # NaN too where the scanner writes it so (nan_is_no_echo; REP-117: invalid)
        no_echo = scan.no_echo_mask()
        if self.params.nan_is_no_echo:
            no_echo |= np.isnan(scan.ranges)
        # returns: scan.valid_mask() but the silent beams (comparisons with NaN never warn)
        valid = (scan.ranges >= scan.range_min) & (scan.ranges <= scan.range_max) & ~no_echo
        ranges = np.where(valid, scan.ranges, np.nan)
        # returns nearer than any floor line can lie are the robot's own body (a mast, a
        # wheel, the frame in the blocked sector) or something touching it
        near = ranges < self.params.min_line_distance_m  # NaN compares False
        silent_body = self._body.silent_body(near, no_echo, dt, self.params.memory_timeout_s)
        if silent_body is not None:  # the body again, too close: unmeasured (body.py)
            no_echo = no_echo & ~silent_body
        if self._noise.update(ranges):  # the scanner's range noise, measured on its scans
            self._scanner_params()
        points = layout.points(ranges)
        beams = indices(valid)
        segments = segment_scan(
            points.take(beams, axis=0),
            beams,
            layout.increment,
            self._segment_params,
            layout.ring,
            no_echo,
        )
        directions = np.empty(len(scan))
        directions.fill(np.nan)
        directions[beams] = segments.directions
        # the scan in its mid-scan frame, deskewed with the prior's velocity (an odometry
        # step no robot of this class can make is slip, and no prior)
        slipped = not self._ego.plausible_step(pose, dt)
        wheel_pose, pose = pose, self._ego.plausible_pose(pose, dt)
        prior = self._ego.prior(dt, pose)
        velocity = prior[0].scaled(1.0 / dt) if dt > 0.0 else Motion()
        mid_points = _mid_scan(points, layout, scan.time_increment, velocity, near)
        prepared = _Prepared(
            scan,
            ranges,
            near,
            no_echo,
            points,
            segments,
            directions,
            mid_points,
            velocity,
            dt,
            pose,
            wheel_pose,
            slipped,
            attitude,
        )
        return prepared, prior

    def _detect(self, prepared: _Prepared, outcome: _MatchOutcome) -> _Found:
        """Compare the scan with the level view and detect its lines."""
        scan, attitude = prepared.scan, prepared.attitude
        match = outcome.match
        # coasting on a constant velocity, the motion is a guess, off by as much as the
        # robot can drive in the time coasted: the scan is compared with the view within
        # that doubt; on the wheel odometry it is a measurement within its spread
        blind = outcome.coast and not outcome.wheels
        # evidence: returns in front of the level view, and returns that stayed put in
        # the world while the sensor moved
        level_ranges = match.ranges
        if level_ranges is None:
            level_ranges = row_norms(unstretch(prepared.mid_points, match.tilt_rad))
        # travel the scans may not have seen can leave the view off along x beyond the
        # re-anchoring's reach, unless the wheels measured it or the IMU shows the plane
        # tilted (a floor line then lies where a search would put a wall)
        unseen_travel = not outcome.wheels and not (attitude is not None and attitude.tilted)
        new, through, view, static, back = self._evidence(
            scan,
            prepared.ranges,
            prepared.no_echo,
            level_ranges,
            prepared.directions,
            match.step,
            prepared.velocity,
            outcome.fresh,
            blind,
            unseen_travel,
            outcome.travel_seen,
        )
        # the body's own returns where it stays (the scan before's beams: it is fixed to the
        # sensor) stand in front of the world the view keeps behind them: never new
        held_body = self._body.held_beams
        if held_body is not None:
            new = new & ~held_body
        # a floor line held through a turn in place keeps its place in the sensor frame
        held = self._follower.held(scan.stamp, self._recent.pose)
        # detect: score segments, claim the points on the lines, build the clusters
        detection = detect_lines(
            scan,
            prepared.points,
            prepared.segments,
            new,
            attitude,
            self._line_params,
            match.step,
            outcome.fresh,
            static,
            through,
            None if view is None else view.ranges,
            outcome.coast,
            held,
        )
        return _Found(detection, new, view, level_ranges, back, static)

    def _match(
        self,
        prepared: _Prepared,
        prior: tuple[Motion, tuple[float, float]],
        fresh: bool,
        wheels: bool,
    ) -> tuple[_MatchOutcome, _Prepared]:
        """The scan's ego-motion, and whether the filter starts afresh or coasts on the
        prior; and the scan as the later stages take it.

        A match that cannot be trusted lets the prior carry on until a scan matches again
        in a pitch event (the last scan was tilted), and on wheel odometry that has proven
        itself: the first tilted scan of an event fails its match before the filter
        knows the event began. Without odometry such a level scan coasts on the guess
        too. Either way it is an **onset**: if it shows no pitch event after all (no
        strong candidate line), the filter re-baselines and the scan removes nothing
        (a scanner blinded for seconds, pressed against a counter, coasted on the wheels
        through every scan and lost a pitch event among them). Otherwise an untrusted
        match re-baselines. ``wheels``: the prior is the wheel odometry's.
        A match that fails against the odometry is made again without it: where the
        wheels slipped (a shove spins one), it carries the motion instead of them, and the
        scan goes on as without odometry (deskewed with the velocity before).
        """
        if fresh:
            self._rebaseline()
            return _AFRESH, prepared
        pose, attitude, dt = prepared.pose, prepared.attitude, prepared.dt
        imu_tilt = None if attitude is None else attitude.tilt_rad
        match = self._ego.match(
            self._layout,
            prepared.mid_points,
            prepared.directions,
            dt,
            prior,
            wheels,
            imu_tilt,
            attitude is not None and attitude.tilted,
        )
        if match.trusted:
            seen = wheels or match.weak[0] >= WEAK_ROWS
            measured = wheels and self._ego.wheels_throughout
            return _MatchOutcome(match, travel_seen=seen, wheels=measured), prepared
        if wheels:  # the match failed against the wheels: did they slip?
            without = self._without_wheels(prepared)
            alone = self._ego.match(
                self._layout,
                without.mid_points,
                without.directions,
                dt,
                self._ego.prior(dt, None),
                False,
                imu_tilt,
                attitude is not None and attitude.tilted,
            )
            if self._ego.wheels_slipped(prior[0], prior[1], dt, alone):
                seen = alone.weak[0] >= WEAK_ROWS
                return _MatchOutcome(alone, travel_seen=seen, wheels_slipped=True), without
        in_event = 0.0 < self._tilted_s <= self.params.max_event_s
        known = self._ego.reference is not None
        # a level scan coasts only if it shows a pitch event after all (checked once
        # detected), on the guess or on wheels that have proven themselves: on wheels,
        # coasting through every failed match would take a blinded scanner's level scans
        # for tilted ones, and a pitch event among them would find no view to compare with
        trusted_prior = pose is None or self._ego.odometry_proven
        onset = self._tilted_s == 0.0 and known and trusted_prior
        if not (in_event or onset):
            self._rebaseline()
            return _AFRESH, prepared
        # the next step starts from the wheels' pose now, slipped or not: from None, the
        # next pose would pass unchecked, and a slip that lasts two scans would be taken in
        slipped = prepared.slipped or self._ego.slipped  # (no trusted match: still slipping)
        coasted = self._ego.coast(match, match.tilt_rad, dt, prepared.wheel_pose, slipped, wheels)
        measured = self._ego.wheels_throughout
        outcome = _MatchOutcome(
            coasted, coast=True, onset=onset, travel_seen=wheels, wheels=measured
        )
        return outcome, prepared

    def _without_wheels(self, prepared: _Prepared) -> _Prepared:
        """``prepared`` as without odometry: no pose, and its points deskewed with the
        velocity before (a slipped wheel's velocity, turning the sensor within the sweep,
        bends the scan it deskews)."""
        dt = prepared.dt
        velocity = self._ego.velocity if dt > 0.0 else Motion()  # (the prior without wheels)
        mid_points = _mid_scan(
            prepared.points, self._layout, prepared.scan.time_increment, velocity, prepared.near
        )
        return prepared._replace(mid_points=mid_points, velocity=velocity, pose=None)

    def _remember(self, prepared: _Prepared, found: _Found, coast: bool) -> None:
        """Teach the level view (from level scans only: a coasting scan is taken as tilted)
        and keep the scan for the world-static test."""
        scan, detection = prepared.scan, found.detection
        params = self.params
        was_in_event = 0.0 < self._tilted_s <= params.max_event_s
        tilted = detection.tilted or coast
        travelling = self._travelling(found, tilted, prepared.dt)
        level = self._level(tilted, prepared.dt, travelling is not None)
        # the doubt of a step into or out of a pitch event stays; after it the view comes
        # closer behind lines across the travel at line_shrink_mps plus the drive
        creep_m = 0.0  # (at once, dt 0: no time to come closer; inf * 0 is NaN)
        if prepared.dt > 0.0:
            creep_m = (params.line_shrink_mps + prepared.velocity.translation_m) * prepared.dt
        self._doubt.settle(was_in_event or not level, creep_m)
        hold = self._hold(detection)
        # the robot's own body is no surface of the world: its returns teach the view
        # nothing where it stays (body.py), and elsewhere the view knows nothing there
        body = None
        if self._body.tracking or np.count_nonzero(prepared.near):
            body = self._body.returning_body(
                np.where(prepared.near, prepared.ranges, np.nan),
                detection.motion,
                prepared.dt,
                params.memory_timeout_s,
            )
        held = self._body.held(body, prepared.dt, params.memory_timeout_s)
        ranges, no_echo = prepared.ranges, prepared.no_echo
        if held is not None:
            ranges = np.where(held, np.nan, ranges)  # (NaN: unmeasured, teaches nothing)
            no_echo = no_echo & ~held
        self._memory.update(
            ranges,
            no_echo,
            found.view,
            prepared.dt,
            self.params,
            level,
            hold,
            prepared.velocity,
            scan.time_increment,
            self._across(prepared.segments, len(scan)),
            found.back,
            scan.range_max,
            travelling,
        )
        if body is not None:  # where it stays, the world behind it is kept (free, or as
            # far as a floor line can lie: nearer, the body itself taught it before it was
            # found to be one)
            if held is not None:
                behind = self._memory.state.ranges >= params.min_line_distance_m
                body = body & ~(held & behind)  # (NaN, unknown, compares False)
            self._memory.forget(body)
        self._recent.add(scan.stamp, found.level_ranges)

    def _travelling(self, found: _Found, tilted: bool, dt: float) -> np.ndarray | None:
        """Per beam: on the scan's floor line that travels with the sensor (None: none, or
        not asked; :func:`~pvfilter.improved.follow.travelling_line`).

        Asked of a tilted scan past ``max_event_s``, where the scans would count as level
        again; and earlier, where a beam of the view would settle onto what stood in front
        of it that long (:func:`_settling`): a line whose beams came in front before the
        scans counted as tilted settles there first, and may no longer be confident when
        the scans' clock asks. Asked early only once the world-static test's earlier scan
        lies within the event: a line not in that scan at all left its place as a
        travelling one does. No verdict is carried past a scan that was not asked."""
        params, static = self.params, found.static
        asked = tilted and (
            self._tilted_s + dt > params.max_event_s
            or (
                static is not None
                and static.span_s + SAME_INSTANT_S < self._tilted_s + dt  # (after the
                # last level scan: the tilted clock started at its stamp)
                and _settling(found.view, dt, params.max_event_s)
            )
        )
        if not asked:
            self._travelled = None
            return None
        travelling, self._travelled = travelling_line(
            found.detection, static, self._line_params, self._travelled
        )
        return travelling

    def _across(self, segments: Segments, count: int) -> np.ndarray | None:
        """Per beam: it lies on a segment across the direction of travel with at least
        ``min_points`` points, where a floor line can lie (None: on none)."""
        lines = segments.across & (segments.sizes >= self._line_params.min_points)
        if not np.count_nonzero(lines):
            return None
        beams = np.zeros(count, dtype=bool)
        beams[segments.beams] = lines.take(segments.labels)
        return beams

    def _hold(self, detection: LineDetection) -> np.ndarray | None:
        """Per beam: the level view does not come closer there (None: nowhere): behind
        the scan's candidate lines, and behind segments that continue the floor line of a
        recent strong line (:mod:`pvfilter.improved.follow`)."""
        if not self.params.hold_behind_lines:
            return None
        hold = detection.candidates
        followed = self._follower.followed(detection, self._recent.pose)
        return hold if followed is None else hold | followed

    def _evidence(
        self,
        scan: Scan,
        ranges: np.ndarray,
        no_echo: np.ndarray,
        level_ranges: np.ndarray,
        directions: np.ndarray,
        step: Motion,
        velocity: Motion,
        fresh: bool,
        blind: bool,
        unseen_travel: bool,
        travel_seen: bool,
    ) -> tuple[
        np.ndarray, np.ndarray | None, LevelView | None, WorldStatic | None, np.ndarray | None
    ]:
        """New returns (in front of the level view moved into this scan's frame), returns
        seen through it (None where no return is new: no share of new returns is worked
        out then), the view itself, the world-static test against the scan
        ``STATIC_BASELINE_S`` back and the one ``STATIC_FAR_BASELINE_S`` back
        (:meth:`_world_static`; None where there is nothing to compare with, or, without an
        IMU, no new return), and where a surface the view gave up is back
        (:meth:`~pvfilter.improved.memory.LevelView.surfaces_back`; None: nowhere). A
        surface back is not new: it stands where the view had it, not in free space.

        A ``blind`` scan (coasting on the constant-velocity guess) is compared with the
        view within the guess's doubt, :func:`blind_margin_m`: the view is neither
        re-anchored nor asked whether the returns stayed put in the world.
        ``travel_seen``: the step's drive was measured in every direction (the
        world-static test takes a sensor that moved no farther than its tolerance since
        the earlier scan for one that stood only where every step since was)."""
        params, layout = self.params, self._layout
        if fresh:
            return np.zeros(layout.count, bool), np.zeros(layout.count, bool), None, None, None
        echoes = no_echo, ranges == ranges  # silent beams, and returns (NaN compares False)
        view = self._memory.view(
            layout, scan.range_max, step, velocity, scan.time_increment, params, *echoes,
            range_min=scan.range_min,
        )  # fmt: skip
        self._recent.advance(step, travel_seen)
        gaps = free_space_gaps(ranges, view.known_free_m(), layout, scan.range_max)
        if blind:  # the motion is a constant-velocity guess: compared within its doubt
            margin_m = params.free_margin_m + blind_margin_m(self._ego.coasted_s)
            new, through = free_space_evidence(gaps, ranges, margin_m, params.free_margin_rel)
            back = view.surfaces_back(ranges, params)
            return new if back is None else new & ~back, through, view, None, back
        new, through = free_space_evidence(
            gaps, ranges, params.free_margin_m, params.free_margin_rel
        )
        doubt = self._doubt.along_beams(layout, view.ranges)  # drive the matches missed
        if doubt is not None:
            margin = params.free_margin_rel * ranges
            margin += params.free_margin_m
            agrees = np.count_nonzero(new) < MIN_PAIRS  # the scan puts the view where it is
            if agrees and self._doubt.confirmed(np.abs(gaps) <= margin, directions):
                self._doubt.reset()  # ... on surfaces across the doubt (NaN compares False)
            else:  # new only beyond it (a return seen through stays so)
                new &= gaps > np.add(doubt, margin, out=doubt)
        # a drifted view puts returns in front of it and beyond it (re-anchoring must
        # explain MIN_PAIRS of those beyond: with fewer there is nothing to try; with no
        # new return, none seen through is worked out)
        drift = (
            through is not None
            and np.count_nonzero(new) >= MIN_PAIRS
            and np.count_nonzero(through) >= MIN_PAIRS
        )
        if params.reanchor_view and drift:
            anchored = self._reanchor(
                scan,
                ranges,
                echoes,
                level_ranges,
                directions,
                view,
                gaps,
                step,
                velocity,
                unseen_travel,
            )
            if anchored is not None:  # registered on the scan: no doubt left
                view, gaps = anchored
                self._doubt.reset()
                new, through = free_space_evidence(
                    gaps, ranges, params.free_margin_m, params.free_margin_rel
                )
        back = view.surfaces_back(ranges, params)
        if back is not None:
            new &= ~back
        # without an IMU only lines with new returns are scored, and only scored lines are
        # tested: a scan with no new return (most) has no use for the test then (with an
        # IMU every gated line is)
        tested = through is not None or self._attitude.current is not None
        static = None
        if tested:
            static = self._world_static(scan.stamp, level_ranges, directions)
        return new, through, view, static, back

    def _world_static(
        self, stamp: float, level_ranges: np.ndarray, directions: np.ndarray
    ) -> WorldStatic | None:
        """The world-static test of the scan now against the kept scan ``STATIC_BASELINE_S``
        back, with the oldest kept (``STATIC_FAR_BASELINE_S``) as its ``farther`` where
        that one is older (None: no scan kept)."""
        earlier = self._recent.oldest(stamp)
        if earlier is None:
            return None
        older = self._recent.oldest_farther(stamp)
        farther = None if older is None else self._test_against(older, level_ranges, directions)
        return self._test_against(earlier, level_ranges, directions, farther)

    def _test_against(
        self,
        earlier: Earlier,
        level_ranges: np.ndarray,
        directions: np.ndarray,
        farther: WorldStatic | None = None,
    ) -> WorldStatic:
        """The world-static test of the scan now against the kept scan ``earlier``."""
        return WorldStatic(
            level_ranges,
            earlier.ranges,
            directions,
            self._layout,
            earlier.since,
            STATIC_TOLERANCE_M,
            earlier.travel_seen,
            earlier.span_s,
            earlier.first_step_s,
            earlier.first_speed_mps,
            farther,
        )

    def _reanchor(
        self,
        scan: Scan,
        ranges: np.ndarray,
        echoes: tuple[np.ndarray, np.ndarray],
        level_ranges: np.ndarray,
        directions: np.ndarray,
        view: LevelView,
        gaps: np.ndarray,
        step: Motion,
        velocity: Motion,
        unseen_travel: bool,
    ) -> tuple[LevelView, np.ndarray] | None:
        """The level view registered against the scan, and its gaps, where the correction
        explains returns seen through the view (:mod:`pvfilter.improved.anchor`); None:
        the view stands (as it does at once where the registration finds it within the
        free-space margin). The memory takes the corrected view in with the scan. Where
        that fails and ``unseen_travel`` may have left the view off along x, the
        registration starts again from a search along x. ``echoes``: per beam, no echo and
        a return (the view's move takes them: :meth:`LevelMemory.view`)."""
        layout, params = self._layout, self.params
        margin = params.free_margin_m + params.free_margin_rel * ranges

        def moved_if_explained(correction: Motion | None, both_ends: bool):
            """The view moved by ``correction`` and its gaps, if that explains returns
            seen through it (and, ``both_ends``, puts more returns on it ahead and
            behind)."""
            if correction is None:
                return None
            moved = self._memory.view(
                layout, scan.range_max, step.then(correction), velocity, scan.time_increment,
                params, *echoes, range_min=scan.range_min,
            )  # fmt: skip
            moved_gaps = free_space_gaps(ranges, moved.known_free_m(), layout, scan.range_max)
            if not explains_view_error(gaps, moved_gaps, margin, directions):
                return None
            if both_ends and not explains_both_ends(gaps, moved_gaps, margin, layout):
                return None
            return moved, moved_gaps

        correction = register_view(level_ranges, directions, view.ranges, layout)
        if correction is not None and within_margin(correction, params):
            return None  # the view is where the scan says, within the free-space margin
        anchored = moved_if_explained(correction, False)
        if anchored is not None or not unseen_travel:
            return anchored
        shift = offset_along_x(level_ranges, view.ranges, layout)
        if shift is None:
            return None
        correction = register_view(
            level_ranges, directions, view.ranges, layout, shift, REFINE_ASSOCIATION_M
        )
        return moved_if_explained(correction, True)

    @staticmethod
    def _tilt(detection: LineDetection, attitude: Attitude | None) -> float:
        """The scan plane's tilt, rad: the IMU's, else the strongest line's (0 where the
        scan has none)."""
        if attitude is not None:
            return attitude.tilt_rad
        if detection.tilted and not math.isnan(detection.plane_tilt_rad):
            return detection.plane_tilt_rad
        return 0.0

    def _rebaseline(self) -> None:
        """Start afresh: no level view, no scan to match or compare with."""
        self._memory.reset()
        self._ego.reset()
        self._recent.clear()
        self._follower.reset()
        self._travelled = None
        self._doubt.reset()
        self._tilted_s = 0.0

    def _level(self, tilted: bool, dt: float, travelling: bool = False) -> bool:
        """The scan plane was level: no strong candidate line, and the IMU (if any) agrees.

        Tilted for longer than ``max_event_s`` cannot be (the robot levels): the scans are
        then taken as level again, so a wall mistaken for a line cannot freeze the view;
        unless the scan's floor line is ``travelling`` with the sensor, as no wall does
        (:func:`~pvfilter.improved.follow.travelling_line`).
        """
        tilted = _shows_tilt(tilted, self._attitude.current)
        self._tilted_s = self._tilted_s + dt if tilted else 0.0
        return not tilted or (self._tilted_s > self.params.max_event_s and not travelling)

    def _scanner_params(self) -> None:
        """The parameters for the scanner: its beam spacing (none seen yet: as given), its
        range noise as measured so far, and the roll learnt
        (:meth:`ImprovedParams.for_beam_spacing`, :meth:`ImprovedParams.for_range_noise`)."""
        spacing = self.params
        if self._layout is not None:
            spacing = spacing.for_beam_spacing(self._layout.increment)
        self._spacing_params = spacing.for_range_noise(self._noise.noise_m)
        self._line_params = self._roll.applied(self._spacing_params)
        self._segment_params = self._roll.segmenting(self._spacing_params)

    def _start(self, scan: Scan) -> tuple[bool, float]:
        """Check stamp and beams: does the scan start afresh, and the time step, s."""
        previous = self._previous_stamp
        if stamp_went_back(scan.stamp, previous, stacklevel=3):
            self._new_sequence = True
            self._body.reset()  # (another recording may follow)
        self._previous_stamp = scan.stamp
        fits = self._layout is not None and self._layout.fits(scan)
        fresh = self._new_sequence or not fits
        self._new_sequence = False
        if not fits:
            self._layout = BeamLayout.of(scan)
            self._body.reset()
            self._noise.reset()
            self._scanner_params()
        dt = 0.0 if previous is None else scan.stamp - previous
        if previous is not None and dt >= 0.0:
            self._gaps.scan(dt, self.params.max_gap_s, stacklevel=3)
        if fresh or dt > self.params.max_gap_s:  # scans this far apart cannot be compared
            return True, 0.0
        return False, dt if dt >= SAME_INSTANT_S else 0.0


def _mid_scan(
    points: np.ndarray,
    layout: BeamLayout,
    time_increment: float,
    velocity: Motion,
    near: np.ndarray,
) -> np.ndarray:
    """The scan's points in its mid-scan frame, deskewed with ``velocity`` (per second),
    m; NaN where none, and on the ``near`` beams: the body moves with the sensor, and would
    pin the scan match to a robot standing still (in a corridor its walls say nothing of
    the drive along them). The match, its reference and the world-static test leave it
    out."""
    mid_points = deskew(points, layout, time_increment, velocity)
    if np.count_nonzero(near):
        mid_points[near] = np.nan
    return mid_points


def _shows_tilt(lines_tilted: bool, attitude: Attitude | None) -> bool:
    """The scan plane was tilted: a strong candidate line, or the IMU (if any) shows it
    tilted beyond its band."""
    return lines_tilted or (attitude is not None and attitude.tilted)


def _settling(view: LevelView | None, dt: float, max_event_s: float) -> bool:
    """Some beam's clock in the level ``view`` passes ``max_event_s`` with this step of
    ``dt`` s: where its return still stands in front of the view, the view settles onto
    it (:meth:`~pvfilter.improved.memory.LevelMemory.update`) unless it lies on a floor
    line that travels with the sensor. Each beam keeps its own clock, so a line whose
    beams came in front a scan or two before the scans counted as tilted settles there
    first, and the scans' own clock would ask too late."""
    return view is not None and float(view.ahead_s.max(initial=0.0)) + dt > max_event_s
