"""Parameters of the improved filter: each one a physical quantity with a unit.

They fall in five groups: the robot (heights, the largest tilt, roll and pitch rate it
survives, the lowest ceiling it drives under), the free-space evidence (margins, how
the level view changes), the ego-motion (turn rate, odometry slip, time gaps), the line
geometry (segmentation, extension) and the decision (``p_th``, the IMU's error).

The defaults describe a small home TWSB robot (the paper's class: a 2D LiDAR about
0.25 m above the floor, up to about 1 m/s) and a LiDAR with centimetre range noise. Only
``lidar_height_m`` (and ``axle_height_m``, ``lidar_ahead_m``) are properties of one
robot that the user should set; ``twsb tune`` fits the others to a robot from generated data
(:mod:`pvfilter.params_file` reads the file it writes).
"""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np

from pvfilter.checks import check_flag, check_integer, check_number

LINE_NOISE_SIGMAS = 3.0  # standard deviations of the range noise within which returns
# of one line lie (ImprovedParams.for_range_noise)
REFERENCE_SPACING_RAD = math.radians(0.5)  # rad: the beam spacing the point counts are set
# for (720 beams a revolution); see ImprovedParams.for_beam_spacing


@dataclasses.dataclass(frozen=True)
class ImprovedParams:
    """Parameters of :class:`~pvfilter.improved.ImprovedPitchVariationFilter`.

    Invalid values raise ``ValueError("<field>: <what was expected>, got <value>")``.

    Attributes:
        lidar_height_m: the scan plane's height above the floor when the robot is level,
            m. A floor line lies ``h / sin(tilt)`` from the sensor.
        axle_height_m: height the robot tilts about (its wheel axle), m: the scanner's
            height at tilt ``p`` is ``axle + (h - axle) cos p`` (``lidar_height_m``: a
            scanner that stays at its height).
        lidar_ahead_m: how far ahead of the axle the scanner sits, m (negative: behind it),
            along the robot's x axis. Pitching nose down lowers a scanner ahead of the
            axle: every floor and ceiling line lies this much nearer on the side ahead, and
            farther behind, than for a scanner over the axle
            (:func:`pvfilter.improved.geometry.axle_distances`).
        max_tilt_deg: the largest tilt of the scan plane the robot survives, deg: no floor
            line is nearer than the scanner's height over ``sin`` of it.
        max_roll_deg: the largest roll (side tilt) while it pitches, deg (uneven floors,
            turns): a floor line's normal leans from the sensor's x axis by about the roll
            over the tilt (``learn_roll`` widens it to the roll the scans measure).
        max_pitch_rate_rad_s: the fastest pitch change, rad/s: with a rotating LiDAR the
            beams of one line are measured at different pitches, which bends the line.
        min_ceiling_m: the lowest ceiling the robot drives under, m: a line on the up side
            of a tilted scan plane is a ceiling only as far out as this height puts it.
        free_margin_m: how much closer than the remembered level view a return must be to
            count as new, m: range noise (about 3 sigma) plus the ego-motion error.
        free_margin_rel: the part of that margin that grows with range, 1 (per metre of
            range): angular error and beam width.
        memory_shrink_mps: how fast the remembered level view may come closer, m/s
            (moving things, the motion estimate's error). A floor line that sweeps in
            faster than this is new.
        line_shrink_mps: how fast it may come closer behind a segment across the
            direction of travel, where a floor line can lie, m/s, on top of the sensor's
            travel in the step (the motion estimate's error along x shows on exactly those
            segments, and is at most the travel): a floor line that a scan or two fail to
            detect stays new, and is found again.
        confirm_free_s: a level return farther than the view (space newly seen free)
            joins the view only after it has been seen for this long, s, and never from a
            tilted scan: a tilted plane that passes over furniture must not teach the view
            that the space behind is free.
        max_event_s: the longest a pitch event lasts (the balance controller levels the
            robot), s: a return in front of the level view for longer is structure, and
            the view takes it; the ego-motion reference is at most this old.
        memory_timeout_s: a beam's level view is forgotten when nothing confirmed it for
            this long, s.
        max_gap_s: scans farther apart than this cannot be compared (a low-rate log, a
            dropped stretch of scans), s: the filter starts its view afresh and removes
            nothing from that scan. At 2 Hz scans are compared, the drive between them
            searched (:mod:`pvfilter.improved.widestep`); compared at 1.2-1.6 Hz, a real
            log lost up to 14 % of a few scans.
        hold_behind_lines: the level view does not come closer behind a segment that may
            be a floor line (a candidate line, or one that continues the last strong
            line: :mod:`pvfilter.improved.follow`): the line stays new for the whole
            event.
        ego_motion: compensate the sensor's own motion between scans (scan matching, with
            wheel odometry as the prior when given).
        reanchor_view: register the level view against a scan with new returns, and
            correct it where that explains returns seen through it (the dead-reckoned
            view drifts over a pitch event; :mod:`pvfilter.improved.anchor`).
        learn_roll: measure the scan plane's roll on the scan's confident floor lines, and
            let the lean gates (``max_roll_deg``) and the segmentation
            (``line_angle_deg``) allow what it measures, where that is more
            (:mod:`pvfilter.improved.roll`).
        nan_is_no_echo: the scanner writes ``NaN`` for a beam that returned nothing, as
            some drivers and the converters of many public logs do (Hokuyo logs: a fifth
            to over half of their beams ``NaN``, never ``+inf``): read it as no echo, like
            ``+inf``. Off, ``NaN`` is an invalid reading, as REP-117 has it: it tells
            nothing of the space along the beam (a range filter's cut, a dark surface),
            and taken for free space, every wall that read ``NaN`` for a while is new
            when it returns. The scans cannot tell the two apart.
        max_yaw_rate_rad_s: fastest turn the ego-motion search considers, rad/s; an
            odometry step that turns faster is wheel slip.
        association_m: beam pairs farther apart than this take no part in the fit, m.
        odom_slip: share of the odometry's step the wheels may be off by (slip on hard
            stops and starts), 1: the odometry prior's spread; a scan match farther from
            the odometry than 4 spreads plus ``association_m`` is not trusted.
        chord_m: length of the chord through each point's neighbours that gives its local
            line direction, m (longer near the sensor, where noise is large against the
            beam spacing, in beams).
        line_angle_deg: a point lies on a candidate floor or ceiling line when its local
            direction is within this angle of the sensor's y axis, deg.
        break_distance_m: consecutive points farther apart than this (plus 2 % of the
            range) are in different segments, m.
        min_points: segments with fewer points are never removed, points (at 0.5° between
            beams: the counts scale with the scan's beam spacing, :meth:`for_beam_spacing`).
        line_length_m: a floor line spans the open space in front of the robot; a segment
            shorter than this scores in proportion to its length, m (clutter makes short
            lines across the direction of travel; fragments of a floor line between
            furniture are taken in by the long line they lie on, ``spread``).
        extend_beams: a detected line grows over at most this many beams at each end
            while the points stay on it, beams (at 0.5° between beams, as ``min_points``).
        extend_tolerance_m: distance from the line within which a point still extends it,
            m (plus 1 % of the range).
        spread: all floor hits of one scan lie on one line: points anywhere on a scored
            line join it, and where no segment alone has ``down_side_min_new`` new points,
            a segment counts the new points of all the points on its line.
        claimed_not_new_weight: the share of a line's score that a point it claims (at
            its ends or along it) takes where the point is not itself new (on the level
            view's surface, beyond it, or where the view knows nothing), 1 (1: every
            claim at the line's score): the foot of the wall behind a floor line lies on
            the line as well as the floor does.
        up_side_weight: score factor of lines on the up side of a tilted scan plane that
            are too near to be its ceiling (furniture met at another height, table
            undersides), 1 (1: no side cue).
        down_side_min_new: the strongest line fixes the down side only with at least this
            many new points, points (at 0.5° between beams, as ``min_points``; the beams
            a segment spans without a return count at its share of new returns, up to
            twice its count; a line whose new points span ``STRONG_LINE_M`` of it counts
            this many for each such length, however few beams it spans:
            :mod:`pvfilter.improved.scoring`).
        new_return_score: the claim score of a new return (in space the level view saw
            free) that no line takes in with more, 1: a rank, not a calibrated
            probability (:mod:`pvfilter.improved.clusters`). Such returns are pitch
            variation far more often than the returns the view knows, which score 0, and
            far less often than a scored line's. Below ``p_th`` (the default) they are
            ranked, not removed; 0: they score 0 too, as outside every cluster of the
            paper's filter.
        p_th: a beam is removed when its claim score exceeds this (the best score of the
            lines that take it in; at least ``new_return_score`` on a new return, so a
            ``p_th`` below that removes every new return), 1.
        imu_angle_error_deg: how far the IMU's pitch may be from the scan plane's, deg:
            bias, noise, and its lag times the pitch rate.
    """

    lidar_height_m: float = 0.25  # m
    axle_height_m: float = 0.08  # m
    lidar_ahead_m: float = 0.0  # m
    max_tilt_deg: float = 45.0  # deg
    max_roll_deg: float = 3.0  # deg
    max_pitch_rate_rad_s: float = 3.0  # rad/s
    min_ceiling_m: float = 1.9  # m
    free_margin_m: float = 0.08  # m
    free_margin_rel: float = 0.015  # 1
    memory_shrink_mps: float = 3.0  # m/s
    line_shrink_mps: float = 0.2  # m/s
    confirm_free_s: float = 0.25  # s
    max_event_s: float = 2.0  # s
    memory_timeout_s: float = 1.5  # s
    max_gap_s: float = 0.6  # s
    hold_behind_lines: bool = True
    ego_motion: bool = True
    reanchor_view: bool = True
    learn_roll: bool = True
    nan_is_no_echo: bool = False
    max_yaw_rate_rad_s: float = 4.0  # rad/s: a spin in place with the wheels at 0.6 m/s
    # on a 0.3 m track; the robots of independent sequences spin at up to 3 rad/s, a wheel a
    # shove spins reads 8-10 rad/s
    association_m: float = 0.25  # m
    odom_slip: float = 0.15  # 1
    chord_m: float = 0.3  # m
    line_angle_deg: float = 40.0  # deg
    break_distance_m: float = 0.15  # m
    min_points: int = 8  # points
    line_length_m: float = 0.6  # m
    extend_beams: int = 10  # beams
    extend_tolerance_m: float = 0.03  # m
    spread: bool = True
    claimed_not_new_weight: float = 0.5  # 1
    up_side_weight: float = 0.3  # 1
    down_side_min_new: int = 20  # points
    new_return_score: float = 0.01  # 1
    p_th: float = 0.5  # 1
    imu_angle_error_deg: float = 2.0  # deg

    def __post_init__(self) -> None:
        check_number("lidar_height_m", self.lidar_height_m, lower=0.0, unit="m")
        check_number("axle_height_m", self.axle_height_m, lower=0.0, unit="m", closed=True)
        if self.axle_height_m > self.lidar_height_m:
            raise ValueError(
                f"axle_height_m: must be <= lidar_height_m ({self.lidar_height_m} m), "
                f"got {self.axle_height_m}"
            )
        check_number("lidar_ahead_m", self.lidar_ahead_m, lower=-math.inf, unit="m")
        check_number("max_tilt_deg", self.max_tilt_deg, lower=0.0, upper=90.0, unit="deg")
        check_number("max_roll_deg", self.max_roll_deg, lower=0.0, upper=90.0, unit="deg")
        check_number("max_pitch_rate_rad_s", self.max_pitch_rate_rad_s, lower=0.0, closed=True)
        check_number(
            "min_ceiling_m", self.min_ceiling_m, lower=self.lidar_height_m, below="lidar_height_m"
        )
        check_number("free_margin_m", self.free_margin_m, lower=0.0, unit="m", closed=True)
        check_number("free_margin_rel", self.free_margin_rel, lower=0.0, upper=1.0, closed=True)
        for name in ("memory_shrink_mps", "line_shrink_mps", "confirm_free_s"):
            check_number(name, getattr(self, name), lower=0.0, closed=True, infinite=True)
        for name in ("max_event_s", "memory_timeout_s", "max_gap_s"):
            check_number(name, getattr(self, name), lower=0.0, unit="s", infinite=True)
        check_number("max_yaw_rate_rad_s", self.max_yaw_rate_rad_s, lower=0.0, closed=True)
        check_number("association_m", self.association_m, lower=0.0, unit="m")
        check_number("odom_slip", self.odom_slip, lower=0.0, upper=1.0, closed=True)
        check_number("chord_m", self.chord_m, lower=0.0, unit="m")
        check_number("line_angle_deg", self.line_angle_deg, lower=0.0, upper=90.0, unit="deg")
        check_number("break_distance_m", self.break_distance_m, lower=0.0, unit="m")
        check_number("line_length_m", self.line_length_m, lower=0.0, unit="m", closed=True)
        check_number("extend_tolerance_m", self.extend_tolerance_m, lower=0.0, closed=True)
        check_number("up_side_weight", self.up_side_weight, lower=0.0, upper=1.0, closed=True)
        check_number(
            "claimed_not_new_weight",
            self.claimed_not_new_weight,
            lower=0.0,
            upper=1.0,
            closed=True,
        )
        check_number("new_return_score", self.new_return_score, lower=0.0, upper=1.0, closed=True)
        check_number("p_th", self.p_th, lower=0.0, upper=1.0, closed=True)
        check_number(
            "imu_angle_error_deg", self.imu_angle_error_deg, lower=0.0, upper=90.0, closed=True
        )
        check_integer("min_points", self.min_points, 1)
        check_integer("extend_beams", self.extend_beams, 0)
        check_integer("down_side_min_new", self.down_side_min_new, 1)
        for name in (
            "hold_behind_lines",
            "ego_motion",
            "reanchor_view",
            "learn_roll",
            "spread",
            "nan_is_no_echo",
        ):
            check_flag(name, getattr(self, name))

    def for_beam_spacing(self, increment_rad: float) -> ImprovedParams:
        """These parameters for a scan whose beams lie ``increment_rad`` apart.

        The point counts (``min_points``, ``down_side_min_new``, ``extend_beams``) are set
        for beams 0.5° apart and scale with the beams per radian: a line at a given
        distance holds that many more or fewer points. A count never drops below 3, 5 and
        2 (a line needs a few points for a direction), or below what it was set to.
        """
        scale = REFERENCE_SPACING_RAD / abs(increment_rad)
        if scale == 1.0:
            return self

        def scaled(count: int, least: int) -> int:
            return max(min(least, count), round(count * scale))

        return dataclasses.replace(
            self,
            min_points=scaled(self.min_points, 3),
            down_side_min_new=scaled(self.down_side_min_new, 5),
            extend_beams=scaled(self.extend_beams, 2),
        )

    def for_range_noise(self, noise_m: float) -> ImprovedParams:
        """These parameters for a scanner whose ranges scatter by ``noise_m`` (one standard
        deviation, m; measured on its scans, :class:`pvfilter.improved.noise.RangeNoise`).

        The two distances that say which returns lie on one line grow with the noise where
        it outgrows them, never below what they were set to, to ``LINE_NOISE_SIGMAS``
        standard deviations: ``break_distance_m`` of the difference of two ranges (two
        neighbours on one surface are one segment), ``extend_tolerance_m`` of one range (a
        return that near a fitted line lies on it). The defaults cover 1 cm of noise (the
        line tolerance, 3 cm) and 3.5 cm (the break distance, 15 cm). A scanner with 10 cm
        of noise scatters a floor line 2 m out over +-0.25 m along its beams; with the
        defaults the line falls apart into pieces too short and too ragged to score.

        The free-space margin, the world-static test's tolerance and the chord stay as
        set: widened with the noise as well, they cost more than they gave on scans from
        generators written apart from this project.
        """
        if not noise_m > 0.0:  # (NaN: unknown; nothing widens)
            return self
        break_m = max(self.break_distance_m, LINE_NOISE_SIGMAS * math.sqrt(2.0) * noise_m)
        extend_m = max(self.extend_tolerance_m, LINE_NOISE_SIGMAS * noise_m)
        if break_m == self.break_distance_m and extend_m == self.extend_tolerance_m:
            return self
        return dataclasses.replace(self, break_distance_m=break_m, extend_tolerance_m=extend_m)

    def scanner_height_m(self, tilt_rad: float | np.ndarray) -> float | np.ndarray:
        """Height of the scanner above the floor with the robot tilted by ``tilt_rad``, m."""
        arm = self.lidar_height_m - self.axle_height_m
        return self.axle_height_m + arm * np.cos(tilt_rad)

    @functools.cached_property  # (asked for every scan; the parameters never change)
    def min_line_distance_m(self) -> float:
        """Nearest a floor line can be to the scan plane's point over the axle, m (at the
        largest tilt)."""
        tilt = math.radians(self.max_tilt_deg)
        return float(self.scanner_height_m(tilt)) / math.sin(tilt)
