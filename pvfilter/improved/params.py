"""Parameters of the improved filter: each one a physical quantity with a unit.

The defaults describe a small home TWSB robot (the paper's class: a 2D LiDAR about 0.25 m
above the floor, up to about 1 m/s) and a LiDAR with centimetre range noise. They are
round values near what ``twsb tune`` found on generated episodes of that class (random
houses, LiDAR heights 0.2-0.35 m, range noise 0-3 cm, softer and stiffer controllers;
scored on held-out episodes of another seed). Only ``lidar_height_m`` is a property of
one robot that the user should set; ``twsb tune`` fits the others to a robot from
generated data (:mod:`pvfilter.params_file` reads the file it writes).
"""

from __future__ import annotations

import dataclasses
import math

from pvfilter.checks import check_flag, check_integer, check_number


@dataclasses.dataclass(frozen=True)
class ImprovedParams:
    """Parameters of :class:`~pvfilter.improved.ImprovedPitchVariationFilter`.

    Invalid values raise ``ValueError("<field>: <what was expected>, got <value>")``.

    Attributes:
        lidar_height_m: the scan plane's height above the floor when the robot is level,
            m. A floor line lies ``lidar_height_m / sin(tilt)`` from the sensor; the
            geometry gates and the IMU option use it.
        max_tilt_deg: the largest tilt of the scan plane the robot survives, deg. A line
            closer than ``lidar_height_m / sin(max_tilt_deg)`` cannot be the floor.
        max_roll_deg: the largest roll (side tilt) while the robot pitches, deg. A floor
            line's normal leans away from the sensor's x axis by the roll over the tilt, so
            lines that would need more roll are structure, not floor.
        free_margin_m: how much closer than the remembered level view a return must be to
            count as new, m: range noise (about 3 sigma) plus the ego-motion error.
        free_margin_rel: the part of that margin that grows with range, 1 (per metre of
            range): angular error and beam width.
        memory_window_beams: the level view of a beam is the nearest of this many beams
            on each side, beams: absorbs sub-beam misalignment after ego-motion.
        memory_shrink_mps: how fast the remembered level view may come closer once
            ego-motion is compensated, m/s. Behind possible floor lines the view holds
            (``hold_behind_lines``), so elsewhere this only has to absorb moving things and
            the motion estimate's error: a fast rate keeps the false alarms of a wrong
            view short. A floor line that sweeps in faster than this stays new anyway.
        max_event_s: the longest a pitch event lasts (the balance controller levels the
            robot), s: a return in front of the level view for longer is structure, and
            the view takes it.
        memory_timeout_s: a beam's level view is forgotten when nothing confirmed it for
            this long, s (e.g. while the sector was hidden behind the robot's leg).
        hold_behind_lines: the level view does not come closer behind a segment that may
            be a floor line (it passes the geometry gates and is mostly new): the line then
            stays new for the whole event, however slowly it moves in the sensor frame
            (the robot pitched and driving at about its own pace).
        ego_motion: compensate the sensor's own rotation and translation between scans
            (a one-step point-to-line fit on the scan itself; no odometry needed).
        max_yaw_rate_rad_s: fastest turn the ego-motion search considers, rad/s.
        association_m: beams whose points moved more than this between scans take no part
            in the ego-motion fit, m.
        local_fit_beams: half-width of the local line fit that gives each point its line
            direction, beams.
        line_angle_deg: a point lies on a candidate floor or ceiling line when its local
            line direction is within this angle of the sensor's y axis, deg (the line
            across the direction of travel, ``x = h / sin(pitch)``).
        break_distance_m: consecutive points farther apart than this (plus 2 % of the
            range) are in different segments, m.
        min_points: segments with fewer points are never removed, points.
        extend_beams: a detected line grows over at most this many beams at each end
            while the points stay on it, beams (the corner where a floor line meets a wall).
        extend_tolerance_m: distance from the line within which a point still extends it,
            m (plus 1 % of the range).
        spread: points anywhere on a detected line join it (all floor hits of one scan
            lie on one line: fragments between furniture legs, and stretches of it too close
            to the structure behind to be new).
        up_side_weight: a tilted scan plane goes down on one side of the sensor and up on
            the other, and the floor is only on the down side: the side of the scan's
            strongest line. Lines on the other side (ceilings and table undersides, but
            mostly furniture met at another height, which a level scanner never saw) get
            their score times this, 1 (1: no side cue).
        down_side_min_new: the strongest line fixes the down side only with at least this
            many new points, points.
        p_th: a segment is removed when the share of its points that are new
            (in previously seen free space) or on the IMU's floor line exceeds this, 1.
        imu_floor_tolerance_m: with pitch and roll given, a point whose height above the
            floor is below this (plus the angle error's share) is on the floor, m: range
            noise times the tilt, the scanner's height error, the floor's unevenness.
        imu_angle_error_deg: error of the IMU's pitch and roll (including its lag behind
            the scan), deg: the floor tolerance grows by ``range * sin`` of it.
        axle_height_m: height the robot tilts about (its wheel axle), m; with the IMU, the
            scanner's height is corrected for the tilt. ``0`` ignores the correction.
    """

    lidar_height_m: float = 0.25  # m
    max_tilt_deg: float = 45.0  # deg
    max_roll_deg: float = 1.5  # deg
    free_margin_m: float = 0.08  # m
    free_margin_rel: float = 0.015  # 1
    memory_window_beams: int = 1  # beams
    memory_shrink_mps: float = 3.0  # m/s
    max_event_s: float = 2.0  # s
    memory_timeout_s: float = 1.5  # s
    hold_behind_lines: bool = True
    ego_motion: bool = True
    max_yaw_rate_rad_s: float = 1.5  # rad/s
    association_m: float = 0.25  # m
    local_fit_beams: int = 8  # beams
    line_angle_deg: float = 40.0  # deg
    break_distance_m: float = 0.15  # m
    min_points: int = 8  # points
    extend_beams: int = 10  # beams
    extend_tolerance_m: float = 0.03  # m
    spread: bool = True
    up_side_weight: float = 0.3  # 1
    down_side_min_new: int = 20  # points
    p_th: float = 0.5  # 1
    imu_floor_tolerance_m: float = 0.02  # m
    imu_angle_error_deg: float = 0.5  # deg
    axle_height_m: float = 0.08  # m

    def __post_init__(self) -> None:
        check = check_number
        check("lidar_height_m", self.lidar_height_m, lower=0.0, unit="m")
        check("max_tilt_deg", self.max_tilt_deg, lower=0.0, upper=90.0, unit="deg")
        check("max_roll_deg", self.max_roll_deg, lower=0.0, upper=90.0, unit="deg")
        check("free_margin_m", self.free_margin_m, lower=0.0, unit="m", closed=True)
        check("free_margin_rel", self.free_margin_rel, lower=0.0, upper=1.0, closed=True)
        check(
            "memory_shrink_mps",
            self.memory_shrink_mps,
            lower=0.0,
            unit="m/s",
            closed=True,
            infinite=True,
        )
        check("max_event_s", self.max_event_s, lower=0.0, unit="s", infinite=True)
        check("memory_timeout_s", self.memory_timeout_s, lower=0.0, unit="s", infinite=True)
        check("max_yaw_rate_rad_s", self.max_yaw_rate_rad_s, lower=0.0, unit="rad/s", closed=True)
        check("association_m", self.association_m, lower=0.0, unit="m")
        check("line_angle_deg", self.line_angle_deg, lower=0.0, upper=90.0, unit="deg")
        check("break_distance_m", self.break_distance_m, lower=0.0, unit="m")
        check("extend_tolerance_m", self.extend_tolerance_m, lower=0.0, unit="m", closed=True)
        check("up_side_weight", self.up_side_weight, lower=0.0, upper=1.0, closed=True)
        check("p_th", self.p_th, lower=0.0, upper=1.0, closed=True)
        check("imu_floor_tolerance_m", self.imu_floor_tolerance_m, lower=0.0, unit="m")
        check("imu_angle_error_deg", self.imu_angle_error_deg, lower=0.0, upper=90.0, closed=True)
        check("axle_height_m", self.axle_height_m, lower=0.0, unit="m", closed=True)
        if self.axle_height_m > self.lidar_height_m:
            raise ValueError(
                f"axle_height_m: must be <= lidar_height_m ({self.lidar_height_m} m), "
                f"got {self.axle_height_m}"
            )
        for name, lowest in (
            ("memory_window_beams", 0),
            ("local_fit_beams", 1),
            ("min_points", 1),
            ("extend_beams", 0),
            ("down_side_min_new", 1),
        ):
            check_integer(name, getattr(self, name), lowest)
        for name in ("ego_motion", "hold_behind_lines", "spread"):
            check_flag(name, getattr(self, name))

    @property
    def min_line_distance_m(self) -> float:
        """Nearest a floor line can be to the sensor, m: ``h / sin(max_tilt)``."""
        return self.lidar_height_m / math.sin(math.radians(self.max_tilt_deg))
