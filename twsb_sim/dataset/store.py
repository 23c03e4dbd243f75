"""The files of a data set on disk: shards, metadata, and how they are written safely.

Layout (the one LeRobot uses, one Parquet file per episode, 1000 per chunk folder)::

    OUT/meta/info.json                           settings, LaserScan intrinsics, labels,
                                                 schema, totals
    OUT/meta/episodes.jsonl                      one summary per episode, in episode order
    OUT/data/chunk-000/episode_000000.parquet    one row per scan (see schema.py)

A shard is complete or absent: it is written under a hidden temporary name (``.``-prefixed,
which pyarrow and pandas skip), flushed to disk, then renamed. Its footer also holds the
episode's summary, so the metadata files can always be rebuilt from the shards alone.

Needs pyarrow and numpy only (no simulator).
"""

from __future__ import annotations

import io
import json
import os
import re
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import pyarrow as pa
import pyarrow.parquet as pq

from twsb_sim.dataset.schema import COLUMNS, EPISODE_METADATA_KEY, FORMAT_VERSION
from twsb_sim.labels import BeamLabel

EPISODES_PER_CHUNK = 1000
INFO_FILE = Path("meta") / "info.json"
EPISODES_FILE = Path("meta") / "episodes.jsonl"
DATA_DIR = "data"
ZSTD_LEVEL = 1  # higher levels take longer and gain < 1 % on these columns
_SHARD_NAME = re.compile(r"episode_(\d{6,})\.parquet")


class DatasetMismatchError(ValueError):
    """``--out`` holds a data set made with other settings (or something else entirely).

    Attributes:
        root: the folder.
        reason: what is wrong with it.
    """

    def __init__(self, root: Path, reason: str) -> None:
        self.root, self.reason = root, reason
        super().__init__(f"{root}: {reason}")


def episode_path(root: Path, episode: int) -> Path:
    """Where episode ``episode``'s shard lives."""
    chunk = episode // EPISODES_PER_CHUNK
    return root / DATA_DIR / f"chunk-{chunk:03d}" / f"episode_{episode:06d}.parquet"


def encode_shard(table: pa.Table, summary: dict[str, Any]) -> bytes:
    """The bytes of a shard: the table, zstd-compressed, with the summary in its footer."""
    metadata = {EPISODE_METADATA_KEY: json.dumps(summary, sort_keys=True).encode()}
    sink = io.BytesIO()
    pq.write_table(
        table.replace_schema_metadata(metadata),
        sink,
        compression="zstd",
        compression_level=ZSTD_LEVEL,
        use_dictionary=["phase"],
        use_byte_stream_split=["ranges.list.element"],  # floats: 12 % smaller
    )
    return sink.getvalue()


def write_atomic(path: Path, data: bytes) -> None:
    """Write ``data`` to ``path`` so that ``path`` is either complete or absent, and no
    temporary file is left behind, even when an interrupt (Ctrl-C) lands mid-write."""
    path.parent.mkdir(parents=True, exist_ok=True)
    temporary = path.with_name(f".{path.name}.partial")
    try:
        with open(temporary, "wb") as file:
            file.write(data)
            file.flush()
            os.fsync(file.fileno())
        os.replace(temporary, path)
    except BaseException:
        temporary.unlink(missing_ok=True)  # (gone already if the rename happened)
        raise
    directory = os.open(path.parent, os.O_RDONLY)
    try:
        os.fsync(directory)  # the rename itself survives a power cut
    finally:
        os.close(directory)


def finished_episodes(root: Path) -> dict[int, Path]:
    """The shards present under ``root``, by episode number."""
    shards = {}
    for path in (root / DATA_DIR).glob("chunk-*/episode_*.parquet"):
        match = _SHARD_NAME.fullmatch(path.name)
        if match:
            shards[int(match.group(1))] = path
    return dict(sorted(shards.items()))


def remove_partial_files(root: Path) -> None:
    """Delete temporary files left by an interrupted run."""
    for path in [
        *(root / DATA_DIR).glob("chunk-*/.*.partial"),
        *(root / "meta").glob(".*.partial"),
    ]:
        path.unlink(missing_ok=True)


def _is_unfinished_creation(root: Path) -> bool:
    """Whether ``root`` holds nothing but what an interrupted creation of a data set leaves:
    the ``meta``, ``data`` and ``data/chunk-*`` folders and hidden ``.partial`` files, no
    ``meta/info.json`` yet (so no finished episode either: shards follow it)."""
    for path in root.rglob("*"):
        relative = path.relative_to(root)
        if path.is_dir() and not path.is_symlink():
            top = relative.parts[0]
            if top not in ("meta", DATA_DIR) or (top == "meta" and len(relative.parts) > 1):
                return False
            if (
                top == DATA_DIR
                and len(relative.parts) > 1
                and not (len(relative.parts) == 2 and relative.parts[1].startswith("chunk-"))
            ):
                return False
        elif not (path.name.startswith(".") and path.name.endswith(".partial")):
            return False
    return True


def read_summary(path: Path) -> dict[str, Any]:
    """The episode summary stored in a shard's footer."""
    metadata = pq.read_schema(path).metadata or {}
    return json.loads(metadata[EPISODE_METADATA_KEY])


def _write_json(path: Path, value: Any) -> None:
    write_atomic(path, (json.dumps(value, indent=2, sort_keys=False) + "\n").encode())


def read_info(root: Path) -> dict[str, Any] | None:
    """The data set's ``meta/info.json``, or None when there is none.

    Raises:
        DatasetMismatchError: the file is there but is not JSON.
    """
    try:
        return json.loads((root / INFO_FILE).read_text(encoding="utf-8"))
    except FileNotFoundError:
        return None
    except ValueError as error:  # not UTF-8, or not JSON
        raise DatasetMismatchError(
            root, f"{INFO_FILE} is not a data set's metadata (not JSON: {error})"
        ) from None


def prepare_output(root: Path, settings: dict[str, Any]) -> None:
    """Make ``root`` ready to receive episodes generated with ``settings``.

    A new or empty folder gets a ``meta/info.json``; a folder holding a data set made
    with the same settings is resumed (partial files of an interrupted run removed). So
    is a folder whose creation was interrupted before ``meta/info.json`` appeared: it
    holds only empty folders and ``.partial`` files, which are removed, and the creation
    starts over. A kill at any moment thus leaves a folder the same command resumes.

    Raises:
        DatasetMismatchError: ``root`` is a file, holds other files, or holds a data set
            whose settings differ (the message lists which).
    """
    if root.exists() and not root.is_dir():
        raise DatasetMismatchError(root, "is a file, not a folder; choose a new --out")
    info = read_info(root)
    if info is None:
        if root.exists() and not _is_unfinished_creation(root):
            raise DatasetMismatchError(
                root, f"not empty and not a data set (no {INFO_FILE}); choose a new --out"
            )
        remove_partial_files(root)
        _write_json(root / INFO_FILE, {"settings": settings})
        return
    stored = info.get("settings", {})
    differences = sorted(_differences(stored, settings))
    if differences:
        listed = "; ".join(differences[:5]) + ("; ..." if len(differences) > 5 else "")
        raise DatasetMismatchError(
            root,
            f"holds a data set made with different settings ({listed}); run with the same "
            "settings to resume or extend it, or choose a new --out",
        )
    remove_partial_files(root)


def _differences(stored: Any, wanted: Any, key: str = "") -> Iterable[str]:
    if isinstance(stored, dict) and isinstance(wanted, dict):
        for name in sorted(set(stored) | set(wanted)):
            yield from _differences(
                stored.get(name), wanted.get(name), f"{key}.{name}" if key else name
            )
    elif stored != wanted:
        yield f"{key}: {json.dumps(stored)} there, {json.dumps(wanted)} here"


def write_metadata(root: Path, settings: dict[str, Any], summaries: list[dict[str, Any]]) -> None:
    """Rewrite ``meta/info.json`` and ``meta/episodes.jsonl`` from the episode summaries.

    Both files depend only on the settings and the set of finished episodes, never on
    how or in which order they were made.
    """
    summaries = sorted(summaries, key=lambda s: s["episode"])
    lines = "".join(json.dumps(s, sort_keys=True) + "\n" for s in summaries)
    write_atomic(root / EPISODES_FILE, lines.encode())
    scans = [s["scan"] for s in summaries if s.get("scan")]
    beams = {label.name: sum(s["beams_per_label"][label.name] for s in summaries)
             for label in BeamLabel}  # fmt: skip
    info = {
        "format_version": FORMAT_VERSION,
        "settings": settings,
        "scan": dict(sorted(scans[0].items())) if scans else None,  # same order as in footers
        "labels": {label.name: int(label) for label in BeamLabel},
        "pitch_variation_labels": ["FLOOR", "CEILING", "HORIZONTAL"],
        "columns": [
            {"name": name, "type": str(dtype), "meaning": meaning}
            for name, dtype, meaning in COLUMNS
        ],
        "layout": {
            "shards": "data/chunk-{episode // 1000:03d}/episode_{episode:06d}.parquet",
            "episodes": str(EPISODES_FILE),
            "episode_summary_key": EPISODE_METADATA_KEY.decode(),
        },
        "totals": {
            "episodes": len(summaries),
            "scans": sum(s["scans"] for s in summaries),
            "fallen_episodes": sum(1 for s in summaries if s["fell"]),
            "beams_per_label": beams,
        },
    }
    _write_json(root / INFO_FILE, info)
