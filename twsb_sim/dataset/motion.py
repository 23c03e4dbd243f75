"""Random command profiles that keep the robot inside the free lane of its start pose.

A start pose of a house (:class:`~twsb_sim.house.SpawnPose`) comes with how far the
robot can drive straight ahead and back before touching anything. An episode's motion
is planned in that one dimension: the position ``s`` along the lane (m, positive
ahead of the start) must stay in ``[-behind_m, ahead_m]``, the lane minus a margin for
what the plan cannot predict exactly (the body leaning over on a hard stop, shoves).

The plan is a chain of maneuvers, each starting and ending at rest and facing along
the lane:

- **drive**: accelerate (ramp), cruise, then stop (hard: a step to zero; or a ramp), or
  reverse straight into the other way and stop later; forward or backward;
- **turn**: in place, by an angle and back, or a 180 deg turnabout that keeps the new
  heading (the lane is then driven the other way);
- **pause**: stand still.

Drives (cruising or braking), turns and pauses may carry a **shove**. The balance
controller tracks velocity, not position, so a shove moves the robot for good (about
``displacement_m_per_n_s`` per N·s of impulse); the plan pushes towards the side with
room and counts the displacement.
The commanded velocity's integral is what the plan tracks: the controller follows it
closely (a 1 m/s hard stop ends within a few cm of it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from twsb_sim.dataset.randomization import MotionRanges, Range, ShoveRanges

MIN_HOLD_S = 0.01  # s, every command point is held at least this long (keeps times ordered)
TURN_RAMP_S = 0.2  # s, yaw-rate ramps of a turn in place
SHOVE_RECOVERY_S = 2.0  # s, a shoved robot stands this long before the next maneuver
MIN_SHOVE_IMPULSE_N_S = 1.0  # N·s, a shove that must be made smaller than this is dropped
MIN_SPEED_MPS = 0.1  # m/s, a drive that would have to be slower than this becomes a pause
BRAKING_SHOVE_WITHIN_S = 0.4  # s, a shove while braking starts this soon after the stop


@dataclass(frozen=True)
class Lane:
    """Where the robot may be along its start heading (m; margins already taken off)."""

    behind_m: float  # >= 0: the robot may back up this far from the start
    ahead_m: float  # >= 0: and drive this far ahead


@dataclass(frozen=True)
class MotionPlan:
    """The timeline of one episode, as scenario-file tables."""

    commands: tuple[dict[str, Any], ...]  # rows of [[commands]]
    shoves: tuple[dict[str, Any], ...]  # rows of [[shoves]]
    final_s_m: float  # where the plan expects the robot at the end, along the lane (m)


def _uniform(rng: np.random.Generator, bounds: Range) -> float:
    low, high = bounds
    return float(rng.uniform(low, high)) if high > low else float(low)


def _ms(seconds: float) -> float:
    return round(seconds, 3)


class _Planner:
    """Builds the timeline maneuver by maneuver, tracking the planned position ``s``."""

    def __init__(
        self,
        rng: np.random.Generator,
        lane: Lane,
        motion: MotionRanges,
        shoves: ShoveRanges,
        duration_s: float,
    ) -> None:
        self.rng, self.motion, self.shove_ranges = rng, motion, shoves
        self.low, self.high = -lane.behind_m, lane.ahead_m
        self.duration_s = duration_s
        self.t = 0.0  # s, when the next command point starts
        self.v = 0.0  # m/s, commanded forward velocity in force (body frame)
        self.s = 0.0  # m, planned position along the lane
        self.facing = 1  # +1 facing along the lane, -1 after a turnabout
        self.commands: list[dict[str, Any]] = []
        self.shoves: list[dict[str, Any]] = []

    # -- building blocks -----------------------------------------------------------------

    def command(self, v: float, w: float, ramp_s: float, hold_s: float, label: str) -> float:
        """Append a command point now; returns its start time."""
        ramp_s, hold_s = _ms(ramp_s), _ms(max(hold_s, MIN_HOLD_S))
        start = self.t
        self.commands.append(
            {
                "t_s": start,
                "velocity_mps": round(v, 4),
                "yaw_rate_rad_s": round(w, 4),
                "ramp_s": ramp_s,
                "label": label,
            }
        )
        self.s += self.facing * (0.5 * (self.v + round(v, 4)) * ramp_s + round(v, 4) * hold_s)
        self.v = round(v, 4)
        self.t = _ms(start + ramp_s + hold_s)
        return start

    def room(self, direction: int) -> float:
        """Room left for driving ``direction`` (+1 forward, -1 backward in the body frame)."""
        along = direction * self.facing
        return self.high - self.s if along > 0 else self.s - self.low

    def shove(self, t_s: float, positions: tuple[float, ...], turned_rad: float = 0.0) -> float:
        """Schedule a shove at ``t_s`` if its push fits the lane from each of ``positions``.

        Args:
            t_s: when it starts (s).
            positions: where the robot may be along the lane while it acts (m).
            turned_rad: how far the robot faces off the lane then (a turn in place); a
                push "from behind" or "from the front" then acts along the lane, at that
                angle to the robot's heading, and its cap blends the two directions'.

        Returns:
            Its planned displacement along the lane (m), 0 when no shove fits.
        """
        r, rng = self.shove_ranges, self.rng
        duration = _ms(_uniform(rng, r.duration_s))
        height = round(_uniform(rng, r.height_m), 3)
        sign = 1 if rng.random() < 0.5 else -1
        fraction = _uniform(rng, r.impulse_fraction)
        lever = duration * height  # N·m·s per N

        def force_n(cap_n_m_s: float, force_range: Range) -> float:
            if r.impulse_fraction[1] > 0.0:  # by impulse: a share of what it survives
                return fraction * cap_n_m_s / lever
            return min(_uniform(rng, force_range), cap_n_m_s / lever)

        if not turned_rad and rng.random() < r.sideways_fraction:
            force = force_n(r.max_sideways_angular_impulse_n_m_s, r.lateral_force_n)
            label = "shove from the right" if sign > 0 else "shove from the left"
            self._add_shove(t_s, (0.0, sign * force), duration, height, label)
            return 0.0  # a push from a side turns and rolls the robot but hardly moves it
        c, s = math.cos(turned_rad), math.sin(turned_rad)
        cap = 1.0 / math.hypot(c / r.max_angular_impulse_n_m_s,
                               s / r.max_sideways_angular_impulse_n_m_s)  # fmt: skip
        force = force_n(cap, r.longitudinal_force_n)
        k = r.displacement_m_per_n_s
        for push in (sign, -sign):  # +1: pushed forward along the lane (a shove from behind)
            along = push * self.facing  # +1 when the push moves the robot towards +s
            room = min((self.high - p) if along > 0 else (p - self.low) for p in positions)
            fits = min(force, room / (k * duration)) if k > 0 else force
            if fits * duration >= MIN_SHOVE_IMPULSE_N_S:
                label = "shove from behind" if push > 0 else "shove from the front"
                if turned_rad:
                    label += " while turning"
                # the lane's direction seen from the robot, turned by turned_rad
                self._add_shove(t_s, (push * fits * c, -push * fits * s), duration, height, label)
                return along * k * fits * duration
        return 0.0

    def _add_shove(
        self, t_s: float, force_n: tuple[float, float], duration_s: float, height_m: float,
        label: str,
    ) -> None:  # fmt: skip
        self.shoves.append(
            {
                "t_s": _ms(t_s),
                "force_n": [round(force_n[0], 2), round(force_n[1], 2), 0.0],
                "duration_s": duration_s,
                "point_m": [0.0, 0.0, height_m],
                "label": label,
            }
        )

    # -- maneuvers -----------------------------------------------------------------------

    def pause(self, with_shove: bool) -> None:
        hold = _uniform(self.rng, self.motion.pause_s)
        if with_shove:
            hold = max(hold, SHOVE_RECOVERY_S + 0.5)
            start = self.command(0.0, 0.0, 0.0, hold, "pause")
            self.s += self.shove(start + _uniform(self.rng, (0.2, 0.5)), (self.s,))
        else:
            self.command(0.0, 0.0, 0.0, hold, "pause")

    def turn(self, with_shove: bool) -> None:
        m, rng = self.motion, self.rng
        sign = 1 if rng.random() < 0.5 else -1
        shoved = with_shove and rng.random() < self.shove_ranges.turning_probability
        if rng.random() < m.turnabout_probability:
            # half a turn: the lane is driven the other way from now on
            self._rotate(sign * math.pi, _uniform(rng, m.turn_rate_rad_s), "turnabout",
                         _uniform(rng, m.pause_s), "pause", shoved)  # fmt: skip
            self.facing = -self.facing
            return
        angle = math.radians(_uniform(rng, m.turn_angle_deg))
        rate, rate_back = _uniform(rng, m.turn_rate_rad_s), _uniform(rng, m.turn_rate_rad_s)
        self._rotate(sign * angle, rate, "turn", _uniform(rng, m.pause_s), "look", shoved)
        self._rotate(-sign * angle, rate_back, "turn back", _uniform(rng, m.pause_s), "pause")

    def _rotate(
        self, angle_rad: float, rate_rad_s: float, label: str, then_hold_s: float, then: str,
        with_shove: bool = False,
    ) -> None:  # fmt: skip
        """Turn in place by ``angle_rad``, then hold still for ``then_hold_s``; with a
        shove at a random moment of the turn.

        The yaw-rate command is a trapezoid (ramp up, hold, ramp down) whose area is the
        angle: ``w * (ramp + hold)``.
        """
        ramp = _ms(min(TURN_RAMP_S, abs(angle_rad) / rate_rad_s))
        hold = max(math.ceil((abs(angle_rad) / rate_rad_s - ramp) * 1000) / 1000, MIN_HOLD_S)
        w = angle_rad / (ramp + hold)  # the rounding to ms taken up by the rate
        start = self.command(0.0, w, ramp, hold, label)
        shift = 0.0
        if with_shove:
            u = _uniform(self.rng, (0.0, ramp + hold))  # s into the turn
            turned = w * u * u / (2 * ramp) if u < ramp else w * (ramp / 2 + u - ramp)
            shift = self.shove(start + u, (self.s,), turned)
        self.command(0.0, 0.0, ramp, then_hold_s, then)
        if shift:
            self.s += shift
            self.command(0.0, 0.0, 0.0, SHOVE_RECOVERY_S, "pause")

    def drive(self, with_shove: bool) -> bool:
        """One drive (maybe with a reversal); False when the lane has no room for it."""
        m, rng = self.motion, self.rng
        ways = [d for d in (1, -1) if self.room(d) >= m.min_drive_m]
        if not ways:
            return False
        direction = ways[0]
        if len(ways) == 2 and rng.random() < m.backward_probability:
            direction = -1
        speed = self._speed(direction)
        distance = _uniform(rng, (m.min_drive_m, self.room(direction)))
        accel = _uniform(rng, m.acceleration_mps2)
        reverse = rng.random() < m.reversal_probability
        brake = self._braking()
        # commanded travel until standstill: speed-up ramp + cruise + braking (0 when hard)
        per_v2 = 0.5 / accel + (0.5 / brake if brake else 0.0)
        speed = min(speed, math.sqrt(distance / per_v2))
        if speed < MIN_SPEED_MPS:
            return False
        cruise_s = (distance - speed * speed * per_v2) / speed
        leg_start = self.s
        self.command(direction * speed, 0.0, speed / accel, 0.0, "accelerate")
        cruise_start = self.command(direction * speed, 0.0, 0.0, cruise_s, "cruise")
        shift = 0.0
        at_stop = (
            with_shove and not reverse and rng.random() < self.shove_ranges.braking_probability
        )
        if with_shove and not reverse and cruise_s > 0.5 and not at_stop:
            # the leg is monotonic: checking its start and its standstill covers it
            stop_travel = 0.5 * speed * speed / brake if brake else 0.0
            leg_end = self.s + self.facing * direction * stop_travel
            t_shove = cruise_start + _uniform(rng, (0.0, cruise_s - 0.3))
            shift = self.shove(t_shove, (leg_start, leg_end))
        if reverse:
            self._reverse(direction, speed, brake)
        else:
            stop_start = self.t
            self._stop(speed, brake)
            if at_stop:  # pushed while braking: the lane from the stop's start to its end
                t_shove = stop_start + _uniform(rng, (0.0, BRAKING_SHOVE_WITHIN_S))
                shift = self.shove(t_shove, (leg_start, self.s))
        if shift:
            self.s += shift
            self.command(0.0, 0.0, 0.0, SHOVE_RECOVERY_S, "pause")
        return True

    def _braking(self) -> float | None:
        """A braking rate (m/s²), or None for a hard stop (a step to the new command)."""
        m = self.motion
        return (
            None
            if self.rng.random() < m.hard_stop_probability
            else _uniform(self.rng, m.braking_mps2)
        )

    def _speed(self, direction: int) -> float:
        m = self.motion
        speeds = m.cruise_velocity_mps if direction > 0 else m.reverse_velocity_mps
        return _uniform(self.rng, speeds)

    def _stop(self, speed: float, brake: float | None) -> None:
        ramp = speed / brake if brake else 0.0
        label = "brake" if brake else "hard stop"
        self.command(0.0, 0.0, ramp, _uniform(self.rng, self.motion.pause_s), label)

    def _reverse(self, direction: int, speed: float, brake: float | None) -> None:
        """Switch straight from ``direction * speed`` into the other way, then stop."""
        back = -direction
        back_speed = self._speed(back)
        ramp = (speed + back_speed) / brake if brake else 0.0
        self.command(back * back_speed, 0.0, ramp, 0.0, "reversal")
        # now moving back: cruise, then stop within the room left
        stop_brake = self._braking()
        stop_travel = 0.5 * back_speed * back_speed / stop_brake if stop_brake else 0.0
        room = self.room(back)
        if stop_travel > room:  # no room to brake gently: stop hard now
            stop_brake, stop_travel = None, 0.0
        distance = _uniform(self.rng, (min(stop_travel + 0.1, room), room))
        self.command(back * back_speed, 0.0, 0.0, (distance - stop_travel) / back_speed, "cruise")
        self._stop(back_speed, stop_brake)

    # -- the episode ---------------------------------------------------------------------

    def plan(self) -> MotionPlan:
        m, rng = self.motion, self.rng
        self.command(0.0, 0.0, 0.0, _uniform(rng, (0.5, 1.5)), "stand")
        while self.t < self.duration_s:
            draw = rng.random()
            with_shove = rng.random() < self.shove_ranges.probability
            if draw < m.turn_probability:
                self.turn(with_shove)
            elif draw < m.turn_probability + m.pause_probability or not self.drive(with_shove):
                self.pause(with_shove)
        commands = tuple(c for c in self.commands if c["t_s"] <= self.duration_s)
        shoves = tuple(s for s in self.shoves if s["t_s"] + s["duration_s"] <= self.duration_s)
        return MotionPlan(commands=commands, shoves=shoves, final_s_m=round(self.s, 4))


def plan_motion(
    rng: np.random.Generator,
    lane: Lane,
    motion: MotionRanges,
    shoves: ShoveRanges,
    duration_s: float,
) -> MotionPlan:
    """Draw an episode's commands and shoves, keeping the planned position in the lane.

    Args:
        rng: the episode's generator for motion.
        lane: the free stretch along the start heading, margins taken off.
        motion, shoves: the ranges to draw from.
        duration_s: the episode's length (s); the plan is cut there.

    Returns:
        Command and shove rows for a scenario table.
    """
    return _Planner(rng, lane, motion, shoves, duration_s).plan()
