"""Scan files: a documented ``.npz`` layout, so recorded scans can be filtered offline.

Input arrays (``m`` scans of ``n`` beams; a scalar field may also be one value per scan):

========================  ==========  =====================================================
key                       shape       meaning
========================  ==========  =====================================================
``ranges``                (m, n)      ranges, m, REP-117 (``inf``, ``-inf``, ``NaN``)
``stamps``                (m,)        scan times, s, non-decreasing
``angle_min``             () or (m,)  angle of beam 0, rad
``angle_increment``       () or (m,)  angle between beams, rad; negative: clockwise
``range_min``             () or (m,)  smallest valid range, m
``range_max``             () or (m,)  largest valid range, m
``time_increment``        () or (m,)  optional, s between beams (default 0)
``scan_time``             () or (m,)  optional, s between scans (default 0)
``intensities``           (m, n)      optional
``labels``                (m, n)      optional, ground truth: the beam label codes 0..6
                                      (``pvfilter eval-labels`` scores filters with them)
``pitch_rad``             (m,)        optional robot input: the pitch the robot's
                                      estimator gave, rad, positive nose down (also
                                      ``roll_rad``)
``pose_sensor_in_odom``   (m, 3)      optional robot input: the LiDAR's odometry pose
                                      ``(x m, y m, yaw rad)``
``lidar_height_m``        ()          optional robot geometry, m (also ``axle_height_m``,
                                      ``lidar_ahead_m``): the ``pvfilter`` command and
                                      ``eval-labels`` tell the filters that take it
========================  ==========  =====================================================

The output file holds every input array unchanged except ``ranges``, which holds the
filtered ranges (removed beams are NaN), plus ``removed`` (bool, (m, n)) and ``scores``
(float64, (m, n): P(C_pv) of each beam's cluster; the improved filter's claim scores).
Other input arrays (labels, say) pass through, so the output is itself a valid input
file.

A file whose ``angle_increment`` is negative (beams clockwise, as ROS allows and some
drivers and simulators write; every scan of a file in one order) is read reversed, as
:meth:`Scan.counter_clockwise` reverses a message: the filters see its beams
counter-clockwise, each at its own angle and time. Per-beam arrays of the file
(``labels``, say) are taken in the same order with :func:`in_scan_order`, and the
output's per-beam arrays are written back in the file's.
"""

from __future__ import annotations

import os
import secrets
import stat
import zipfile
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import BinaryIO

import numpy as np

from pvfilter.result import FilterResult
from pvfilter.scan import Scan

REQUIRED_KEYS = ("ranges", "stamps", "angle_min", "angle_increment", "range_min", "range_max")
PER_SCAN_KEYS = (
    "angle_min",
    "angle_increment",
    "range_min",
    "range_max",
    "time_increment",
    "scan_time",
)


def read_arrays(path: str | Path) -> dict[str, np.ndarray]:
    """All arrays of an ``.npz`` file (no pickled objects).

    Raises:
        OSError: the file cannot be opened.
        ValueError: ``"<path>: ..."``: not an ``.npz`` archive (empty, truncated, another
            kind of file), or an array of Python objects.
    """
    try:
        with np.load(path, allow_pickle=False) as data:
            if not isinstance(data, np.lib.npyio.NpzFile):
                raise ValueError(f"{path}: a single .npy array, not an .npz scan file")
            return {key: data[key] for key in data.files}
    except (EOFError, zipfile.BadZipFile, UnicodeDecodeError):
        message = "not an .npz scan file (empty, truncated or another format)"
        raise ValueError(f"{path}: {message}") from None
    except ValueError as error:
        if str(error).startswith(str(path)):
            raise
        if "Object arrays" in str(error):
            message = "holds arrays of Python objects; scan files hold numbers"
            raise ValueError(f"{path}: {message}") from None
        raise ValueError(f"{path}: not an .npz scan file ({error.__class__.__name__})") from None


def scans_from_arrays(arrays: dict[str, np.ndarray], source: str = "arrays") -> list[Scan]:
    """Build the scans described by the arrays of a scan file (see the module docstring).

    Args:
        arrays: the file's arrays by key.
        source: where they came from, for error messages.

    Raises:
        ValueError: ``"<source>: <key>: <what is wrong>"`` for a missing or malformed
            array, or ``"<source>: scan <i>: <field>: ..."`` for a scan that is invalid.
    """
    missing = [key for key in REQUIRED_KEYS if key not in arrays]
    if missing:
        raise ValueError(f"{source}: {missing[0]}: missing (required: {', '.join(REQUIRED_KEYS)})")
    ranges = np.asarray(arrays["ranges"])
    if ranges.dtype.kind not in "biuf":  # (text, objects: named, not failed on later)
        raise ValueError(f"{source}: ranges: must be numbers, got {ranges.dtype}")
    if ranges.ndim != 2:
        raise ValueError(f"{source}: ranges: must be 2-D (scans, beams), got shape {ranges.shape}")
    count = len(ranges)
    fields = {"stamp": _per_scan(arrays, "stamps", count, source)}
    for key in PER_SCAN_KEYS:
        if key in arrays:
            fields[key] = _per_scan(arrays, key, count, source)
    increments = fields["angle_increment"]
    if np.any(increments < 0.0) and np.any(increments > 0.0):
        # (each is read counter-clockwise, its stamp moved to its first beam's time: in
        # one file, the time between scans would swing by a sweep)
        raise ValueError(
            f"{source}: angle_increment: the scans run both clockwise and counter-clockwise; "
            "a file holds scans of one order"
        )
    intensities = arrays.get("intensities")
    if intensities is not None and np.shape(intensities) != ranges.shape:
        raise ValueError(f"{source}: intensities: must have the shape of ranges {ranges.shape}")
    scans = []
    for i in range(count):
        try:
            scan, _ = Scan.counter_clockwise(
                ranges=ranges[i],
                **{k: float(v[i]) for k, v in fields.items()},
                intensities=None if intensities is None else intensities[i],
            )
        except ValueError as error:
            raise ValueError(f"{source}: scan {i}: {error}") from None
        scans.append(scan)
    return scans


def clockwise_scans(arrays: dict[str, np.ndarray], count: int) -> np.ndarray:
    """Which of a file's ``count`` scans run clockwise (negative ``angle_increment``),
    bool ``(count,)``: :func:`scans_from_arrays` reads them reversed."""
    increments = np.asarray(arrays["angle_increment"], dtype=np.float64)
    return np.broadcast_to(increments < 0.0, (count,))


def in_scan_order(per_beam: np.ndarray, clockwise: np.ndarray) -> np.ndarray:
    """A file's per-beam array ``(m, n)`` in the order of the scans read from it: the rows
    of clockwise scans reversed. The same call maps a result back to the file's order."""
    if not np.any(clockwise):
        return per_beam
    ordered = np.array(per_beam)
    ordered[clockwise] = ordered[clockwise, ::-1]
    return ordered


def load_scans(path: str | Path) -> list[Scan]:
    """Read the scans of a scan file (see the module docstring)."""
    return scans_from_arrays(read_arrays(path), source=str(path))


def arrays_from_scans(scans: Sequence[Scan]) -> dict[str, np.ndarray]:
    """The arrays of a scan file holding ``scans`` (all with the same beam count).

    Raises:
        ValueError: if the scans do not all have the same number of beams.
    """
    if len({len(scan) for scan in scans}) > 1:
        raise ValueError("ranges: every scan of a file must have the same number of beams")
    arrays = {
        "ranges": _stack([s.ranges for s in scans], len(scans[0]) if scans else 0, np.float64),
        "stamps": np.array([s.stamp for s in scans], dtype=np.float64),
    }
    for key in PER_SCAN_KEYS:
        arrays[key] = np.array([getattr(s, key) for s in scans], dtype=np.float64)
    if scans and all(s.intensities is not None for s in scans):
        arrays["intensities"] = np.array([s.intensities for s in scans])
    return arrays


def save_results(
    path: str | Path, arrays: dict[str, np.ndarray], results: Sequence[FilterResult]
) -> None:
    """Write a filtered scan file: the input ``arrays`` with filtered ``ranges``, plus
    ``removed`` and ``scores``.

    The file is written under a temporary name beside ``path`` and renamed into place, so
    an interrupted write never leaves a truncated file, nor touches an existing one.

    Args:
        path: the output file, written under exactly this name.
        arrays: the input file's arrays.
        results: one result per scan, in order.
    """
    beams = np.shape(arrays["ranges"])[1]
    clockwise = clockwise_scans(arrays, len(results))
    output = dict(arrays)
    for key, values, dtype in (
        ("ranges", [r.scan.ranges for r in results], np.float64),
        ("removed", [r.removed for r in results], bool),
        ("scores", [r.scores for r in results], np.float64),
    ):
        output[key] = in_scan_order(_stack(values, beams, dtype), clockwise)
    write_atomically(path, lambda file: np.savez_compressed(file, **output))


def write_atomically(path: str | Path, write: Callable[[BinaryIO], object]) -> None:
    """Call ``write`` on a temporary file beside ``path``, then rename it to ``path``.

    The file gets the permissions a plain ``open`` would give it: an existing file's own,
    else ``0o666`` less the process's umask (``tempfile.mkstemp`` makes it readable by its
    owner alone, and a filtered log that the robot's other users and nodes cannot read is
    no use to them).
    """
    path = Path(path)
    handle, temporary = _new_beside(path)
    try:
        if path.exists():  # (an overwritten file keeps its mode, as open() keeps it)
            os.chmod(temporary, stat.S_IMODE(path.stat().st_mode))
        with os.fdopen(handle, "wb") as file:
            write(file)
        os.replace(temporary, path)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise


def _new_beside(path: Path) -> tuple[int, str]:
    """A new file beside ``path`` (``.<name>.<random>.partial``), opened for writing, made
    with mode ``0o666`` for the system to take the umask from (``os.open``), and its name."""
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0)
    for _ in range(100):  # (a name taken: another random one)
        name = str(path.parent / f".{path.name}.{secrets.token_hex(4)}.partial")
        try:
            return os.open(name, flags, 0o666), name
        except FileExistsError:
            continue
    raise FileExistsError(f"{path.parent}: no free name for a temporary file")


def _per_scan(arrays: dict[str, np.ndarray], key: str, count: int, source: str) -> np.ndarray:
    values = _numbers(arrays, key, source)
    if values.shape not in ((), (count,)):
        raise ValueError(
            f"{source}: {key}: must be one value or one per scan ({count}), "
            f"got shape {values.shape}"
        )
    return np.broadcast_to(values, (count,))


def _numbers(arrays: dict[str, np.ndarray], key: str, source: str) -> np.ndarray:
    """``arrays[key]`` as float64. Text (digits too, as for ``ranges``) and objects are
    refused with the key named, not with a bare ``could not convert string to float``."""
    values = np.asarray(arrays[key])
    if values.dtype.kind not in "biuf":
        raise ValueError(f"{source}: {key}: must be numbers, got {values.dtype}")
    return values.astype(np.float64, copy=False)


def _stack(rows: list[np.ndarray], beams: int, dtype: type) -> np.ndarray:
    return np.array(rows, dtype=dtype).reshape(len(rows), beams)
