"""Scoring a filter on labelled scan files: per-beam precision, recall and PR-curve AUC.

A labelled scan file is a scan file (layout in :mod:`pvfilter.io`) with the ground truth
of every beam: an array ``labels`` of the shape of ``ranges`` holding the beam label codes
(0 NO_RETURN, 1 STATIC, 2 FLOOR, 3 CEILING, 4 HORIZONTAL, 5 DYNAMIC, 6 OCCLUDED), as the
simulator writes them (``twsb run --out``) and as any other generator or hand labelling
can. The robot's geometry may come with it, one value each: ``lidar_height_m``,
``axle_height_m``, ``lidar_ahead_m`` (m); a filter whose parameters have such a field is
told it.

The counting rule is the project's (:mod:`pvfilter.precision_recall`): beams with a
finite input range count; FLOOR, CEILING and HORIZONTAL beams are the positives; a beam is
predicted positive when the filter removed it. DYNAMIC beams (a moving object) and
OCCLUDED ones (the robot's own body) are neither hits nor false alarms, as in the
simulator's stress matrix.

The PR curve sweeps the filter's threshold parameter (its registry entry's
``threshold``). One pass gives every value for a ``one_pass`` filter, whose scores say at
which thresholds each beam is removed (the improved filter); any other filter runs afresh
for every value, as its state may depend on it (the paper's tracking does). A filter
without a threshold gives one point.
"""

from __future__ import annotations

import dataclasses
import math
import time
import warnings
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from pvfilter.contract import ScanFilter
from pvfilter.io import clockwise_scans, in_scan_order, read_arrays, scans_from_arrays
from pvfilter.precision_recall import PrCurve, pr_curve
from pvfilter.registry import ROBOT_GEOMETRY_FIELDS, FilterEntry
from pvfilter.scan import Scan

LABEL_NAMES = ("NO_RETURN", "STATIC", "FLOOR", "CEILING", "HORIZONTAL", "DYNAMIC", "OCCLUDED")
PITCH_VARIATION_LABELS = (2, 3, 4)  # FLOOR, CEILING, HORIZONTAL
NOT_COUNTED_LABELS = (5, 6)  # DYNAMIC, OCCLUDED: neither hits nor false alarms
STATIC_LABEL = 1
OCCLUDED_LABEL = 6
# the threshold sweep: dense near 1, where the filters' operating points are (the
# simulator's evaluations sweep the same values)
THRESHOLD_SWEEP: tuple[float, ...] = (
    *(round(0.05 * k, 2) for k in range(18)),  # 0.0 .. 0.85
    *(round(0.9 + 0.01 * k, 2) for k in range(10)),  # 0.9 .. 0.99
    0.995,
    0.999,
)
INPUT_KEYS = {"imu": ("pitch_rad", "roll_rad"), "odometry": ("pose_sensor_in_odom",)}


@dataclasses.dataclass(frozen=True)
class LabelledReport:
    """One filter over one labelled scan file.

    Attributes:
        file: the file's name without extension (with its folder's where names repeat).
        filter: the filter's name.
        scans: scans in the file.
        beams: beams counted (returns, in ``[range_min, range_max)``; not DYNAMIC or
            OCCLUDED), over the file.
        positives: of those, FLOOR, CEILING or HORIZONTAL.
        thresholds: the swept values of the filter's threshold (one, NaN, without one).
        tp, fp, fn: beam counts per swept value.
        operating_point: the threshold value the filter ran with (one of ``thresholds``).
        recall_by_label: at the operating point, the share of each positive label's
            counted beams removed (NaN: none in the file).
        static_removed: STATIC beams removed at the operating point.
        static_beams: STATIC beams counted.
        inputs: the robot inputs the filter was given.
        geometry: the robot geometry the file stated and the filter was told, m.
        scans_per_s: the filter's rate at the operating point.
        per_scan: the counts per scan at the operating point, where asked for
            (:func:`evaluate_labelled`'s ``counts_per_scan``; None: not asked).
    """

    file: str
    filter: str
    scans: int
    beams: int
    positives: int
    thresholds: tuple[float, ...]
    tp: tuple[int, ...]
    fp: tuple[int, ...]
    fn: tuple[int, ...]
    operating_point: float
    recall_by_label: dict[str, float]
    static_removed: int
    static_beams: int
    inputs: tuple[str, ...]
    geometry: dict[str, float]
    scans_per_s: float
    per_scan: ScanCounts | None = dataclasses.field(default=None, compare=False, repr=False)

    @property
    def curve(self) -> PrCurve:
        """The PR curve (its AUC by the project's rule)."""
        return pr_curve(self.thresholds, self.tp, self.fp, self.fn)

    @property
    def auc(self) -> float:
        """Area under the PR curve."""
        return self.curve.auc

    @property
    def precision(self) -> float:
        """Precision at the operating point."""
        return self._at("precision")

    @property
    def recall(self) -> float:
        """Recall at the operating point."""
        return self._at("recall")

    def _at(self, figure: str) -> float:
        curve = self.curve
        k = _index_of(curve.thresholds, self.operating_point)
        return float(getattr(curve, figure)[k])


@dataclasses.dataclass(frozen=True)
class BeamTruth:
    """A file's ground truth, per scan: which beams count, and which are positive."""

    counted: np.ndarray  # bool (m, n)
    positive: np.ndarray  # bool (m, n)
    labels: np.ndarray  # int (m, n)


@dataclasses.dataclass(frozen=True, eq=False)  # holds arrays: no field-wise ==
class ScanCounts:
    """A filter's beams per scan at its operating point: where in a file it finds the
    pitch variation, misses it, or removes structure. Each array has one value per scan
    scored (in the file's order; with ``every``, every that many scans of it).

    Attributes:
        scan: the scan's index in the file.
        stamp_s: its stamp in the file, s (a clockwise scan's too, which the reader
            moves to its first beam's time).
        beams: beams counted (as :class:`LabelledReport` counts them).
        positives: of those, FLOOR, CEILING or HORIZONTAL.
        removed: counted beams the filter removed.
        hits: removed positives.
        static_removed: removed STATIC beams (the other false alarms are NO_RETURN
            beams a file labels so while it gives them a range).
        by_label: per positive label name, its counted beams and those removed, two
            arrays.
    """

    scan: np.ndarray
    stamp_s: np.ndarray
    beams: np.ndarray
    positives: np.ndarray
    removed: np.ndarray
    hits: np.ndarray
    static_removed: np.ndarray
    by_label: dict[str, tuple[np.ndarray, np.ndarray]]

    @property
    def false_alarms(self) -> np.ndarray:
        """Removed beams that are not positives, per scan."""
        return self.removed - self.hits

    def rows(self) -> list[dict[str, float | int]]:
        """One row per scan, as the ``--per-scan`` tables write them."""
        columns = {
            "scan": self.scan,
            "stamp_s": self.stamp_s,
            "beams": self.beams,
            "positives": self.positives,
            "removed": self.removed,
            "hits": self.hits,
            "false_alarms": self.false_alarms,
            "static_removed": self.static_removed,
        }
        for name, (counted, removed) in self.by_label.items():
            columns[name.lower()] = counted
            columns[f"{name.lower()}_removed"] = removed
        names = list(columns)
        return [
            dict(zip(names, values, strict=True))
            for values in zip(*(column.tolist() for column in columns.values()), strict=True)
        ]


def scan_counts(
    removed: np.ndarray, truth: BeamTruth, file_scans: np.ndarray, stamps_s: np.ndarray
) -> ScanCounts:
    """:class:`ScanCounts` of a removed mask ``(m, n)`` over the scans of ``truth``
    (``file_scans``: each one's index in its file; ``stamps_s``: its stamp there, s)."""
    removed = removed & truth.counted
    hits = removed & truth.positive
    static = removed & (truth.labels == STATIC_LABEL)
    by_label = {}
    for code in PITCH_VARIATION_LABELS:
        beams = truth.counted & (truth.labels == code)
        by_label[LABEL_NAMES[code]] = (
            np.count_nonzero(beams, axis=1),
            np.count_nonzero(beams & removed, axis=1),
        )
    return ScanCounts(
        scan=np.asarray(file_scans, dtype=np.int64),
        stamp_s=np.asarray(stamps_s, dtype=np.float64),
        beams=np.count_nonzero(truth.counted, axis=1),
        positives=np.count_nonzero(truth.positive, axis=1),
        removed=np.count_nonzero(removed, axis=1),
        hits=np.count_nonzero(hits, axis=1),
        static_removed=np.count_nonzero(static, axis=1),
        by_label=by_label,
    )


def read_labels(arrays: Mapping[str, np.ndarray], source: str) -> np.ndarray:
    """The file's ``labels`` as integers, checked against ``ranges``.

    Raises:
        ValueError: ``"<source>: labels: ..."``: missing, of another shape than
            ``ranges``, or holding anything but the codes 0..6.
    """
    if "labels" not in arrays:
        raise ValueError(
            f"{source}: labels: missing: scoring needs the ground truth of every beam "
            "(pvfilter eval-logs counts what a filter removes from unlabelled logs)"
        )
    labels, shape = np.asarray(arrays["labels"]), np.shape(arrays["ranges"])
    if labels.shape != shape:
        raise ValueError(
            f"{source}: labels: must have the shape of ranges {shape}, got {labels.shape}"
        )
    codes = labels.astype(np.float64, copy=False)
    bad = ~np.isin(codes, np.arange(len(LABEL_NAMES)))
    if np.count_nonzero(bad):
        value = labels[bad][0].item()
        raise ValueError(
            f"{source}: labels: codes are 0..6 ({', '.join(LABEL_NAMES)}), got {value!r}"
        )
    return labels.astype(np.int64)


def scan_labels(arrays: Mapping[str, np.ndarray], source: str, count: int) -> np.ndarray:
    """The file's ``labels`` (:func:`read_labels`) in the beam order of its ``count`` scans
    as read (a clockwise file's rows reversed: :func:`pvfilter.io.in_scan_order`)."""
    return in_scan_order(read_labels(arrays, source), clockwise_scans(arrays, count))


def geometry_of(arrays: Mapping[str, np.ndarray], source: str) -> dict[str, float]:
    """The robot geometry the file states (``lidar_height_m`` ...), m.

    Raises:
        ValueError: ``"<source>: <key>: ..."`` for a value that is not one finite number.
    """
    geometry = {}
    for key in ROBOT_GEOMETRY_FIELDS:
        if key not in arrays:
            continue
        try:
            value = np.asarray(arrays[key], dtype=np.float64)
        except (TypeError, ValueError):  # (text, say)
            value = np.array([np.nan])
        if value.size != 1 or not np.isfinite(value).all():
            raise ValueError(f"{source}: {key}: must be one finite number, m")
        geometry[key] = float(value.reshape(()))
    return geometry


def robot_inputs_of(
    arrays: Mapping[str, np.ndarray], count: int, asked: Sequence[str], source: str
) -> list[dict[str, Any]]:
    """Per scan, the robot inputs ``asked`` for (``imu``: ``pitch_rad`` and ``roll_rad``;
    ``odometry``: ``pose_sensor_in_odom``, or ``odom_poses`` with ``laser_offset``).

    Raises:
        ValueError: ``"<source>: ..."``: an input the file does not hold, or one of the
            wrong shape.
    """
    from pvfilter.logs import odometry_inputs  # (the real-log evaluation reads odometry)

    per_scan: list[dict[str, Any]] = [{} for _ in range(count)]
    for name in asked:
        if name == "odometry":
            try:
                poses = odometry_inputs(dict(arrays), count)
            except ValueError as error:
                raise ValueError(f"{source}: {error}") from None
            if poses is None:
                raise ValueError(
                    f"{source}: odometry: the file has no pose_sensor_in_odom or odom_poses"
                )
            for inputs, pose in zip(per_scan, poses, strict=True):
                inputs.update(pose)
            continue
        for key in INPUT_KEYS[name]:
            if key not in arrays:
                if key == "roll_rad":
                    continue  # the filters take the roll as 0 with a pitch
                raise ValueError(f"{source}: {name}: the file has no {key} array")
            values = np.asarray(arrays[key], dtype=np.float64)
            if values.shape != (count,):
                raise ValueError(f"{source}: {key}: must have shape ({count},), got {values.shape}")
            for inputs, value in zip(per_scan, values.tolist(), strict=True):
                inputs[key] = value
    return per_scan


NOISE_SEED = 0  # the seed of the range noise added to a file's scans (the same every run)
DROPOUT_SEED = 1  # the seed of the echoes dropped from a file's scans (the same every run)
JITTER_SEED = 2  # the seed of the angle_min jitter of a file's scans (the same every run)


def with_range_noise(scans: Sequence[Scan], noise_m: float) -> list[Scan]:
    """``scans`` with Gaussian noise of ``noise_m`` (one standard deviation, m) added to
    every finite range, drawn from ``NOISE_SEED`` in scan and beam order: the same noise
    for every filter and every run. A range the noise takes outside the scan's limits is
    left there: the filter sees it as the scanner would report it."""

    def add_noise(ranges: np.ndarray, finite: np.ndarray, rng: np.random.Generator) -> None:
        ranges[finite] += rng.normal(0.0, noise_m, int(np.count_nonzero(finite)))

    return _drawn_per_scan(scans, NOISE_SEED, add_noise)


def with_dropouts(scans: Sequence[Scan], share: float) -> list[Scan]:
    """``scans`` with each finite range lost (``+inf``, no echo) with probability
    ``share``, drawn from ``DROPOUT_SEED`` in scan and beam order: the same echoes lost
    for every filter and every run, as a scanner loses them on dark, shiny or distant
    surfaces."""

    def drop(ranges: np.ndarray, finite: np.ndarray, rng: np.random.Generator) -> None:
        ranges[finite & (rng.random(ranges.size) < share)] = np.inf

    return _drawn_per_scan(scans, DROPOUT_SEED, drop)


def _drawn_per_scan(scans: Sequence[Scan], seed: int, change) -> list[Scan]:
    """``scans`` with ``change(ranges, finite, rng)`` applied in place to a copy of each
    scan's ranges, in scan order, from one generator seeded ``seed``: the same draws
    every run."""
    rng = np.random.default_rng(seed)
    changed = []
    for scan in scans:
        ranges = np.array(scan.ranges, dtype=np.float64)
        change(ranges, np.isfinite(ranges), rng)
        changed.append(scan.with_ranges(ranges))
    return changed


def with_range_max(scans: Sequence[Scan], range_max_m: float) -> list[Scan]:
    """``scans`` as a scanner that reaches ``range_max_m`` writes them: every return
    beyond it is no echo (``+inf``), and ``range_max`` is ``range_max_m``.

    Raises:
        ValueError: where ``range_max_m`` is not within every scan's
            ``(range_min, range_max]`` (the message names the reach the scans have).
    """
    low, high = max(s.range_min for s in scans), min(s.range_max for s in scans)
    if not low < range_max_m <= high:
        raise ValueError(f"--range-max {range_max_m:g}: its scans reach ({low:g}, {high:g}] m")
    changed = []
    for scan in scans:
        beyond = scan.ranges > range_max_m  # (NaN compares False; +inf stays +inf)
        ranges = np.where(beyond, np.inf, scan.ranges)
        changed.append(dataclasses.replace(scan, ranges=ranges, range_max=range_max_m))
    return changed


def with_beam_stride(
    scans: Sequence[Scan], labels: np.ndarray, stride: int
) -> tuple[list[Scan], np.ndarray]:
    """``scans`` and their ``labels`` (``(scans, beams)``) with every ``stride``-th beam
    kept, from beam 0: the scans a scanner with that many times coarser a spacing would
    write over the same sweep (``angle_increment`` and ``time_increment`` times
    ``stride``; intensities kept with their beams). On a full turn a stride that does not
    divide the beam count leaves a narrower step across the seam."""

    def thinned(scan: Scan) -> Scan:
        intensities = None if scan.intensities is None else scan.intensities[::stride]
        return dataclasses.replace(
            scan,
            ranges=scan.ranges[::stride],
            angle_increment=scan.angle_increment * stride,
            time_increment=scan.time_increment * stride,
            intensities=intensities,
        )

    return [thinned(scan) for scan in scans], np.asarray(labels)[:, ::stride]


def with_angle_jitter(scans: Sequence[Scan], beams: float) -> list[Scan]:
    """``scans`` with each ``angle_min`` moved by a uniform draw within ``beams`` / 2 of
    a beam either way, from ``JITTER_SEED`` in scan order, the ranges kept: as drivers
    that take ``angle_min`` from each turn's first sample write it. Each scan is the one
    a sensor turned by that fraction of a beam would see: its beams hit what they hit."""
    rng = np.random.default_rng(JITTER_SEED)
    shifts = rng.uniform(-0.5, 0.5, len(scans)) * beams
    return [
        dataclasses.replace(scan, angle_min=scan.angle_min + shift * scan.angle_increment)
        for scan, shift in zip(scans, shifts, strict=True)
    ]


def with_occluded_reads(scans: Sequence[Scan], labels: np.ndarray, value: float) -> list[Scan]:
    """``scans`` with every OCCLUDED beam (the sector the robot's body blocks) read as
    ``value``: ``+inf`` as a driver that reports the body as no echo, ``-inf`` as REP-117
    has a body closer than ``range_min``, ``NaN`` as an invalid reading, a range as a body
    that returns there (a mast or a frame a few decimetres from the sensor).

    Args:
        scans: the file's scans.
        labels: their beam label codes, ``(scans, beams)``.
        value: the range every OCCLUDED beam reads, m.
    """
    occluded = np.asarray(labels) == OCCLUDED_LABEL
    return [
        scan.with_ranges(np.where(blocked, value, scan.ranges))
        for scan, blocked in zip(scans, occluded, strict=True)
    ]


def with_no_echo_reads(scans: Sequence[Scan], value: float | str) -> list[Scan]:
    """``scans`` with every beam that returned nothing (``+inf``) read as ``value``, as
    scanners differ in writing no echo: ``0.0`` (as many low-cost scanners' drivers do),
    ``NaN`` (invalid, by REP-117), or ``"range_max"``, the scan's own limit, as a clamping
    driver or simulator writes it. :meth:`Scan.no_echo_mask` reads all but ``NaN`` as no
    echo again."""
    changed = []
    for scan in scans:
        read = scan.range_max if value == "range_max" else float(value)
        changed.append(scan.with_ranges(np.where(scan.ranges == np.inf, read, scan.ranges)))
    return changed


def evaluate_labelled(
    path: str | Path,
    entry: FilterEntry,
    params: Any = None,
    fields: Mapping[str, Any] | None = None,
    inputs: Sequence[str] = (),
    thresholds: Sequence[float] = THRESHOLD_SWEEP,
    name: str | None = None,
    range_noise_m: float = 0.0,
    occluded_reads: float | None = None,
    dropout_share: float = 0.0,
    no_echo_reads: float | str | None = None,
    angle_jitter_beams: float = 0.0,
    imu_nose_up: bool = False,
    every: int = 1,
    beam_stride: int = 1,
    range_max_m: float | None = None,
    ignore_geometry: bool = False,
    counts_per_scan: bool = False,
) -> LabelledReport | None:
    """Run the filter over a labelled scan file, and count per swept threshold.

    Args:
        path: the scan file (.npz) with ``labels``.
        entry: the filter's registry entry.
        params: its parameters (None: its defaults).
        fields: parameter values that replace those of ``params`` (they win over the
            geometry the file states).
        inputs: the robot inputs to give (``imu``, ``odometry``), those the filter
            accepts; none: the scans alone.
        thresholds: the values of the filter's threshold to sweep; the operating point
            (its parameters' value) is added when missing.
        name: the file's name in the report (None: its name without extension).
        range_noise_m: Gaussian noise added to every finite range first, one standard
            deviation, m (0: none): a noisier scanner than the file's, the same draws for
            every filter and run (:func:`with_range_noise`).
        occluded_reads: the range every OCCLUDED beam reads instead of the file's (None:
            the file's; :func:`with_occluded_reads`).
        dropout_share: the share of the finite ranges lost, read as no echo, after the
            noise (0: none; :func:`with_dropouts`).
        no_echo_reads: what every beam without an echo reads, last (the dropouts and
            occluded beams read as ``+inf`` included): a range, or ``"range_max"`` (None:
            ``+inf``, as the file has it; :func:`with_no_echo_reads`).
        angle_jitter_beams: each scan's ``angle_min`` moved within half this many beams
            either way (0: none; :func:`with_angle_jitter`).
        imu_nose_up: the IMU's pitch negated, as an IMU that gives it positive nose up
            (the other convention) would feed it.
        every: every this many scans is kept, from the first, with its labels and inputs
            (1: all): a thinned log, or a scanner that scans that many times less often.
        beam_stride: every this many beams is kept, from beam 0, with its labels, after
            ``every`` (1: all): a scanner with that many times coarser a spacing
            (:func:`with_beam_stride`).
        range_max_m: every return beyond this range reads no echo, after the range noise
            (None: the file's reach): a scanner that reaches less far, and measures its
            noisy ranges against it (:func:`with_range_max`).
        ignore_geometry: the robot geometry the file states is not told to the filter,
            which takes its own values (a user who did not set them).
        counts_per_scan: keep the counts per scan at the operating point in the report
            (:class:`ScanCounts`).

    Returns:
        The report; None when the file holds no scans.

    Raises:
        ValueError: ``"<path>: ..."`` for a malformed file or a missing input.
    """
    path = Path(path)
    arrays = read_arrays(path)
    if "ranges" not in arrays:
        return None
    source = str(path)
    scans = scans_from_arrays(arrays, source=source)
    if not scans:
        return None
    labels = scan_labels(arrays, source, len(scans))
    count = len(scans)  # the file's, for its per-scan inputs
    scans, labels = scans[::every], labels[::every]
    file_scans = np.arange(0, count, every)  # each kept scan's index in the file
    if beam_stride < 1:
        raise ValueError(f"beam_stride: a number of beams >= 1, got {beam_stride}")
    if beam_stride > 1:
        if beam_stride * 2 > len(scans[0]):
            raise ValueError(
                f"{source}: --beam-stride {beam_stride} leaves fewer than 2 of its "
                f"{len(scans[0])} beams"
            )
        scans, labels = with_beam_stride(scans, labels, beam_stride)
    if occluded_reads is not None:  # (first: a body that returns scatters with the noise)
        scans = with_occluded_reads(scans, labels, occluded_reads)
    if range_noise_m > 0.0:
        scans = with_range_noise(scans, range_noise_m)
    if range_max_m is not None:
        try:
            scans = with_range_max(scans, range_max_m)
        except ValueError as error:
            raise ValueError(f"{source}: {error}") from None
    if dropout_share > 0.0:
        scans = with_dropouts(scans, dropout_share)
    if no_echo_reads is not None:
        scans = with_no_echo_reads(scans, no_echo_reads)
    if angle_jitter_beams > 0.0:
        scans = with_angle_jitter(scans, angle_jitter_beams)
    truth = truth_of(labels, scans)
    fields = dict(fields or {})
    stated = {} if ignore_geometry else geometry_of(arrays, source)
    geometry = {k: v for k, v in stated.items() if k not in fields}
    takes = (
        set()
        if entry.params_type is None
        else {f.name for f in dataclasses.fields(entry.params_type)}
    )
    told = {k: v for k, v in geometry.items() if k in takes}  # what the filter is told
    usable = set(entry.accepts) | set(entry.needs)  # (a filter gets what it takes)
    per_scan = robot_inputs_of(arrays, count, inputs, source)[::every]
    per_scan = [{k: v for k, v in extra.items() if k in usable} for extra in per_scan]
    if imu_nose_up:
        per_scan = [
            {**extra, "pitch_rad": -extra["pitch_rad"]} if "pitch_rad" in extra else extra
            for extra in per_scan
        ]

    def make(**extra: Any) -> ScanFilter:
        return entry.make(params, robot_geometry=geometry, **{**fields, **extra})

    operating = _operating_point(entry, params, fields)
    values = np.unique(np.append(np.asarray(thresholds, dtype=np.float64), operating))
    if entry.threshold is None:
        values = np.array([operating])
    if entry.one_pass or entry.threshold is None:
        counts, at_operating, rate = _one_pass(make(), scans, per_scan, truth, values, operating)
    else:  # a fresh pass per value; the operating point's (one of them) is the one reported
        counts = np.zeros((values.size, 3), dtype=np.int64)
        for k, value in enumerate(values.tolist()):
            removed, pass_rate = _removed(make(**{entry.threshold: value}), scans, per_scan)
            counts[k] = _counts(removed, truth)
            if value == operating:
                at_operating, rate = removed, pass_rate
    stamps = np.broadcast_to(np.asarray(arrays["stamps"], dtype=np.float64), (count,))[::every]
    scanned = scan_counts(at_operating, truth, file_scans, stamps)
    by_label = {}
    for label, (beams, found) in scanned.by_label.items():
        total = int(beams.sum())
        by_label[label] = int(found.sum()) / total if total else math.nan
    static = truth.counted & (truth.labels == STATIC_LABEL)
    return LabelledReport(
        file=path.stem if name is None else name,
        filter=entry.name,
        scans=len(scans),
        beams=int(scanned.beams.sum()),
        positives=int(scanned.positives.sum()),
        thresholds=tuple(values.tolist()),
        tp=tuple(counts[:, 0].tolist()),
        fp=tuple(counts[:, 1].tolist()),
        fn=tuple(counts[:, 2].tolist()),
        operating_point=operating,
        recall_by_label=by_label,
        static_removed=int(scanned.static_removed.sum()),
        static_beams=int(np.count_nonzero(static)),
        inputs=tuple(sorted({k for extra in per_scan for k in extra})),
        geometry=told,
        scans_per_s=rate,
        per_scan=scanned if counts_per_scan else None,
    )


def pooled(reports: Sequence[LabelledReport]) -> PrCurve:
    """The PR curve of one filter's reports with their counts summed (the files taken as
    one sequence). Their swept values must agree."""
    first = reports[0].thresholds
    if any(not np.array_equal(r.thresholds, first, equal_nan=True) for r in reports):
        raise ValueError("pooled: the reports were swept over different thresholds")
    tp, fp, fn = (np.sum([getattr(r, k) for r in reports], axis=0) for k in ("tp", "fp", "fn"))
    return pr_curve(first, tp, fp, fn)


def _operating_point(entry: FilterEntry, params: Any, fields: Mapping[str, Any]) -> float:
    """The threshold value the filter runs with (NaN: it has none)."""
    if entry.threshold is None:
        return math.nan
    if entry.threshold in fields:
        return float(fields[entry.threshold])
    params = entry.default_params() if params is None else params
    return float(getattr(params, entry.threshold))


def truth_of(labels: np.ndarray, scans: Sequence[Scan]) -> BeamTruth:
    """Which beams of ``scans`` are scored, and which of those are positive, by their
    ``labels`` (in the scans' beam order). Scored: the returns, in ``[range_min,
    range_max]`` but the no-echo encodings ``range_max`` itself and ``0.0``
    (:meth:`Scan.no_echo_mask`), and not DYNAMIC or OCCLUDED. A beam a file writes out of
    range or as no echo holds no point to remove, whatever its label says it would have
    hit."""
    returns = np.zeros(np.shape(labels), bool)
    for row, scan in zip(returns, scans, strict=True):
        row[:] = scan.valid_mask() & ~scan.no_echo_mask()
    counted = returns & ~np.isin(labels, NOT_COUNTED_LABELS)
    positive = counted & np.isin(labels, PITCH_VARIATION_LABELS)
    return BeamTruth(counted, positive, labels)


def _run(scan_filter: ScanFilter, scans: Sequence[Scan], per_scan: Sequence[dict]):
    """Every result of a fresh pass, and the pass's rate (scans per second)."""
    scan_filter.reset()
    with warnings.catch_warnings():  # stamps that go back: the filters say so, once each
        warnings.simplefilter("ignore")
        start = time.perf_counter()
        results = [
            scan_filter.process(s, **extra) for s, extra in zip(scans, per_scan, strict=True)
        ]
        seconds = time.perf_counter() - start
    return results, (len(scans) / seconds if seconds > 0.0 else math.inf)


def _removed(scan_filter: ScanFilter, scans: Sequence[Scan], per_scan: Sequence[dict]):
    results, rate = _run(scan_filter, scans, per_scan)
    return np.stack([r.removed for r in results]), rate


def _counts(removed: np.ndarray, truth: BeamTruth) -> np.ndarray:
    """(tp, fp, fn) of one removed mask over the counted beams."""
    predicted = removed & truth.counted
    tp = int(np.count_nonzero(predicted & truth.positive))
    return np.array(
        [tp, int(np.count_nonzero(predicted)) - tp, int(np.count_nonzero(truth.positive)) - tp]
    )


def _one_pass(scan_filter, scans, per_scan, truth: BeamTruth, values: np.ndarray, operating: float):
    """Counts per value from one pass: a beam is removed at ``v`` when its score exceeds
    ``v`` (a filter without a threshold: its removed mask, one point)."""
    results, rate = _run(scan_filter, scans, per_scan)
    removed = np.stack([r.removed for r in results])
    if math.isnan(operating):
        return _counts(removed, truth)[None, :], removed, rate
    scores = np.stack([r.scores for r in results])
    counted, positive = scores[truth.counted], truth.positive[truth.counted]
    # per value, beams scoring above it: from the sorted scores, without a (k, beams) mask
    positives = np.count_nonzero(positive)
    above = counted.size - np.searchsorted(np.sort(counted), values, side="right")
    tp = positives - np.searchsorted(np.sort(counted[positive]), values, side="right")
    counts = np.stack([tp, above - tp, positives - tp], axis=1)
    return counts, removed, rate


def _index_of(thresholds: np.ndarray, value: float) -> int:
    if math.isnan(value):
        return 0
    return int(np.flatnonzero(np.asarray(thresholds) == value)[0])
