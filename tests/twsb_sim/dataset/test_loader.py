"""Reading a data set: plain pyarrow and pandas, and the package's loader."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pyarrow.dataset as pads
import pyarrow.parquet as pq
import pytest

from twsb_sim.dataset.loader import DatasetFormatWarning, label_count_filter, open_dataset
from twsb_sim.dataset.schema import COLUMNS, SCHEMA, SENSOR_COLUMNS
from twsb_sim.labels import BeamLabel, is_pitch_variation

from .conftest import EPISODES, as_format_1


def test_plain_pyarrow_reads_every_scan_with_the_documented_schema(reference):
    table = pads.dataset(reference / "data", format="parquet").to_table()
    assert table.schema.remove_metadata().equals(SCHEMA)
    info = json.loads((reference / "meta" / "info.json").read_text())
    assert table.num_rows == info["totals"]["scans"]
    assert sorted(set(table["episode"].to_pylist())) == list(range(EPISODES))
    shard = pq.read_table(reference / "data" / "chunk-000" / "episode_000003.parquet")
    assert set(shard["episode"].to_pylist()) == {3}
    assert shard["frame"].to_pylist() == list(range(shard.num_rows))
    assert (
        pq.ParquetFile(reference / "data/chunk-000/episode_000000.parquet")
        .metadata.row_group(0)
        .column(3)
        .compression
        == "ZSTD"
    )


def test_plain_pandas_reads_the_folder(reference):
    pd = pytest.importorskip("pandas")
    frame = pd.read_parquet(reference / "data")
    assert len(frame) == len(open_dataset(reference))
    assert frame["ranges"].iloc[0].dtype == np.float32
    assert frame["labels"].iloc[0].dtype == np.uint8


def test_metadata_describes_the_set(reference):
    info = json.loads((reference / "meta" / "info.json").read_text())
    assert info["labels"] == {label.name: int(label) for label in BeamLabel}
    assert info["scan"]["beams"] == 720 and info["scan"]["scan_time"] == pytest.approx(0.1)
    assert info["settings"]["seed"] == 11
    assert "kept" in info["settings"]["fallen_episodes"]
    lines = (reference / "meta" / "episodes.jsonl").read_text().splitlines()
    summaries = [json.loads(line) for line in lines]
    assert [s["episode"] for s in summaries] == list(range(EPISODES))
    assert sum(s["scans"] for s in summaries) == info["totals"]["scans"]


def test_loader_iterates_episodes_and_scans_in_order(reference):
    data = open_dataset(reference)
    assert data.episode_ids == list(range(EPISODES))
    episodes = list(data.episodes())
    assert [e.episode for e in episodes] == list(range(EPISODES))
    scans = list(data.scans())
    assert len(scans) == len(data) == sum(len(e) for e in episodes)
    first = episodes[0]
    assert first.ranges.shape == (len(first), 720) and first.ranges.dtype == np.float32
    np.testing.assert_array_equal(scans[0].ranges, first.ranges[0])
    np.testing.assert_array_equal(scans[0].labels, first.labels[0])
    assert scans[0].values["pitch_rad"] == first.column("pitch_rad")[0]
    scan = scans[5].scan()  # a pvfilter.Scan, ready for the filter
    assert len(scan) == 720 and scan.stamp == scans[5].stamp_s


@pytest.mark.parametrize(
    ("min_counts", "max_counts", "keep"),
    [
        ({"FLOOR": 10}, None, lambda lb: (lb == BeamLabel.FLOOR).sum(1) >= 10),
        ({"pitch_variation": 1}, None, lambda lb: is_pitch_variation(lb).any(1)),
        (None, {"PITCH_VARIATION": 0}, lambda lb: ~is_pitch_variation(lb).any(1)),
        ({"floor": 1}, {"ceiling": 0}, lambda lb: (lb == 2).any(1) & ~(lb == 3).any(1)),
    ],
)
def test_label_count_filters_match_the_labels(reference, min_counts, max_counts, keep):
    data = open_dataset(reference)
    labels = np.concatenate([e.labels for e in data.episodes()])
    expected = int(keep(labels).sum())
    assert expected > 0
    kept = list(data.scans(min_counts, max_counts, columns=[]))
    assert len(kept) == expected
    assert data.table(min_counts, max_counts, columns=["frame"]).num_rows == expected


def test_unknown_label_name_is_refused():
    with pytest.raises(ValueError, match="CEILING"):
        label_count_filter({"WALL": 1})


def test_reading_never_loads_the_simulator(reference):
    code = (
        "import sys; from twsb_sim.dataset import open_dataset; "
        f"d = open_dataset({str(reference)!r}); n = sum(1 for _ in d.scans(columns=[])); "
        "print(n, 'mujoco' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == [str(len(open_dataset(reference))), "False"]


def test_docs_document_every_column():
    """docs/datasets.md documents the truth columns, docs/sensors.md the robot's sensor
    columns."""
    root = Path(__file__).parents[3]
    section = (root / "docs" / "datasets.md").read_text(encoding="utf-8")
    sensors_page = (root / "docs" / "sensors.md").read_text(encoding="utf-8")
    sensor_names = {name for name, _, _ in SENSOR_COLUMNS}
    page = {name: sensors_page if name in sensor_names else section for name, _, _ in COLUMNS}
    missing = [name for name, text in page.items() if f"`{name}`" not in text]
    assert not missing


def test_an_older_data_set_loads_and_says_what_it_lacks(reference, tmp_path):
    old = tmp_path / "old"
    as_format_1(reference, old)
    with pytest.warns(DatasetFormatWarning, match=r"format 1 .*odom_x_m"):
        data = open_dataset(old)
    assert data.format_version == 1
    assert "est_pitch_rad" in data.missing_columns and "ranges" not in data.missing_columns
    first = data.episode(data.episode_ids[0])
    assert len(first) > 0 and first.ranges.shape[1] == 720
    assert sum(1 for _ in data.scans(columns=["pitch_rad"])) == len(data)
    with pytest.raises(KeyError, match=r"no column est_pitch_rad .* format 1 .*added in format 2"):
        data.episode(data.episode_ids[0], columns=["est_pitch_rad"])
