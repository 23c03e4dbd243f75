"""Why the filter misses: the stage that lost each missed beam, and what each false alarm hit.

For every **missed** pitch-variation beam (finite range, FLOOR/CEILING/HORIZONTAL label,
not removed), the first stage of the pipeline that lost it, in pipeline order:

| key | stage |
|---|---|
| ``invalid`` | never clustered: the range is outside ``[range_min, range_max]`` |
| ``small`` | never clustered: its cluster had fewer than ``m_th`` points |
| ``merged`` | merged into a cluster mostly of structure (at most half pitch variation) |
| ``v_c`` | the ``v_C >= v_th`` gate (detection and tracking share it) |
| ``score`` | detection: ``P(C_pv) = 1 - P(theta) P(L) <= P_th``, and no track to continue |
| ``track_distance`` | tracking: the nearest queued centroid is farther than ``d_track`` |
| ``track_band`` | tracking: the centroid's range is outside ``[d_min, d_max]`` |
| ``track_size`` | tracking: the size ratio to the associated cluster is outside the bounds |
| ``unexplained`` | none of the above: the diagnosis disagrees with the filter (a bug) |

A miss is charged to tracking only when the previous tracking queue held a cluster that
was mostly pitch variation (there was a track this cluster could continue); then the
first of Algorithm 2's checks that fails against the nearest queued cluster names it
(its ``v_C`` check is the ``v_c`` stage above). Otherwise detection lost it (``score``).
These gate outcomes are recomputed here from the filter's per-cluster records and
``FilterParams``, the same tests as :mod:`pvfilter.paper.tracking`.

For every **false alarm** (a removed beam that is not a pitch-variation point), what it
hit, from the hit geom's name (``wall_<k>``, ``door_frame_<k>_<side>``, furniture
``<kind>_<k>_<part>``), whether that surface was **first seen** (no hit of the previous
frame within ``NEW_SURFACE_M`` in the world's x-y plane), and whether the filter removed
it by detection or by tracking.
"""

from __future__ import annotations

import dataclasses
from collections import Counter

import numpy as np
from scipy.spatial import cKDTree

from pvfilter import FilterParams, FilterResult, PaperResult
from twsb_sim.frame import Frame
from twsb_sim.house import FURNITURE_KINDS
from twsb_sim.labels import is_pitch_variation

MISS_STAGES: dict[str, str] = {
    "invalid": "never clustered: invalid range",
    "small": "never clustered: cluster smaller than m_th",
    "merged": "merged into a cluster that is mostly structure",
    "v_c": "v_C gate (v_C < v_th)",
    "score": "P(θ)·P(L) not low enough (P(C_pv) ≤ P_th), no track to continue",
    "track_distance": "tracking: nearest queued cluster farther than d_track",
    "track_band": "tracking: centroid range outside [d_min, d_max]",
    "track_size": "tracking: size ratio outside [m/2, 2m]",
    "unexplained": "not explained by any stage (the diagnosis disagrees with the filter)",
}
_STAGE_KEYS = tuple(MISS_STAGES)
NOT_MISSED = -1  # stage code of a beam that is not a miss
NEW_SURFACE_M = 0.3  # m: a hit farther than this from every previous hit is first seen
MOSTLY = 0.5  # a cluster is "mostly" pitch variation when more than this share is


@dataclasses.dataclass(frozen=True, eq=False)
class Queue:
    """The tracking queue Q^{t-1} as the diagnosis needs it.

    Attributes:
        centroids: queued centroids, sensor frame, m, ``(q, 2)``.
        sizes: their sizes, ``(q,)``.
        pitch_variation: per queued cluster, True when mostly pitch-variation beams.
    """

    centroids: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros((0, 2)))
    sizes: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros(0))
    pitch_variation: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros(0, dtype=bool))


def cluster_pv_share(result: PaperResult, positive: np.ndarray) -> np.ndarray:
    """Share of each cluster's beams that are pitch-variation points."""
    clusters = result.detection.clusters
    labels = clusters.labels
    member = labels >= 0
    hits = np.bincount(labels[member], positive[member].astype(float), len(clusters))
    return hits / np.maximum(clusters.sizes, 1)


def queue_of(result: PaperResult, positive: np.ndarray) -> Queue:
    """Q^t of a scan: its detected or tracked clusters (what the next scan associates with)."""
    clusters = result.detection.clusters
    queued = result.detection.detected | result.tracked
    share = cluster_pv_share(result, positive)
    return Queue(clusters.centroids[queued], clusters.sizes[queued], share[queued] > MOSTLY)


def attribute_misses(
    frame: Frame, result: PaperResult, previous: Queue, params: FilterParams
) -> np.ndarray:
    """The stage that lost each missed beam: an index into :data:`MISS_STAGES` per beam.

    Args:
        frame: the frame (labels are the ground truth).
        result: the filter's result for ``frame.scan``.
        previous: the queue after the previous frame (empty at a sequence start).
        params: the filter's parameters.

    Returns:
        int8 per beam: the stage's index in ``MISS_STAGES``, or ``NOT_MISSED``.
    """
    positive, finite = is_pitch_variation(frame.labels), np.isfinite(frame.scan.ranges)
    stages = np.full(len(frame.scan), NOT_MISSED, dtype=np.int8)
    missed = np.flatnonzero(positive & finite & ~result.removed)
    if missed.size == 0:
        return stages
    detection = result.detection
    clusters = detection.clusters
    share = cluster_pv_share(result, positive)
    if detection.new_sequence:
        previous = Queue()
    track_exists = bool(previous.pitch_variation.any())
    code = _STAGE_KEYS.index
    valid = frame.scan.valid_mask()
    for beam in missed:
        c = clusters.labels[beam]
        if c < 0:
            stages[beam] = code("small") if valid[beam] else code("invalid")
        elif share[c] <= MOSTLY:  # at most half pitch variation: mostly structure
            stages[beam] = code("merged")
        elif detection.v_c[c] < params.v_th:
            stages[beam] = code("v_c")
        elif not track_exists:
            stages[beam] = code("score")
        else:
            check = _failed_track_check(clusters.centroids[c], clusters.sizes[c], previous, params)
            stages[beam] = code(check)
    return stages


def _failed_track_check(centroid: np.ndarray, size: int, queue: Queue, params: FilterParams) -> str:
    """The first of Algorithm 2's checks (after association) that a cluster fails."""
    gaps = np.linalg.norm(queue.centroids - centroid, axis=1)
    nearest = int(np.argmin(gaps))
    if gaps[nearest] > params.d_track:
        return "track_distance"
    if not params.d_min <= float(np.linalg.norm(centroid)) <= params.d_max:
        return "track_band"
    ratio = size / queue.sizes[nearest]
    if not params.size_ratio_min <= ratio <= params.size_ratio_max:
        return "track_size"
    return "unexplained"  # every check passes, so the filter should have tracked it


def surface_kind(geom_name: str) -> str:
    """What a geom is, for people: wall, door frame, a furniture kind, or other."""
    if geom_name.startswith("wall_"):
        return "wall"
    if geom_name.startswith("door_frame_"):
        return "door frame"
    for kind in FURNITURE_KINDS:
        if geom_name.startswith(f"{kind}_"):
            return f"furniture ({kind})"
    return geom_name or "other"


def first_seen(frame: Frame, previous: Frame | None, beams: np.ndarray) -> np.ndarray:
    """Per beam of ``beams``: no hit of ``previous`` within ``NEW_SURFACE_M`` (x-y, world)."""
    if previous is None:
        return np.ones(beams.size, dtype=bool)
    before = previous.hit_points_world[:, :2]
    before = before[np.isfinite(before).all(axis=1)]
    if len(before) == 0:
        return np.ones(beams.size, dtype=bool)
    distance, _ = cKDTree(before).query(frame.hit_points_world[beams, :2])
    return distance > NEW_SURFACE_M


def describe_false_alarms(
    frame: Frame, previous: Frame | None, result: FilterResult, geom_names: tuple[str, ...]
) -> Counter:
    """Count a frame's false-alarm beams by (what it hit, first seen?, removed how).

    Any filter whose result has clusters (:meth:`pvfilter.FilterResult.cluster_view`).

    Returns:
        Counter of ``(kind, "first seen" | "seen before", how)`` -> beams, ``how`` one of
        ``"detected"``, ``"tracked"`` and ``"new return"``: removed by no detected or
        tracked cluster (the improved filter at a ``p_th`` below its ``new_return_score``
        removes every new return, in a cluster or not).
    """
    positive, finite = is_pitch_variation(frame.labels), np.isfinite(frame.scan.ranges)
    beams = np.flatnonzero(result.removed & finite & ~positive)
    if beams.size == 0:
        return Counter()
    new = first_seen(frame, previous, beams)
    view = result.cluster_view()
    cluster_of = view.clusters.labels[beams]  # -1: in no cluster
    detected = np.append(view.detected, False)[cluster_of]
    tracked = np.append(view.tracked, False)[cluster_of]
    how = np.where(detected, "detected", np.where(tracked, "tracked", "new return"))
    ids = frame.geom_ids[beams] if frame.geom_ids is not None else np.full(beams.size, -1)
    kinds = [surface_kind(geom_names[g]) if g >= 0 else "other" for g in ids.tolist()]
    return Counter(
        (kind, "first seen" if n else "seen before", h)
        for kind, n, h in zip(kinds, new.tolist(), how.tolist(), strict=True)
    )


@dataclasses.dataclass
class RunDiagnosis:
    """The diagnosis of one or more runs.

    Attributes:
        misses: stage key -> missed beams.
        false_alarms: (kind, first seen?, detected / tracked / new return) -> false-alarm
            beams.
        examples: reason key (a stage key, or ``false_alarm``) -> (beams, snapshot) of
            the frame with the most beams for that reason.
        scores: per cluster that passed the ``v_C`` gate, a row (mostly pitch variation,
            in a pitch-variation onset frame, P(theta), P(L), P(C_pv)): what separates
            the two kinds of cluster, or fails to.
    """

    misses: Counter = dataclasses.field(default_factory=Counter)
    false_alarms: Counter = dataclasses.field(default_factory=Counter)
    examples: dict = dataclasses.field(default_factory=dict)
    scores: list = dataclasses.field(default_factory=list)

    def merge(self, other: RunDiagnosis) -> None:
        """Add another diagnosis (of the same sequence) into this one."""
        self.misses.update(other.misses)
        self.false_alarms.update(other.false_alarms)
        self.scores.extend(other.scores)
        for key, (beams, shot) in other.examples.items():
            if beams > self.examples.get(key, (0, None))[0]:
                self.examples[key] = (beams, shot)


def diagnose_run(
    frames: tuple[Frame, ...],
    results: tuple[PaperResult, ...],
    params: FilterParams,
    geom_names: tuple[str, ...],
    run_id: str,
) -> RunDiagnosis:
    """Attribute every miss and describe every false alarm of one run.

    Args:
        frames: the run's frames, in order, from a sequence start.
        results: the filter's result per frame (run with ``params``).
        params: the filter's parameters.
        geom_names: geom names of the run's model, by id.
        run_id: the run's name, for the example pictures.
    """
    from twsb_sim.evaluation.frame_pictures import snapshot

    diagnosis = RunDiagnosis()
    queue, previous, previous_had_pv = Queue(), None, False
    for frame, result in zip(frames, results, strict=True):
        positive = is_pitch_variation(frame.labels) & np.isfinite(frame.scan.ranges)
        onset = bool(positive.any()) and not previous_had_pv
        share = cluster_pv_share(result, positive)
        detection = result.detection
        for c in np.flatnonzero(detection.v_c >= params.v_th):
            scores = (detection.p_theta[c], detection.p_likelihood[c], detection.p_pv[c])
            diagnosis.scores.append((bool(share[c] > MOSTLY), onset, *map(float, scores)))
        stages = attribute_misses(frame, result, queue, params)
        lost = np.bincount(stages[stages >= 0], minlength=len(MISS_STAGES))
        false_alarms = describe_false_alarms(frame, previous, result, geom_names)
        per_reason = {key: int(n) for key, n in zip(MISS_STAGES, lost, strict=True) if n}
        diagnosis.misses.update(per_reason)
        diagnosis.false_alarms.update(false_alarms)
        if false_alarms:
            per_reason["false_alarm"] = sum(false_alarms.values())
        for key, beams in per_reason.items():
            if beams > diagnosis.examples.get(key, (0, None))[0]:
                reason = MISS_STAGES.get(key, "false alarms")
                shot = snapshot(
                    frame, result, run_id, f"most beams in one frame: {reason} ({beams})"
                )
                diagnosis.examples[key] = (beams, shot)
        queue, previous = queue_of(result, positive), frame
        previous_had_pv = bool(positive.any())
    return diagnosis
