"""Ego-motion over a sequence: scan matching through pitch events, a prior, a trust check.

During a pitch event a tilted plane sees the walls it still meets stretched along its x
axis (by ``1 / cos(tilt)``): a plain scan match reads a drive that did not happen, the
level view drifts, and when the robot levels the real wall in front looks new. So:

- each scan is **unstretched** before it is matched against the previous one (stored
  unstretched by its own tilt): its x axis is scaled by ``cos(tilt)``, the tilt being
  the IMU's when given, else the previous scan's (the pitch changes little in a scan
  time). The previous scan's tilt is that of its floor line, 0 where it showed none,
  and so for a scan that coasted too, although it was matched at the tilt before it: a
  coasted scan without a floor line shows the robot levelled, and the next, level scan
  unstretched as if tilted would have its walls ahead and behind nearer by
  ``1 - cos(tilt)``, which the match reads as travel;
- the **prior** is the wheel odometry's step when the robot gives its pose (with a
  spread that grows with the step: the wheels slip on hard stops; a step faster than the
  robot can turn or drive is slip, not motion, and so is the step after it:
  :meth:`EgoMotion.plausible_pose`; a match that fails against the odometry while the
  match without it and the velocity before agree is taken as the wheels' slip:
  :meth:`EgoMotion.wheels_slipped`), else
  the last step at constant velocity; where that finds no pairs of points (a velocity
  from a bad match in a pitch event puts every wall farther off than ``association_m``,
  and a coasting filter would carry it for ``max_event_s``), the match is tried once
  more from the robot standing since the reference, as it mostly does at the end of a
  hard stop;
- at a **low scan rate** (no odometry, and a gap long enough for the constant-velocity
  prior to be off by more than ``association_m``) the drive between the scans is
  searched before the fit (:mod:`pvfilter.improved.widestep`);
- a match that is not to be **trusted** (too few pairs, a poor fit, a turn or a drive
  faster than a robot of this class can, or far from the odometry): in the middle of a
  pitch event the prior carries the motion (**coasting**) until a scan matches again,
  against the last matched scan, searched over the turn the robot can make in the time
  since; otherwise the filter re-baselines. A scan coasting on the odometry is filtered
  as usual (the odometry measures the motion, within its spread); one coasting on a
  constant velocity is compared with the level view only within the guess's doubt (the
  robot may have driven anywhere from standing to its top speed meanwhile:
  :func:`pvfilter.improved.filter.blind_margin_m`).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from pvfilter.improved.beams import BeamLayout, indices, row_norms
from pvfilter.improved.motion import (
    MIN_PAIRS,
    STILL,
    Motion,
    coarse_turn,
    estimate_motion,
    odometry_motion,
)
from pvfilter.improved.noise import range_noise_m
from pvfilter.improved.params import ImprovedParams
from pvfilter.improved.sweep import unstretch
from pvfilter.improved.widestep import MAX_SEARCH_M, prior_doubt_m, wide_step

ODOM_TURN_RAD = math.radians(0.5)  # rad: the odometry's turn error per step, besides slip
ODOM_SHIFT_M = 0.01  # m: its translation error per step, besides slip
STEADY_TURN_RAD = 0.01  # rad: how much the turn may change in one step (constant velocity)
STEADY_SHIFT_M = 0.03  # m: how much the translation may change in one step
MAX_RESIDUAL_M = 0.05  # m: a fit (the match, the level view's registration) whose median
# residual is larger is not trusted; a level scan's match may be, where the scan's range
# noise explains it (fit_trusted)
NOISE_RESIDUAL_FACTOR = 2.0  # 1: a level scan's fit whose median residual is at most this
# many times the scan's range noise (:func:`pvfilter.improved.noise.range_noise_m`) is
# trusted: right fits leave 0.7 to 1.3 times it (two ranges' noise seen across a surface)
MAX_NOISE_RESIDUAL_M = 0.12  # m: ... but never one over this: right fits of a scanner with
# 5 cm of noise plus 1 % of the range leave 5-6 cm; where range jumps spoil most triples
# of consecutive beams (clutter, a garbled scan), the "noise" measured is the scene's
STEP_NOISE_M = 0.01  # m: the least step error a match is allowed beyond the steady doubt
STEP_RESIDUAL_FACTOR = 2.0  # 1: ... or this many times its median residual (a noisier
# scanner's fits err more: with 5 cm of range noise, 1 cm cost the simulator's noisy robot
# 0.027 of AUC)
ODOM_SIGMAS = 4.0  # a match farther from the odometry than this many spreads is not trusted
MAX_SPEED_MPS = 3.0  # m/s: faster than a TWSB robot drives; a match that says so is wrong
MIN_REFERENCE_POINTS = MIN_PAIRS  # a scan with fewer points left to match against
# (its new returns and candidate lines left out) does not replace the reference
SEEN = (math.inf, 0.0)  # a step's drive seen in every direction (Match.weak)
ODOM_AGREEMENT_SCANS = 10  # scans: the memory of the odometry's agreement with the matches
# (an exponential average over about this many trusted matches)


@dataclasses.dataclass(frozen=True)
class Match:
    """One scan's ego-motion.

    Attributes:
        step: the motion from the previous scan to this one.
        trusted: the match can be trusted.
        tilt_rad: the tilt the scan was unstretched by before the match, rad, >= 0.
        ranges: the scan's ranges, mid-scan and unstretched, m (None: not matched).
        weak: the fit's least constrained direction of translation: its support in
            rows and its direction in this scan's frame, rad
            (:attr:`pvfilter.improved.motion.Motion.weak_rows`; ``SEEN``: no fit).
    """

    step: Motion
    trusted: bool
    tilt_rad: float = 0.0
    ranges: np.ndarray | None = None
    weak: tuple[float, float] = SEEN


class EgoMotion:
    """The sensor's motion from scan to scan.

    Args:
        params: ``ego_motion``, ``max_yaw_rate_rad_s``, ``association_m``, ``odom_slip``
            and ``max_tilt_deg`` are used.
    """

    def __init__(self, params: ImprovedParams) -> None:
        self.params = params
        # the mean square of the odometry's turn error against trusted matches, in units
        # of its spread (a property of the robot, kept through re-baselines); it starts
        # as unproven, above 1
        self.odometry_disagreement = 2.0
        self.reset()

    def reset(self) -> None:
        """Forget the scans so far (a new sequence, or a re-baseline)."""
        self.reference: np.ndarray | None = None  # the last matched scan, unstretched
        self.reference_ranges: np.ndarray | None = None  # its ranges
        self.reference_all: np.ndarray | None = None  # its points with the new returns too
        self.since_reference = Motion()  # its motion to the previous scan (coasting)
        self.coasted_s = 0.0  # time from the reference to the previous scan, s (coasting)
        self.velocity = Motion()  # the last step, per second
        self.pose: np.ndarray | None = None  # the odometry pose at the previous scan
        # the wheels slipped in the step to it, or before and have not run true since:
        # the step from it is no prior either (a wheel that spun may spin on, at a rate a
        # robot can turn)
        self.slipped = False
        # the wheels measured every step coasted since the reference (a step without a
        # pose, or before the first, was the constant-velocity guess)
        self.wheels_throughout = True
        self.tilt = 0.0  # the previous scan's tilt, rad
        self.level = False  # the previous scan was level (no floor line, no IMU tilt)
        self.steady = False  # the velocity was measured between two level scans in a row

    def plausible_step(self, pose: np.ndarray | None, dt: float) -> bool:
        """The odometry's step to ``pose`` from the previous scan's turns and drives no
        faster than a robot of this class can (``max_yaw_rate_rad_s``, ``MAX_SPEED_MPS``,
        as a match is judged); True where there is no step to judge. A shove can spin a
        wheel, and the odometry then reads a turn of a radian in a tenth of a second."""
        if pose is None or self.pose is None or dt <= 0.0:
            return True
        step = odometry_motion(self.pose, pose)
        turn_ok = abs(step.theta_rad) <= self.params.max_yaw_rate_rad_s * dt + math.radians(2.0)
        drive_ok = step.translation_m <= MAX_SPEED_MPS * dt + self.params.association_m
        return turn_ok and drive_ok

    def plausible_pose(self, pose: np.ndarray | None, dt: float) -> np.ndarray | None:
        """``pose`` as the prior's, or None where it gives no step to trust: no pose came
        before it (odometry that starts in a sequence), or the wheels slipped, in the step
        to it (:meth:`plausible_step`) or before, and have not run true since
        (:attr:`slipped`, :meth:`still_slipping`). The scan is matched as without odometry
        then. The next step starts from ``pose`` all the same (:meth:`commit` and
        :meth:`coast` keep the pose as given)."""
        if self.pose is None or self.slipped or not self.plausible_step(pose, dt):
            return None
        return pose

    def prior(self, dt: float, pose: np.ndarray | None) -> tuple[Motion, tuple[float, float]]:
        """The step expected from the previous scan to this one, and its spread (rad, m)."""
        if pose is not None and self.pose is not None:
            step = odometry_motion(self.pose, pose)
            slip = self.params.odom_slip
            spread = (
                ODOM_TURN_RAD + slip * abs(step.theta_rad),
                ODOM_SHIFT_M + slip * step.translation_m,
            )
            return step, spread
        return self.velocity.scaled(dt), (STEADY_TURN_RAD, STEADY_SHIFT_M)

    def match(
        self,
        layout: BeamLayout,
        points: np.ndarray,
        directions: np.ndarray,
        dt: float,
        prior: tuple[Motion, tuple[float, float]],
        odometry: bool,
        imu_tilt: float | None,
        imu_tilted: bool = False,
    ) -> Match:
        """Match a scan against the previous one.

        Args:
            layout: the beams.
            points: the scan's points per beam in its mid-scan frame (NaN rows: none), m.
            directions: the local line direction per beam, rad (NaN: none).
            dt: time since the previous scan, s.
            prior: the expected step and its spread (from :meth:`prior`).
            odometry: the prior is the wheel odometry's.
            imu_tilt: the IMU's tilt, rad, or None.
            imu_tilted: the IMU shows the plane tilted beyond its error band (with
                ``imu_tilt``; :attr:`pvfilter.improved.imu.Attitude.tilted`).
        """
        step_prior, spread = prior
        if not self.params.ego_motion:
            return Match(Motion(), True)
        max_tilt = math.radians(self.params.max_tilt_deg)
        # the tilt: the IMU's, else the last scan's (the pitch changes little in a scan time)
        guess = min(abs(imu_tilt) if imu_tilt is not None else self.tilt, max_tilt)
        # level: no floor line in the last scan, or an IMU that shows no tilt beyond its
        # band (a balancing robot's estimate is never exactly 0)
        level_scan = self.tilt == 0.0 if imu_tilt is None else not imu_tilted
        if self.reference is None:
            return Match(step_prior, False, guess)
        expected = self.since_reference.then(step_prior)
        # the turn since the reference is bounded by the fastest yaw over the time since it
        # (one scan, or more while coasting: a turn carries on through a pitch event)
        turn = min(self.params.max_yaw_rate_rad_s * (dt + self.coasted_s), math.pi)
        max_shift = min(math.ceil(turn / layout.increment) + 1, layout.count // 4)
        level = unstretch(points, guess)
        ranges = row_norms(level)
        reference_ranges = self.reference_ranges
        first = min(max(round(expected.theta_rad / layout.increment), -max_shift), max_shift)
        shift = coarse_turn(ranges, reference_ranges, max_shift, layout, first)

        def fit(around: Motion, around_spread: tuple[float, float]) -> Motion:
            association = self.params.association_m
            return estimate_motion(
                level, directions, self.reference, layout, shift, association, around, around_spread
            )

        found = fit(expected, spread)
        since_s = dt + self.coasted_s
        if not odometry and self.steady and self.coasted_s == 0.0 and found.pairs >= MIN_PAIRS:
            # the velocity measured between two level scans, and the fit found around it:
            # no farther off it than physics allows. Not where a tilted scan's match set
            # the velocity (in the stress matrix's strong shoves, drawn towards a shove's
            # 1.4 m/s read so, a wall ahead came out new for four scans), nor after a
            # start afresh (nothing has measured it), nor around the robot standing or a
            # wide step (there the prior has proven wrong, or a low rate leaves it in doubt)
            found = self._within_steady_doubt(found, expected, since_s)
        if found.pairs < MIN_PAIRS and not odometry and expected.translation_m > 0.0:
            # no pairs where the constant-velocity prior put them (a wrong velocity, or a
            # hard stop while coasting): try the robot standing since the reference
            standing = Motion(expected.theta_rad, 0.0, 0.0)
            found = fit(standing, (spread[0], self.params.association_m))
        if not odometry and prior_doubt_m(dt) > self.params.association_m:
            # a low scan rate: the drive may lie beyond the pairs' reach; search it
            wide = wide_step(
                level,
                ranges,
                directions,
                self.reference_all,
                layout,
                turn,
                expected,
                min(MAX_SPEED_MPS * since_s, MAX_SEARCH_M),
                self.params.association_m,
                spread[0],
                found,
            )
            if wide is not None and fit_trusted(wide.residual_m, ranges, level_scan):
                found = wide
        step = self.since_reference.inverse().then(found)
        trusted = found.pairs >= MIN_PAIRS and fit_trusted(found.residual_m, ranges, level_scan)
        # no faster than a robot of this class turns and drives since the reference
        trusted &= abs(found.theta_rad) <= self.params.max_yaw_rate_rad_s * since_s + math.radians(
            2.0
        )
        trusted &= found.translation_m <= MAX_SPEED_MPS * since_s + self.params.association_m
        if odometry:
            trusted &= self._within_odometry_spread(found, expected, spread)
            if trusted and self.coasted_s == 0.0:
                self._odometry_agrees(_turn_between(found, expected) / spread[0])
        if not trusted:  # what the prior expected, for a filter that coasts on it
            return Match(step_prior, False, guess, ranges)
        return Match(step, True, guess, ranges, (found.weak_rows, found.weak_axis_rad))

    def _within_odometry_spread(
        self, found: Motion, expected: Motion, spread: tuple[float, float]
    ) -> bool:
        """``found`` lies within ``ODOM_SIGMAS`` of the odometry's ``spread`` (rad, m) of
        ``expected``, with the match's own uncertainty (2 degrees, half ``association_m``)."""
        off_turn = _turn_between(found, expected)
        off_shift = math.hypot(found.tx_m - expected.tx_m, found.ty_m - expected.ty_m)
        return (
            off_turn <= ODOM_SIGMAS * spread[0] + math.radians(2.0)
            and off_shift <= ODOM_SIGMAS * spread[1] + 0.5 * self.params.association_m
        )

    def still_slipping(self, pose: np.ndarray | None, dt: float, match: Match) -> bool:
        """The wheels slipped before (:attr:`slipped`), and their step to ``pose`` has not
        run true since: ``match``, made without them, is not trusted, or its step lies
        beyond the odometry's spread of theirs. A wheel a shove spun can spin on for
        several scans at a rate a robot can turn."""
        if not self.slipped or pose is None:
            return False
        wheels, spread = self.prior(dt, pose)
        return not (match.trusted and self._within_odometry_spread(match.step, wheels, spread))

    def wheels_slipped(
        self, wheel_step: Motion, spread: tuple[float, float], dt: float, alone: Match
    ) -> bool:
        """The wheels slipped, and the scans measured the step: two witnesses against one.

        Where a match fails against the odometry, either the match is wrong (floor lines
        pull it) or the wheels are (a shove spins one, and the odometry turns the wrong
        way). The velocity measured between the last two level scans is a third witness
        where it is fresh (``steady``, no coasting since): if the match made without the
        wheels (``alone``, trusted) lies within the odometry's spread of the constant
        velocity, and the wheels' step ``wheel_step`` does not, the wheels are the odd
        one out. A hard stop or a spin moves the wheels off a stale velocity too; the
        velocity is only a witness while fresh.
        """
        if not (alone.trusted and self.steady and self.coasted_s == 0.0):
            return False
        constant = self.velocity.scaled(dt)
        return self._within_odometry_spread(
            alone.step, constant, spread
        ) and not self._within_odometry_spread(wheel_step, constant, spread)

    def _within_steady_doubt(self, found: Motion, expected: Motion, since_s: float) -> Motion:
        """``found`` with its drive off the constant-velocity prior by no more than the
        body can move the sensor in ``since_s`` (:meth:`steady_doubt_m`): a floor line that
        moves with the pitch pulls the fit along it where the walls that would hold it
        are hidden, farther than any drive could."""
        off_x, off_y = found.tx_m - expected.tx_m, found.ty_m - expected.ty_m
        off = math.hypot(off_x, off_y)
        noise_m = max(STEP_NOISE_M, STEP_RESIDUAL_FACTOR * found.residual_m)
        bound = self.steady_doubt_m(since_s) + noise_m
        if off <= bound:
            return found
        share = bound / off
        # the fit did not measure the drive along the pull: that direction is left to the
        # prior, as a fit with no rows along it would leave it (the view's doubt takes it)
        return dataclasses.replace(
            found,
            tx_m=expected.tx_m + share * off_x,
            ty_m=expected.ty_m + share * off_y,
            weak_rows=0.0,
            weak_axis_rad=math.atan2(off_y, off_x) % math.pi,
        )

    def steady_doubt_m(self, since_s: float) -> float:
        """How far the sensor may have moved from the constant-velocity prior in
        ``since_s``, m: the axle's hardest braking or speeding up (``prior_doubt_m``),
        and the body's pitch swinging the sensor about the axle (at the LiDAR's distance
        from it) at up to ``max_pitch_rate_rad_s``, either way (against the swing the
        prior carried on), and never by more than from ``max_tilt_deg`` on one side to
        the other. A LiDAR 0.24 m above the axle: 3.8 cm at 40 Hz, 16.9 cm at 10 Hz."""
        params = self.params
        since_s = max(since_s, 0.0)
        arm_m = math.hypot(
            params.lidar_ahead_m, max(params.lidar_height_m - params.axle_height_m, 0.0)
        )
        widest = 2.0 * math.sin(math.radians(params.max_tilt_deg))
        swing = min(params.max_pitch_rate_rad_s * since_s, widest)
        return prior_doubt_m(since_s) + 2.0 * arm_m * swing

    def _odometry_agrees(self, turn_error: float) -> None:
        """Average in one trusted match's turn error against the odometry, in spreads."""
        weight = 1.0 / ODOM_AGREEMENT_SCANS
        self.odometry_disagreement += weight * (turn_error**2 - self.odometry_disagreement)

    @property
    def odometry_proven(self) -> bool:
        """The odometry has turned as the scans did, within its spread: its turn errors
        against the recent trusted matches are no larger than the spread says (a mean
        square of at most 1). A two-wheeled robot's odometry is; a skid-steer rover's,
        whose wheels slide in every turn, is not."""
        return self.odometry_disagreement <= 1.0

    def coast(
        self,
        match: Match,
        tilt_rad: float,
        dt: float,
        pose: np.ndarray | None,
        slipped: bool = False,
        wheels: bool = False,
    ) -> Match:
        """Carry on with the prior where a match failed in a pitch event: the previous scan
        stays the reference, and the motion since is what the prior expected.

        Args:
            match: the failed match (its step: the prior's).
            tilt_rad: the scan's tilt, rad.
            dt: the time since the previous scan, s.
            pose: the odometry pose now, as given (None: no odometry); the next prior is the
                odometry's step from here, as the coasted motion already holds the steps up
                to here.
            slipped: the wheels slipped in the step to ``pose`` (:attr:`slipped`).
            wheels: the prior is the wheels' step (:attr:`wheels_throughout`).
        """
        self._carry(match.step, tilt_rad, dt, pose, slipped)
        self.wheels_throughout = self.wheels_throughout and wheels
        self.level = self.steady = False  # (a coasting scan is taken as tilted)
        return dataclasses.replace(match, trusted=True)

    def coasted_tilt(self, tilt_rad: float) -> None:
        """The tilt of the scan that coasted, once its lines are known (rad; 0 where it
        showed no floor line): the next scan is unstretched by it, not by the guess the
        coasted scan was matched with."""
        self.tilt = tilt_rad

    def _carry(
        self, step: Motion, tilt_rad: float, dt: float, pose: np.ndarray | None, slipped: bool
    ) -> None:
        """Keep the reference and add ``step`` to the motion since it."""
        self.since_reference = self.since_reference.then(step)
        self.coasted_s += dt
        self.tilt = tilt_rad
        self.pose, self.slipped = pose, slipped and pose is not None

    def commit(
        self,
        points: np.ndarray,
        moving: np.ndarray,
        match: Match,
        tilt_rad: float,
        dt: float,
        pose: np.ndarray | None,
        level: bool | None = None,
        slipped: bool = False,
    ) -> None:
        """Take the scan in as the next reference, unstretched by its tilt (rad); ``moving``
        beams (new, candidate lines) never take part in a match. ``level``: the scan
        showed no floor line and no IMU tilt (None: its tilt is 0). ``pose``: the odometry
        pose as given; ``slipped``: the wheels slipped in the step to it
        (:attr:`slipped`).

        A scan with fewer than ``MIN_REFERENCE_POINTS`` points left once those are out
        (in a hall beyond the scanner's range, a pitched scan can be all floor and
        ceiling) keeps the previous reference, with this scan's measured step added to
        the motion since it: a reference with nothing to match would fail every match
        after it, until the filter re-baselines and loses its level view.
        """
        every = unstretch(points, tilt_rad)  # new returns too: for a search across a wide step
        reference = every.copy()
        moving = indices(moving)
        reference[moving] = np.nan
        level = tilt_rad == 0.0 if level is None else level
        if match.trusted and dt > 0.0:
            self.velocity = match.step.scaled(1.0 / dt)
            # matched against the scan before, level both: the drive is measured
            self.steady = level and self.level and self.coasted_s == 0.0
        self.level = level
        left = np.count_nonzero(reference[:, 0] == reference[:, 0])  # NaN compares False
        self.wheels_throughout = True  # (a trusted match measured the motion since)
        if match.trusted and self.reference is not None and left < MIN_REFERENCE_POINTS:
            self._carry(match.step, tilt_rad, dt, pose, slipped)
            return
        if match.ranges is not None and _same_stretch(tilt_rad, match.tilt_rad):
            # the match measured these points' ranges already (unstretched alike)
            ranges = match.ranges.copy()
            ranges[moving] = np.nan
        else:
            ranges = row_norms(reference)
        self.reference, self.reference_ranges = reference, ranges
        self.reference_all = every
        self.since_reference = STILL
        self.coasted_s = 0.0
        self.tilt = tilt_rad
        self.pose, self.slipped = pose, slipped and pose is not None


def _turn_between(a: Motion, b: Motion) -> float:
    """How far the turns of two steps differ, rad (>= 0; wrapped: a turn is an angle)."""
    return abs(math.remainder(a.theta_rad - b.theta_rad, 2.0 * math.pi))


def fit_trusted(residual_m: float, ranges: np.ndarray, level: bool) -> bool:
    """A match's median residual is small enough to trust.

    A scanner with 5 cm of range noise leaves about 5 cm on right fits: with the fixed
    bound alone, 44 % of its matches were refused, and a refused level scan starts the
    filter afresh. A tilted scan's fit carries more than the noise (it is unstretched by
    the last scan's tilt, and the pitch changes within the sweep), and one refused there
    only coasts: the fixed bound stays.

    Args:
        residual_m: the fit's median absolute point-to-line residual, m (NaN: no fit).
        ranges: the fitted scan's ranges per beam, m (NaN or infinite: no return).
        level: the scan is level (see :meth:`EgoMotion.match`).

    Returns:
        The residual is at most ``MAX_RESIDUAL_M``; or, for a level scan, at most
        ``NOISE_RESIDUAL_FACTOR`` times the scan's range noise, and at most
        ``MAX_NOISE_RESIDUAL_M``. The noise is worked out only for a level scan's residual
        over the fixed bound; where it cannot be (no three consecutive returns), the fixed
        bound stands.
    """
    if residual_m <= MAX_RESIDUAL_M:
        return True
    if not level or math.isnan(residual_m) or residual_m > MAX_NOISE_RESIDUAL_M:
        return False
    return residual_m <= NOISE_RESIDUAL_FACTOR * range_noise_m(ranges)  # NaN noise: False


def _same_stretch(tilt_rad: float, other_rad: float) -> bool:
    """:func:`unstretch` by either tilt gives the same points: both leave them as they are
    (0 or NaN), or the tilts are equal."""
    unchanged = tilt_rad == 0.0 or math.isnan(tilt_rad)
    other_unchanged = other_rad == 0.0 or math.isnan(other_rad)
    return unchanged == other_unchanged and (unchanged or tilt_rad == other_rad)
