"""Scan files: the .npz layout, round trips, and errors that name the key."""

import os
import stat

import numpy as np
import pytest

from pvfilter import PitchVariationFilter
from pvfilter.io import (
    arrays_from_scans,
    clockwise_scans,
    in_scan_order,
    load_scans,
    save_results,
    scans_from_arrays,
)
from pvfilter.synthetic import room_sequence


def minimal_arrays(count=3, beams=5):
    return dict(
        ranges=np.ones((count, beams)),
        stamps=0.1 * np.arange(count),
        angle_min=-1.0,
        angle_increment=0.1,
        range_min=0.05,
        range_max=10.0,
    )


def test_scalar_fields_apply_to_every_scan_and_per_scan_fields_to_theirs():
    arrays = minimal_arrays() | {"angle_min": np.array([-1.0, -0.5, 0.0])}
    scans = scans_from_arrays(arrays)
    assert [s.angle_min for s in scans] == [-1.0, -0.5, 0.0]
    assert [s.angle_increment for s in scans] == [0.1] * 3
    assert [s.stamp for s in scans] == pytest.approx([0.0, 0.1, 0.2])


def test_scans_round_trip_through_a_file(tmp_path):
    scans = room_sequence(4).scans
    np.savez(tmp_path / "scans.npz", **arrays_from_scans(scans))
    loaded = load_scans(tmp_path / "scans.npz")
    for a, b in zip(scans, loaded, strict=True):
        np.testing.assert_array_equal(a.ranges, b.ranges)
        assert (a.stamp, a.angle_min, a.angle_increment, a.scan_time) == (
            b.stamp,
            b.angle_min,
            b.angle_increment,
            b.scan_time,
        )


def test_results_file_keeps_other_arrays_and_adds_masks(tmp_path):
    scans = room_sequence(30).scans
    arrays = arrays_from_scans(scans) | {"labels": np.zeros((30, 720), dtype=np.uint8)}
    pvf = PitchVariationFilter()
    results = [pvf.process(scan) for scan in scans]
    save_results(tmp_path / "out.npz", arrays, results)
    with np.load(tmp_path / "out.npz") as out:
        assert out["removed"].shape == (30, 720) and out["removed"].dtype == bool
        assert out["removed"].any()
        np.testing.assert_array_equal(
            np.isnan(out["ranges"]) & ~np.isnan(arrays["ranges"]), out["removed"]
        )
        np.testing.assert_array_equal(out["labels"], arrays["labels"])
        np.testing.assert_array_equal(out["stamps"], arrays["stamps"])


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"stamps": None}, r"^f: stamps: missing"),
        ({"ranges": np.ones(5)}, r"^f: ranges: must be 2-D"),
        ({"angle_min": np.zeros(2)}, r"^f: angle_min: must be one value or one per scan"),
        ({"intensities": np.ones((3, 4))}, r"^f: intensities: must have the shape"),
        ({"angle_increment": np.array([0.1, 0.0, 0.1])}, r"^f: scan 1: angle_increment:"),
        ({"angle_increment": np.array([0.1, -0.1, 0.1])}, r"^f: angle_increment: the scans run"),
        ({"angle_min": np.array("abc")}, r"^f: angle_min: must be numbers, got <U3"),
        ({"stamps": np.array(["0", "x", "1"])}, r"^f: stamps: must be numbers"),
        ({"ranges": np.full((3, 5), "1.0")}, r"^f: ranges: must be numbers"),
    ],
)
def test_malformed_files_raise_naming_the_key(change, message):
    arrays = {k: v for k, v in (minimal_arrays() | change).items() if v is not None}
    with pytest.raises(ValueError, match=message):
        scans_from_arrays(arrays, source="f")


def clockwise(arrays):
    """The same scans written clockwise, as a driver with a negative angle_increment
    writes them: every per-beam array reversed, angle_min the last beam's angle."""
    ranges = arrays["ranges"]
    last = ranges.shape[1] - 1
    flipped = {k: v[:, ::-1] for k, v in arrays.items() if np.shape(v) == ranges.shape}
    return (
        arrays
        | flipped
        | {
            "angle_min": arrays["angle_min"] + last * arrays["angle_increment"],
            "angle_increment": -arrays["angle_increment"],
        }
    )


def test_a_clockwise_file_reads_as_its_scans_counter_clockwise_and_writes_back_in_its_order(
    tmp_path,
):
    scans = room_sequence(30).scans
    arrays = arrays_from_scans(scans) | {"labels": np.arange(30 * 720).reshape(30, 720)}
    arrays["intensities"] = np.arange(30 * 720.0).reshape(30, 720)
    written = clockwise(arrays)
    # the message's beam 0 is the sweep's last beam, measured 719 increments after its first
    written["stamps"] = arrays["stamps"] + 719 * arrays["time_increment"]
    written["time_increment"] = -arrays["time_increment"]
    read = scans_from_arrays(written)
    for scan, again, shining in zip(scans, read, arrays["intensities"], strict=True):
        np.testing.assert_array_equal(again.ranges, scan.ranges)
        np.testing.assert_array_equal(again.intensities, shining)
        np.testing.assert_allclose(again.angles(), scan.angles(), atol=1e-12)
        assert again.stamp == pytest.approx(scan.stamp, abs=1e-12)
        assert again.time_increment == pytest.approx(scan.time_increment, abs=1e-15)
    assert clockwise_scans(written, 30).all() and not clockwise_scans(arrays, 30).any()
    np.testing.assert_array_equal(in_scan_order(written["labels"], clockwise_scans(written, 30)),
                                  arrays["labels"])  # fmt: skip
    pvf = PitchVariationFilter()
    results = [pvf.process(scan) for scan in read]
    save_results(tmp_path / "out.npz", written, results)
    with np.load(tmp_path / "out.npz") as out:
        assert out["removed"].any()
        np.testing.assert_array_equal(
            out["removed"], np.array([r.removed for r in results])[:, ::-1]
        )
        np.testing.assert_array_equal(
            np.isnan(out["ranges"]) & ~np.isnan(written["ranges"]), out["removed"]
        )
        np.testing.assert_array_equal(out["labels"], written["labels"])
        np.testing.assert_array_equal(out["intensities"], written["intensities"])


def test_a_results_file_gets_the_permissions_a_plain_file_would(tmp_path):
    scans = room_sequence(3).scans
    results = [PitchVariationFilter().process(s) for s in scans]
    mask = os.umask(0o027)  # (a umask other than the default: the file must follow it)
    try:
        save_results(tmp_path / "out.npz", arrays_from_scans(scans), results)
    finally:
        os.umask(mask)
    assert stat.S_IMODE((tmp_path / "out.npz").stat().st_mode) == 0o640
    assert [p.name for p in tmp_path.iterdir()] == ["out.npz"]  # no temporary file left


def test_an_overwritten_results_file_keeps_its_permissions(tmp_path):
    scans = room_sequence(3).scans
    results = [PitchVariationFilter().process(s) for s in scans]
    out = tmp_path / "out.npz"
    out.write_bytes(b"old")
    out.chmod(0o600)  # the user's own choice: readable by them alone
    save_results(out, arrays_from_scans(scans), results)
    assert stat.S_IMODE(out.stat().st_mode) == 0o600
    with np.load(out) as written:
        assert "removed" in written
