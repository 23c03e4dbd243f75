"""Following a floor line into the scans after it was seen strongly.

The level view comes closer in a level scan at most ``memory_shrink_mps`` (behind a
segment across the travel, ``line_shrink_mps`` plus the sensor's travel), and not at all
behind a candidate line (:mod:`pvfilter.improved.memory`). A floor line that settles
near the structure behind it, as a held tilt in front of a wall puts it, can lose the
new points that made it a candidate: most of its points lie within the free-space
margin of that wall, and the scan looks level. Such a scan would pull the view onto the
line where it still stood in front of it, and from then on the line is what the view
holds.

A tilted plane's floor line lies on the side the plane tilts down to and moves with the
pitch, by no more than ``max_pitch_rate_rad_s`` allows. So for ``FOLLOW_S`` after scans
with a strong line, a gated segment with new points is taken for the same floor line,
and the view does not come closer behind it either, when it lies on the same side, at a
tilt within that reach of the latest strong line's, and **it has moved**: its distance
differs by more than the free-space margin from where the earliest of those lines would
lie had it stayed put in the world (moved by the sensor's travel since). A wall that
reappears where a floor line was, taken for one, stays put in the world; following it
would hold the view off it, and keep it new, for as long as it is seen.

A pitch event ends within ``max_event_s`` (the robot levels), and past it the scans are
taken as level again, so that a wall taken for a floor line cannot freeze the level
view. A tilt can last longer: a robot held leaning while it drives on, a body that
follows a ramp's slope. Its floor line then **travels with the sensor**: it keeps its
distance while the sensor moves through the world, where a wall stays put and comes
nearer or recedes by the travel. So a scan past ``max_event_s`` whose strongest
confident line left its place in the world since the world-static test's earlier scan
(:func:`travelling_line`: at least half of its returns tell, and their median left the
place) still counts as tilted, and the view does not settle onto that line. A return
tells where the sensor moved along its beam by more than twice the test's tolerance
within ``STATIC_BASELINE_S``: for a line 1.8 m ahead, a drive of about 0.3 m/s. A robot
that stands or creeps tells nothing by its travel, and the event ends at ``max_event_s``
as before, unless the test told before that its line travels (below).

Two things make the question come in time. The level view keeps a clock per beam, and
its beams settle onto returns that stood in front of them for ``max_event_s``; a line's
beams that came in front a scan or two before the scans counted as tilted settle first,
and the line, no longer new there, may be no longer confident when the scans' own clock
asks. So the filter asks whenever a beam would settle in a tilted scan, once the
world-static test's earlier scan lies within the event (before, a line not in that scan
at all left its place as a travelling one does). And the test's tolerance grows with the
range: a robot driving at 0.5-0.9 m/s tells a floor line 8 m off on some scans only
(twice the tolerance there is 0.22 m, and the earlier scan lies 0.3 s back on some
scans, 0.4 s on others). So a line the test told travels goes on travelling while the
test cannot tell, as long as it keeps the place it had then (:class:`LinePlace`: the
same side, its distance within twice the test's tolerance, its direction within
``TURN_TOLERANCE``); a wall approached too slowly to tell leaves that place as the
travel adds up, and a scan whose test tells that the line stayed put ends it.

The hold lasts as long as the scans show such a line: a line that travels with the
sensor is no wall, but it may be something that moves with the robot (a cart it follows
at a steady distance, across its path, confident as a floor line); then the view is held
off that line for as long as the robot follows it. A single scan without a confident line
ends the hold (the line's beams, in front of the view for longer than ``max_event_s``,
settle at once).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from pvfilter.improved.clusters import LineDetection
from pvfilter.improved.evidence import WorldStatic
from pvfilter.improved.geometry import TURN_TOLERANCE, folded, line_lean
from pvfilter.improved.medians import median_in_place, median_of_few
from pvfilter.improved.motion import Motion
from pvfilter.improved.params import ImprovedParams
from pvfilter.improved.scoring import HeldLine, strongest_confident
from pvfilter.improved.segmentation import Segments

TOLD_SHARE = 0.5  # of a line's returns, the share whose place the sensor's travel must tell
FOLLOW_S = 0.3  # s: how long after a scan with a strong line its floor line is followed
# (three scans at 10 Hz; a pitch event's scans come in a run)


@dataclasses.dataclass(frozen=True)
class LinePlace:
    """Where a floor line lay in the sensor frame.

    Attributes:
        side: +1 ahead, -1 behind.
        distance_m: its distance from the sensor, m.
        lean_rad: the direction of its normal from the sensor's x axis, rad
            (:func:`~pvfilter.improved.geometry.line_lean`).
    """

    side: int
    distance_m: float
    lean_rad: float

    @classmethod
    def of(cls, segments: Segments, segment: int) -> LinePlace:
        """The place of ``segments``' line ``segment``."""
        normal_x, normal_y = segments.normals[segment].tolist()
        side = 1 if segments.centroids[segment, 0] >= 0.0 else -1
        return cls(side, float(segments.distances[segment]), float(line_lean(normal_y, normal_x)))

    def kept_by(self, place: LinePlace, tolerance_m: float) -> bool:
        """``place`` is this one, as far as the world-static test could tell them apart:
        the same side, the distance within ``tolerance_m``, the direction within
        ``TURN_TOLERANCE``."""
        return (
            place.side == self.side
            and abs(place.distance_m - self.distance_m) <= tolerance_m
            and abs(float(folded(place.lean_rad - self.lean_rad))) <= TURN_TOLERANCE
        )


@dataclasses.dataclass(frozen=True)
class StrongLine:
    """The floor line of a scan that showed one strongly.

    Attributes:
        side: +1 ahead (nose down), -1 behind (nose up).
        tilt_rad: the tilt that puts the floor on it, rad.
        distance_m: its distance from the sensor, m.
        lean_rad: the direction of its normal from the sensor's x axis, rad, in
            ``[-pi/2, pi/2)`` (:func:`~pvfilter.improved.geometry.line_lean`).
        stamp: the scan's stamp, s.
        pose: the sensor's pose then, from the fixed frame of the filter's
            :class:`~pvfilter.improved.evidence.RecentScans` (to tell how far it has
            travelled since).
    """

    side: int
    tilt_rad: float
    distance_m: float
    lean_rad: float
    stamp: float
    pose: Motion

    @classmethod
    def of(cls, detection: LineDetection, pose: Motion) -> StrongLine | None:
        """The scan's strong line, if it is tilted by one (None: not); ``pose``: the
        sensor's, from a fixed frame."""
        tilt = detection.plane_tilt_rad
        if not detection.tilted or detection.down_side == 0 or np.isnan(tilt):
            return None
        scores, segments = detection.segment_scores, detection.segments
        # the strongest gated segment on the down side (the IMU may have chosen the side),
        # among those with new points that may say where the floor is (a face with returns
        # beyond it is no floor line); where there is none such, among them all
        on_side = scores.gates & (np.sign(segments.centroids[:, 0]) == detection.down_side)
        if scores.voters is not None:
            preferred = on_side & scores.voters & (scores.new_counts > 0)
            if np.count_nonzero(preferred):
                on_side = preferred
        if not np.count_nonzero(on_side):
            return None
        # the most new points; of those, the most points: the best measured direction
        new_counts = np.where(on_side, scores.new_counts, -1.0)
        strongest = int(np.lexsort((segments.sizes, new_counts))[-1])
        place = LinePlace.of(segments, strongest)
        return cls(
            detection.down_side,
            tilt,
            place.distance_m,
            place.lean_rad,
            detection.scan.stamp,
            pose,
        )


class FloorFollower:
    """The strong lines of the last ``FOLLOW_S``, and the segments that continue them."""

    def __init__(self, params: ImprovedParams) -> None:
        self.params = params
        self.lines: list[StrongLine] = []  # oldest first

    def reset(self) -> None:
        """Forget the lines (a re-baseline)."""
        self.lines.clear()

    def followed(self, detection: LineDetection, pose: Motion) -> np.ndarray | None:
        """Per beam: it lies on a segment that continues the strong lines (None: no such
        segment); then takes the scan's own strong line in.

        Args:
            detection: the scan's line detection.
            pose: the sensor's pose now, from the fixed frame the strong lines' poses are
                in (the filter's :class:`~pvfilter.improved.evidence.RecentScans` keeps it).
        """
        stamp = detection.scan.stamp
        self.lines = self._recent(stamp)
        beams = self._continuing(detection, pose) if self.lines else None
        line = StrongLine.of(detection, pose)
        if line is not None:
            self.lines.append(line)
        return beams

    def held(self, stamp: float, pose: Motion) -> HeldLine | None:
        """The floor line of a held tilt: the strong lines within ``FOLLOW_S``, if the
        sensor turned since the earliest by more than twice ``TURN_TOLERANCE`` (None: no
        strong line, or too little turn to tell it from a wall fixed in the world); its
        side and tilt the earliest's, its direction the median of theirs (a line's fitted
        direction wanders by a degree or two from scan to scan).

        Args:
            stamp: the scan's stamp, s.
            pose: the sensor's pose now, from the fixed frame the strong lines' poses are in.
        """
        recent = self._recent(stamp)
        if not recent:
            return None
        earliest = recent[0]  # the longest turn to tell by
        turn = earliest.pose.inverse().then(pose).theta_rad
        if abs(turn) <= 2.0 * TURN_TOLERANCE:
            return None
        # the line's direction from all of them: one strong line may be a floor line run
        # into a wall at a small angle, one segment, leaning between the two
        latest = recent[-1]
        leans = [folded(line.lean_rad - latest.lean_rad) for line in recent]
        lean = float(folded(latest.lean_rad + median_of_few(leans)))
        return HeldLine(earliest.side, earliest.tilt_rad, lean)

    def _recent(self, stamp: float) -> list[StrongLine]:
        """The strong lines of the ``FOLLOW_S`` before ``stamp``, oldest first."""
        return [line for line in self.lines if 0.0 < stamp - line.stamp <= FOLLOW_S]

    def _continuing(self, detection: LineDetection, pose: Motion) -> np.ndarray | None:
        params, scores, segments = self.params, detection.segment_scores, detection.segments
        if scores.gates.size == 0:
            return None
        latest, earliest = self.lines[-1], self.lines[0]
        reach = params.max_pitch_rate_rad_s * (detection.scan.stamp - latest.stamp)
        followed = scores.gates & (scores.new_counts > 0)
        if not np.count_nonzero(followed):  # (most scans: their lines were never fitted)
            return None
        followed &= np.sign(segments.centroids[:, 0]) == latest.side
        followed &= np.abs(scores.tilt_rad - latest.tilt_rad) <= reach
        if not np.count_nonzero(followed):  # none on the line's side, within its reach
            return None
        # where the earliest line would lie now had it stayed put in the world: moved
        # along x by the sensor's travel, turned back by its turn
        since = earliest.pose.inverse().then(pose)
        staying = earliest.distance_m - earliest.side * since.tx_m
        margin = params.free_margin_m + params.free_margin_rel * earliest.distance_m
        moved = np.abs(segments.distances - staying) > margin
        normals = segments.normals
        turned_to = earliest.lean_rad - since.theta_rad
        turned = (
            np.abs(folded(line_lean(normals[:, 1], normals[:, 0]) - turned_to)) > TURN_TOLERANCE
        )
        followed &= moved | turned
        if not np.count_nonzero(followed):
            return None
        beams = np.zeros(len(detection.scan), dtype=bool)
        beams[segments.beams] = followed.take(segments.labels)
        return beams


def travelling_line(
    detection: LineDetection,
    static: WorldStatic | None,
    params: ImprovedParams,
    travelled: LinePlace | None = None,
) -> tuple[np.ndarray | None, LinePlace | None]:
    """Whether the scan's strongest confident floor line travelled with the sensor.

    It travelled where at least half of its returns tell, against a return the earlier
    scan saw on the same beam (the sensor moved along their beams by more than the
    world-static test's tolerance twice,
    :meth:`~pvfilter.improved.evidence.WorldStatic.offsets`), and the median of those
    lies farther than the tolerance from where the earlier scan, moved by the sensor's
    travel, puts a surface fixed in the world (:func:`_left_its_place`). Where too few
    tell, it still travels if it keeps the place it had when the test last told that it
    travelled (``travelled``: :meth:`LinePlace.kept_by`, within twice the test's
    tolerance at its distance): the tolerance grows with the range, and a robot driving
    at a few decimetres a second tells a floor line 8 m off on some scans only. A wall
    that the sensor comes nearer to or recedes from too slowly to tell leaves that place
    as the travel adds up. A scan whose test tells that the line stayed put, that has no
    confident line, or that has no earlier scan to compare with (``static`` None: a
    fresh start, a scan the filter coasted through) ends it.

    Args:
        detection: the scan's line detection.
        static: the world-static test against an earlier scan (None: none).
        params: ``down_side_min_new`` (what makes a line confident).
        travelled: where the line lay when the test last told it travelled, as the scan
            before returned it (None: it did not travel).

    Returns:
        Per beam, the line's beams (None: it did not travel); and the place to pass as
        ``travelled`` with the next scan: this scan's line's where the test told, the
        one passed in where the line kept it (None: it did not travel).
    """
    if static is None:
        return None, None
    segments = detection.segments
    strongest = strongest_confident(segments, detection.segment_scores, params)
    if strongest is None:
        return None, None
    beams = segments.beams[segments.labels == strongest]
    place = LinePlace.of(segments, strongest)
    offsets = static.offsets(beams)
    told = offsets.telling & offsets.seen
    if np.count_nonzero(told) >= TOLD_SHARE * beams.size:
        if not _left_its_place(offsets.world_m[told], offsets.tolerance_m[told]):
            return None, None
    elif travelled is None or not travelled.kept_by(
        place, 2.0 * static.tolerance_at(place.distance_m)
    ):
        return None, None
    else:
        place = travelled  # (kept, not told: the place stays the one the test last told)
    travelling = np.zeros(len(detection.scan), dtype=bool)
    travelling[beams] = True
    return travelling, place


def _left_its_place(world_m: np.ndarray, tolerance_m: np.ndarray) -> bool:
    """A line whose returns lie ``world_m`` from where a surface fixed in the world would
    (m, all finite) left its place: their median lies farther than the median of their
    ``tolerance_m`` (both arrays are reordered). A median, not a count of returns beyond
    the tolerance: a scanner with 5 cm of range noise scatters about half of a wall's
    returns beyond it, scan after scan, while their median stays within a centimetre."""
    return abs(median_in_place(world_m)) > median_in_place(tolerance_m)  # (copies: masked)
