"""Reading a data set back, with pyarrow and numpy only (no simulator needed).

.. code-block:: python

    from twsb_sim.dataset import open_dataset

    data = open_dataset("data/pv")
    for scan in data.scans(min_counts={"CEILING": 5}):      # scans with >= 5 ceiling beams
        scan.ranges, scan.labels, scan.values["pitch_rad"]
    for episode in data.episodes(include_fallen=False):
        episode.ranges            # float32[scans, beams]
    table = data.table(min_counts={"PITCH_VARIATION": 1}, columns=["ranges", "labels"])

Label counts are filtered on the per-scan count columns (``n_floor``, ``n_ceiling``, ...,
``n_pitch_variation``), so only the matching rows are decoded.

Data sets of an older format (``schema.FORMAT_VERSION``) still load: opening one warns
(:class:`DatasetFormatWarning`) with what it lacks, ``missing_columns`` lists those
columns, and asking for one of them is a ``KeyError`` that says so.
"""

from __future__ import annotations

import json
import warnings
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.parquet as pq

from twsb_sim.dataset.schema import COLUMN_SINCE, COUNT_COLUMNS, FORMAT_CHANGES, FORMAT_VERSION
from twsb_sim.dataset.store import EPISODES_FILE, finished_episodes, read_info, read_summary

if TYPE_CHECKING:
    from pvfilter import Scan


class DatasetFormatWarning(UserWarning):
    """The data set was written in an older format: it lacks some columns."""


def label_count_filter(
    min_counts: Mapping[str, int] | None = None, max_counts: Mapping[str, int] | None = None
) -> pc.Expression | None:
    """A row filter on per-scan label counts, e.g. ``min_counts={"FLOOR": 10}``.

    Keys are label names (``FLOOR``, ``CEILING``, ``HORIZONTAL``, ..., any case) or
    ``PITCH_VARIATION`` (the three together); bounds are inclusive.

    Raises:
        ValueError: for an unknown label name.
    """
    terms = []
    for bounds, compare in ((min_counts, pc.Expression.__ge__), (max_counts, pc.Expression.__le__)):
        for name, count in (bounds or {}).items():
            column = COUNT_COLUMNS.get(name.upper())
            if column is None:
                known = ", ".join(COUNT_COLUMNS)
                raise ValueError(f"label: expected one of {known}, got {name!r}")
            terms.append(compare(pc.field(column), int(count)))
    if not terms:
        return None
    expression = terms[0]
    for term in terms[1:]:
        expression = expression & term
    return expression


def _matrix(column: pa.ChunkedArray, dtype: type) -> np.ndarray:
    """A list column of equal-length rows as a 2-D array (no copy per row)."""
    rows = len(column)
    values = pa.concat_arrays([chunk.flatten() for chunk in column.chunks]) if rows else []
    flat = np.asarray(values, dtype=dtype)
    return flat.reshape(rows, -1) if rows else np.zeros((0, 0), dtype)


@dataclass(frozen=True, eq=False)
class ScanRecord:
    """One row: a labeled scan and the robot's truth at that instant."""

    episode: int
    frame: int
    stamp_s: float
    ranges: np.ndarray  # float32[beams], m, REP-117
    labels: np.ndarray  # uint8[beams], BeamLabel codes
    values: dict[str, Any]  # every other column read, by name
    intrinsics: dict[str, float]  # the LaserScan fields shared by all scans

    def scan(self) -> Scan:
        """As a :class:`pvfilter.Scan`, ready for the filter."""
        from pvfilter import Scan

        i = self.intrinsics
        return Scan(
            ranges=self.ranges.astype(np.float64),
            angle_min=i["angle_min"],
            angle_increment=i["angle_increment"],
            range_min=i["range_min"],
            range_max=i["range_max"],
            stamp=self.stamp_s,
            time_increment=i["time_increment"],
            scan_time=i["scan_time"],
        )


@dataclass(frozen=True, eq=False)
class Episode:
    """One episode's rows and its summary."""

    episode: int
    summary: dict[str, Any]
    table: pa.Table

    def __len__(self) -> int:
        return self.table.num_rows

    @property
    def ranges(self) -> np.ndarray:
        """float32[scans, beams], m."""
        return _matrix(self.table["ranges"], np.float32)

    @property
    def labels(self) -> np.ndarray:
        """uint8[scans, beams]."""
        return _matrix(self.table["labels"], np.uint8)

    def column(self, name: str) -> np.ndarray:
        """A scalar column as a numpy array."""
        return self.table[name].to_numpy()


class ScanDataset:
    """A data set written by ``twsb generate`` (see the README for its layout)."""

    def __init__(self, root: str | Path) -> None:
        self.root = Path(root)
        info = read_info(self.root)
        if info is None:
            raise FileNotFoundError(f"{self.root}: not a data set (no meta/info.json)")
        self.info: dict[str, Any] = info
        version = info.get("format_version", info.get("settings", {}).get("format_version", 1))
        self.format_version = int(version)
        if self.format_version > FORMAT_VERSION:
            raise ValueError(
                f"{self.root}: data set format {self.format_version} is newer than this "
                f"version of twsb-pvfilter reads ({FORMAT_VERSION}): update it"
            )
        self.missing_columns = tuple(
            name for name, since in COLUMN_SINCE.items() if since > self.format_version
        )
        if self.missing_columns:
            added = "; ".join(
                f"format {v}: {text}"
                for v, text in FORMAT_CHANGES.items()
                if v > self.format_version
            )
            warnings.warn(
                f"{self.root}: data set format {self.format_version} (this version writes "
                f"{FORMAT_VERSION}); it lacks what later formats added ({added}); missing "
                f"columns: {', '.join(self.missing_columns)}",
                DatasetFormatWarning,
                stacklevel=2,
            )
        self._paths = finished_episodes(self.root)
        self.summaries: dict[int, dict[str, Any]] = self._read_summaries()

    def _read_summaries(self) -> dict[int, dict[str, Any]]:
        listed = {}
        path = self.root / EPISODES_FILE
        if path.is_file():
            for line in path.read_text(encoding="utf-8").splitlines():
                summary = json.loads(line)
                listed[summary["episode"]] = summary
        # an interrupted run may have left shards newer than the list: read their footers
        return {k: listed.get(k) or read_summary(p) for k, p in self._paths.items()}

    def require(self, columns: Sequence[str]) -> None:
        """Raise a ``KeyError`` naming the columns an older data set does not have."""
        absent = [c for c in columns if c in self.missing_columns]
        if absent:
            raise KeyError(
                f"{self.root}: no column {', '.join(absent)} in a data set of format "
                f"{self.format_version} (added in format {COLUMN_SINCE[absent[0]]}: "
                f"{FORMAT_CHANGES[COLUMN_SINCE[absent[0]]]})"
            )

    @property
    def episode_ids(self) -> list[int]:
        return list(self._paths)

    @property
    def intrinsics(self) -> dict[str, float]:
        """The LaserScan fields (angle_min, angle_increment, range_min, ...) and ``beams``."""
        scan = self.info.get("scan")
        if scan is None and self.summaries:
            scan = next(iter(self.summaries.values()))["scan"]
        return scan

    def __len__(self) -> int:
        """The number of scans."""
        return sum(s["scans"] for s in self.summaries.values())

    def _selected(self, include_fallen: bool) -> list[int]:
        return [k for k, s in self.summaries.items() if include_fallen or not s["fell"]]

    def episode(
        self, episode: int, columns: Sequence[str] | None = None, where: pc.Expression | None = None
    ) -> Episode:
        """Episode ``episode`` (optionally only some columns, some rows)."""
        if episode not in self._paths:
            raise KeyError(f"{self.root}: no episode {episode}")
        self.require(columns or ())
        table = pq.read_table(self._paths[episode], columns=columns, filters=where)
        return Episode(episode, self.summaries[episode], table)

    def episodes(
        self, include_fallen: bool = True, columns: Sequence[str] | None = None
    ) -> Iterator[Episode]:
        """Every episode in order (those that ended in a fall too, unless told)."""
        for k in self._selected(include_fallen):
            yield self.episode(k, columns)

    def scans(
        self,
        min_counts: Mapping[str, int] | None = None,
        max_counts: Mapping[str, int] | None = None,
        include_fallen: bool = True,
        columns: Sequence[str] | None = None,
    ) -> Iterator[ScanRecord]:
        """Every scan in order, or those whose label counts are within the bounds.

        Args:
            min_counts, max_counts: inclusive bounds on beams per label in a scan, by
                label name or ``PITCH_VARIATION`` (see :func:`label_count_filter`).
            include_fallen: also scans of episodes that ended in a fall.
            columns: the columns to read into ``values`` besides the ranges and labels
                (default: all).
        """
        where = label_count_filter(min_counts, max_counts)
        wanted = None
        if columns is not None:
            wanted = list(dict.fromkeys(["episode", "frame", "stamp_s", "ranges", "labels",
                                         *columns]))  # fmt: skip
        for k in self._selected(include_fallen):
            episode = self.episode(k, wanted, where)
            ranges, labels = episode.ranges, episode.labels
            others = [n for n in episode.table.column_names if n not in ("ranges", "labels")]
            rows = episode.table.select(others).to_pylist()
            for i, row in enumerate(rows):
                yield ScanRecord(
                    episode=row.pop("episode"),
                    frame=row.pop("frame"),
                    stamp_s=row.pop("stamp_s"),
                    ranges=ranges[i],
                    labels=labels[i],
                    values=row,
                    intrinsics=self.intrinsics,
                )

    def table(
        self,
        min_counts: Mapping[str, int] | None = None,
        max_counts: Mapping[str, int] | None = None,
        include_fallen: bool = True,
        columns: Sequence[str] | None = None,
    ) -> pa.Table:
        """All matching rows of all episodes as one Arrow table (``.to_pandas()`` works)."""
        where = label_count_filter(min_counts, max_counts)
        tables = [self.episode(k, columns, where).table for k in self._selected(include_fallen)]
        if not tables:
            return pq.read_schema(next(iter(self._paths.values()))).empty_table()
        return pa.concat_tables(tables)


def open_dataset(root: str | Path) -> ScanDataset:
    """Open the data set in folder ``root``."""
    return ScanDataset(root)
