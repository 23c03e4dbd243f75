"""Filters scored on labelled scan files: the counting rule, the sweep, the command."""

import contextlib
import dataclasses
import functools
import json
from typing import ClassVar

import numpy as np
import pytest

from pvfilter.cli import main
from pvfilter.io import arrays_from_scans, scans_from_arrays
from pvfilter.labelled import (
    evaluate_labelled,
    geometry_of,
    pooled,
    read_labels,
    with_angle_jitter,
    with_dropouts,
    with_no_echo_reads,
    with_occluded_reads,
    with_range_noise,
)
from pvfilter.registry import FilterEntry, filter_entry, register_filter, unregister_filter
from pvfilter.synthetic import room_sequence

STATIC, FLOOR, CEILING, DYNAMIC, OCCLUDED = 1, 2, 3, 5, 6


def labelled_arrays(count=60):
    """A synthetic room sequence with floor lines, as a labelled scan file's arrays."""
    sequence = room_sequence(count, event_every=20)
    arrays = arrays_from_scans(sequence.scans)
    ranges = arrays["ranges"]
    labels = np.where(np.isfinite(ranges), STATIC, 0).astype(np.uint8)
    labels[np.isnan(ranges)] = OCCLUDED  # the blocked sector
    labels[np.array(sequence.truth)] = FLOOR
    arrays["labels"] = labels
    return arrays, np.array(sequence.truth)


@pytest.fixture
def labelled_file(tmp_path):
    arrays, _ = labelled_arrays()
    path = tmp_path / "room.npz"
    np.savez(path, **arrays)
    return path


@dataclasses.dataclass(frozen=True)
class OracleParams:
    lidar_height_m: float = 0.25


class Removing:
    """A stand-in filter without parameters that removes a fixed mask, scan by scan."""

    def __init__(self, mask):
        self.mask = mask
        self.count = 0

    def process(self, scan, **inputs):
        removed = self.mask[self.count].copy()
        self.count += 1
        return type("Result", (), {"removed": removed, "scores": removed * 1.0})()

    def reset(self):
        self.count = 0


class Oracle(Removing):
    """A stand-in filter that removes exactly the floor-line beams of the fixture."""

    seen_heights: ClassVar[list[float]] = []

    def __init__(self, params=OracleParams()):
        super().__init__(labelled_arrays()[1])
        Oracle.seen_heights.append(params.lidar_height_m)


@contextlib.contextmanager
def registered(entry):
    """A stand-in filter registered for a test, and taken out after."""
    try:
        yield register_filter(entry)
    finally:
        unregister_filter(entry.name)


@pytest.fixture
def oracle():
    with registered(FilterEntry("oracle", Oracle, OracleParams, "the labels")) as entry:
        yield entry


def test_the_labels_themselves_score_one_and_remove_no_static_beam(labelled_file, oracle):
    report = evaluate_labelled(labelled_file, oracle)
    _, truth = labelled_arrays()
    assert report.positives == truth.sum() > 0
    assert (report.tp, report.fp, report.fn) == ((truth.sum(),), (0,), (0,))
    assert report.auc == pytest.approx(1.0) and report.precision == report.recall == 1.0
    assert report.recall_by_label["FLOOR"] == 1.0 and np.isnan(report.recall_by_label["CEILING"])
    assert report.static_removed == 0 and report.static_beams > 0


def test_one_pass_gives_what_a_fresh_pass_per_threshold_gives(labelled_file):
    improved = filter_entry("improved")
    values = (0.0, 0.2, 0.5, 0.8, 0.95)
    one = evaluate_labelled(labelled_file, improved, thresholds=values)
    fresh = evaluate_labelled(
        labelled_file, dataclasses.replace(improved, one_pass=False), thresholds=values
    )
    assert one.thresholds == fresh.thresholds == values
    assert (one.tp, one.fp, one.fn) == (fresh.tp, fresh.fp, fresh.fn)
    assert one.tp[0] > 0 and one.auc == pytest.approx(fresh.auc)


def test_dynamic_and_occluded_beams_are_neither_hits_nor_false_alarms(tmp_path, oracle):
    arrays, truth = labelled_arrays()
    moving = (arrays["labels"] == STATIC) & (np.arange(arrays["ranges"].shape[1]) % 7 == 0)
    arrays["labels"][moving] = DYNAMIC
    path = tmp_path / "people.npz"
    np.savez(path, **arrays)
    report = evaluate_labelled(path, oracle)
    finite = np.isfinite(arrays["ranges"])
    assert report.beams == np.count_nonzero(finite) - np.count_nonzero(moving)
    assert report.positives == truth.sum()


def test_the_file_states_the_robot_geometry_and_set_values_win(tmp_path, oracle):
    arrays, _ = labelled_arrays()
    arrays["lidar_height_m"] = np.array(0.4)
    path = tmp_path / "tall.npz"
    np.savez(path, **arrays)
    assert geometry_of(arrays, "tall") == {"lidar_height_m": 0.4}
    Oracle.seen_heights.clear()
    evaluate_labelled(path, oracle)
    evaluate_labelled(path, oracle, fields={"lidar_height_m": 0.3})
    assert Oracle.seen_heights == [0.4, 0.3]


def test_the_files_geometry_can_be_withheld_as_from_a_user_who_never_set_it(tmp_path, capsys):
    arrays, _ = labelled_arrays(30)
    arrays["lidar_height_m"] = np.array(0.4)
    np.savez(tmp_path / "tall.npz", **arrays)
    told = evaluate_labelled(tmp_path / "tall.npz", filter_entry("improved"), ignore_geometry=True)
    assert told.geometry == {}
    out = tmp_path / "report"
    argv = ["eval-labels", str(tmp_path / "tall.npz"), "--ignore-geometry", "--out", str(out)]
    assert main([*argv, "--compare"]) == 0
    assert json.loads((out / "report.json").read_text())["ignore_geometry"] is True
    report = (out / "report.md").read_text()
    assert "geometry the files state is not told to the filters" in report
    assert "lidar_height_m" not in report.split("| file |")[1]  # the geometry column: none


def test_a_filter_is_given_only_the_inputs_asked_for_that_it_takes(tmp_path):
    arrays, _ = labelled_arrays(30)
    arrays["pitch_rad"] = np.zeros(30)
    path = tmp_path / "imu.npz"
    np.savez(path, **arrays)
    improved, paper = filter_entry("improved"), filter_entry("paper")
    assert evaluate_labelled(path, improved).inputs == ()
    assert evaluate_labelled(path, improved, inputs=["imu"]).inputs == ("pitch_rad",)
    assert evaluate_labelled(path, paper, inputs=["imu"], thresholds=(0.8,)).inputs == ()
    with pytest.raises(ValueError, match="odometry: the file has no pose_sensor_in_odom"):
        evaluate_labelled(path, improved, inputs=["odometry"])


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda a: a.pop("labels"), "labels: missing"),
        (lambda a: a.update(labels=a["labels"][:, :-1]), "labels: must have the shape of ranges"),
        (lambda a: a["labels"].__setitem__((0, 0), 9), r"labels: codes are 0\.\.6"),
        (lambda a: a.update(lidar_height_m=np.ones(3)), "lidar_height_m: must be one finite"),
    ],
)
def test_a_malformed_labelled_file_is_named_with_what_is_wrong(tmp_path, change, message):
    arrays, _ = labelled_arrays(10)
    change(arrays)
    path = tmp_path / "bad.npz"
    np.savez(path, **arrays)
    with pytest.raises(ValueError, match=message):
        evaluate_labelled(path, filter_entry("improved"))


def test_read_labels_takes_integral_floats():
    arrays, _ = labelled_arrays(5)
    arrays["labels"] = arrays["labels"].astype(np.float32)
    assert read_labels(arrays, "floats").dtype == np.int64


def test_the_command_prints_and_writes_every_curve(labelled_file, tmp_path, capsys):
    out = tmp_path / "report"
    assert main(["eval-labels", str(labelled_file.parent), "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "room" in printed and "improved" in printed and "paper" in printed
    assert "all 1 files" in printed and "pooled AUC" in printed
    document = json.loads((out / "report.json").read_text())
    rows = {row["filter"]: row for row in document["files"]}
    assert set(rows) == {"improved", "paper"}
    improved = rows["improved"]
    assert improved["operating_point"] == 0.5 and len(improved["tp"]) == 30
    assert document["summary"]["improved"]["pooled_auc"] == pytest.approx(improved["auc"])
    assert "| room | improved |" in (out / "report.md").read_text()


def test_pooled_counts_are_the_sums(labelled_file, tmp_path):
    arrays, _ = labelled_arrays(30)
    second = tmp_path / "second.npz"
    np.savez(second, **arrays)
    improved = filter_entry("improved")
    reports = [evaluate_labelled(p, improved) for p in (labelled_file, second)]
    curve = pooled(reports)
    np.testing.assert_array_equal(curve.tp, np.add(reports[0].tp, reports[1].tp))
    assert min(r.auc for r in reports) <= curve.auc <= max(r.auc for r in reports) + 1e-9


def removing(mask):
    """The entry of a stand-in filter that removes ``mask`` (for :func:`registered`)."""
    return FilterEntry("removing", functools.partial(Removing, mask), None, "a fixed mask")


def test_the_per_scan_counts_are_the_beams_removed_in_each_scan(tmp_path):
    arrays, truth = labelled_arrays()
    labels, ranges = arrays["labels"], arrays["ranges"]
    beams = np.arange(truth.shape[1])
    wrong = (labels == STATIC) & (beams < 10)  # the first ten beams on a wall removed ...
    wrong[1::2] = False  # ... in every other scan
    labels[wrong & (beams < 3)] = 0  # three of them with a range but labelled NO_RETURN
    ceiling = truth & (beams % 2 == 0)  # and half of each floor line a ceiling line
    labels[ceiling] = CEILING
    body = labels == OCCLUDED  # the body's beams, removed too, are not counted
    found = truth & (beams % 3 != 0)  # two in three of the floor and ceiling beams
    silent = truth & (beams % 3 == 1)  # of those, some without an echo, some past the reach
    ranges[silent & (beams % 2 == 0)] = np.inf
    ranges[silent & (beams % 2 == 1)] = 100.0
    # counted: none of the silent beams
    truth, found, ceiling = (mask & ~silent for mask in (truth, found, ceiling))
    path = tmp_path / "room.npz"
    np.savez(path, **arrays)
    with registered(removing(found | silent | wrong | body)) as entry:
        report = evaluate_labelled(path, entry, counts_per_scan=True)
        unasked = evaluate_labelled(path, entry)
    counts = report.per_scan
    counted = (ranges < 100.0) & (labels != OCCLUDED)  # (inf and NaN compare False)
    np.testing.assert_array_equal(counts.scan, np.arange(len(truth)))
    np.testing.assert_array_equal(counts.stamp_s, arrays["stamps"])
    np.testing.assert_array_equal(counts.beams, counted.sum(axis=1))
    np.testing.assert_array_equal(counts.positives, (truth & counted).sum(axis=1))
    np.testing.assert_array_equal(counts.hits, found.sum(axis=1))
    np.testing.assert_array_equal(counts.false_alarms, (wrong & counted).sum(axis=1))
    np.testing.assert_array_equal(counts.static_removed, (wrong & (labels == STATIC)).sum(axis=1))
    assert counts.static_removed.sum() < counts.false_alarms.sum()
    assert counts.false_alarms[0] > 0 and counts.false_alarms[1] == 0
    np.testing.assert_array_equal(counts.removed, counts.hits + counts.false_alarms)
    for name, beams_of in (("FLOOR", truth & ~ceiling), ("CEILING", ceiling)):
        labelled, found_removed = counts.by_label[name]
        np.testing.assert_array_equal(labelled, beams_of.sum(axis=1))
        np.testing.assert_array_equal(found_removed, (beams_of & found).sum(axis=1))
    assert counts.by_label["CEILING"][0].any() and not counts.by_label["HORIZONTAL"][0].any()
    # the whole file's counts are the scans' summed
    assert (counts.hits.sum(), counts.false_alarms.sum()) == (report.tp[0], report.fp[0])
    assert counts.static_removed.sum() == report.static_removed
    assert silent.any() and unasked.per_scan is None  # kept only where asked


def test_the_per_scan_counts_follow_the_operating_point_and_the_kept_scans(labelled_file):
    improved = filter_entry("improved")
    report = evaluate_labelled(labelled_file, improved, counts_per_scan=True, every=3)
    counts = report.per_scan
    np.testing.assert_array_equal(counts.scan, np.arange(0, 60, 3))  # the file's indices
    at = report.thresholds.index(report.operating_point)
    assert counts.hits.sum() == report.tp[at] > 0
    assert counts.false_alarms.sum() == report.fp[at]
    assert counts.positives.sum() == report.positives and counts.beams.sum() == report.beams
    looser = evaluate_labelled(
        labelled_file, improved, fields={"p_th": 0.0}, counts_per_scan=True, every=3
    )
    assert looser.per_scan.removed.sum() >= counts.removed.sum()
    assert looser.per_scan.removed.sum() == looser.tp[0] + looser.fp[0]


def test_the_command_writes_a_per_scan_table_per_file_and_filter(labelled_file, tmp_path, capsys):
    out = tmp_path / "report"
    argv = ["eval-labels", str(labelled_file), "--out", str(out), "--per-scan"]
    assert main(argv) == 0
    assert "wrote 2 per-scan tables" in capsys.readouterr().out
    document = json.loads((out / "report.json").read_text())
    assert all("per_scan" not in row for row in document["files"])  # the tables hold them
    for row in document["files"]:
        lines = (out / "per_scan" / f"room.{row['filter']}.csv").read_text().splitlines()
        header = lines[0].split(",")
        assert header[:8] == [
            "scan", "stamp_s", "beams", "positives", "removed", "hits", "false_alarms",
            "static_removed",
        ]  # fmt: skip
        assert "horizontal_removed" in header and len(lines) == 1 + row["scans"]
        table = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
        at = row["thresholds"].index(row["operating_point"])
        assert table[:, header.index("hits")].sum() == row["tp"][at]
        assert table[:, header.index("false_alarms")].sum() == row["fp"][at]
    assert main(["eval-labels", str(labelled_file), "--per-scan"]) == 2  # without --out
    assert "--per-scan: add --out DIR" in capsys.readouterr().err


def test_each_per_scan_table_has_a_name_of_its_own(labelled_file, tmp_path, capsys):
    # two files both named a/room, and a compared filter whose label has a space
    for folder in ("x", "y"):
        (tmp_path / folder / "a").mkdir(parents=True)
        np.savez(tmp_path / folder / "a" / "room.npz", **labelled_arrays(30)[0])
    out = tmp_path / "report"
    (out / "per_scan").mkdir(parents=True)
    (out / "per_scan" / "earlier.csv").write_text("scan\n0\n")  # an earlier run's table
    files = [str(tmp_path / folder / "a" / "room.npz") for folder in ("x", "y")]
    argv = ["eval-labels", *files, "--set", "p_th=0.3", "--compare", "improved"]
    assert main([*argv, "--out", str(out), "--per-scan"]) == 0
    assert "wrote 4 per-scan tables" in capsys.readouterr().out
    written = sorted(path.name for path in (out / "per_scan").iterdir())
    assert written == [
        "a_room.improved-2.csv",
        "a_room.improved.csv",
        "a_room.improved_defaults-2.csv",
        "a_room.improved_defaults.csv",
    ]


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["missing.npz"], "missing.npz: no such file"),
        (["--set", "nonsense=1", "missing.npz"], "unknown parameter 'nonsense'"),
        (["--range-noise", "-0.01", "missing.npz"], "--range-noise: a standard deviation"),
        (["--dropout", "1.5", "missing.npz"], "--dropout: a share in [0, 1]"),
    ],
)
def test_a_user_mistake_exits_2_with_one_line(argv, message, capsys):
    assert main(["eval-labels", *argv]) == 2
    assert message in capsys.readouterr().err


def test_files_of_one_name_in_two_folders_are_told_apart(labelled_file, tmp_path, capsys):
    other = tmp_path / "other"
    other.mkdir()
    np.savez(other / "room.npz", **labelled_arrays(30)[0])
    np.savez(other / "hall.npz", **labelled_arrays(30)[0])
    assert main(["eval-labels", str(labelled_file), str(other), "--compare"]) == 0
    printed = capsys.readouterr().out
    assert f"{labelled_file.parent.name}/room " in printed and "other/room " in printed
    assert "other/hall " in printed  # all named alike


def test_a_tuned_filter_is_compared_with_its_defaults(labelled_file, capsys):
    argv = ["eval-labels", str(labelled_file), "--set", "p_th=0.3", "--compare", "improved"]
    assert main(argv) == 0
    printed = capsys.readouterr().out
    assert "improved   AUC" in printed and "improved (defaults) AUC" in printed
    assert "at 0.3;" in printed and "at 0.5;" in printed


def test_the_report_is_strict_json_and_states_the_geometry_told(tmp_path, capsys):
    arrays, _ = labelled_arrays(30)
    arrays["lidar_height_m"] = np.array(0.3)
    np.savez(tmp_path / "room.npz", **arrays)
    out = tmp_path / "report"
    assert main(["eval-labels", str(tmp_path / "room.npz"), "--out", str(out)]) == 0

    def refuse(constant):
        raise ValueError(constant)

    document = json.loads((out / "report.json").read_text(), parse_constant=refuse)
    rows = {row["filter"]: row for row in document["files"]}
    assert rows["improved"]["recall_by_label"]["CEILING"] is None  # no ceiling beam: null
    assert rows["improved"]["geometry"] == {"lidar_height_m": 0.3}
    assert "lidar_height_m 0.300" in (out / "report.md").read_text()


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--target", "1.5"], "--target: an AUC is in [0, 1]"),
        (["--params", "nosuch.toml"], "--params nosuch.toml: No such file or directory"),
        (["--filter", "imu_gate", "--compare"], "needs pitch_rad: add --inputs imu"),
    ],
)
def test_a_mistake_in_the_options_stops_before_any_file_is_read(
    labelled_file, argv, message, capsys
):
    assert main(["eval-labels", str(labelled_file), *argv]) == 2
    captured = capsys.readouterr()
    assert message in captured.err and captured.out == ""


def test_an_out_path_that_cannot_be_a_folder_stops_before_the_work(labelled_file, capsys):
    assert main(["eval-labels", str(labelled_file), "--out", str(labelled_file)]) == 2
    captured = capsys.readouterr()
    assert "cannot be a folder" in captured.err and captured.out == ""


def test_added_range_noise_is_the_same_every_run_and_reported(labelled_file, tmp_path):
    improved = filter_entry("improved")
    noisy = [evaluate_labelled(labelled_file, improved, range_noise_m=0.05) for _ in range(2)]
    np.testing.assert_array_equal(noisy[0].tp, noisy[1].tp)
    np.testing.assert_array_equal(noisy[0].fp, noisy[1].fp)
    quiet = evaluate_labelled(labelled_file, improved)
    assert not (np.array_equal(quiet.tp, noisy[0].tp) and np.array_equal(quiet.fp, noisy[0].fp))
    assert quiet.positives == noisy[0].positives  # the same beams count: finite stays finite
    out = tmp_path / "report"
    assert (
        main(["eval-labels", str(labelled_file), "--range-noise", "0.05", "--out", str(out)]) == 0
    )
    assert json.loads((out / "report.json").read_text())["range_noise_m"] == 0.05
    assert "Range noise added: 5 cm" in (out / "report.md").read_text()


def test_range_noise_spares_the_beams_without_a_return():
    scan = room_sequence(1).scans[0]
    noisy = with_range_noise([scan], 0.05)[0]
    finite = np.isfinite(scan.ranges)
    np.testing.assert_array_equal(noisy.ranges[~finite], scan.ranges[~finite])
    spread = np.std(noisy.ranges[finite] - scan.ranges[finite])
    assert spread == pytest.approx(0.05, rel=0.15)


def test_occluded_beams_read_as_asked_and_nothing_else_changes():
    arrays, _ = labelled_arrays(count=3)
    scans = room_sequence(3, event_every=20).scans
    labels = arrays["labels"]
    for value in (np.inf, -np.inf, 0.2):
        changed = with_occluded_reads(scans, labels, value)
        for scan, new, codes in zip(scans, changed, labels, strict=True):
            blocked = codes == OCCLUDED
            assert blocked.any() and (new.ranges[blocked] == value).all()
            np.testing.assert_array_equal(new.ranges[~blocked], scan.ranges[~blocked])


def test_dropouts_lose_that_share_of_the_returns_the_same_every_run():
    scans = room_sequence(20).scans
    dropped = [with_dropouts(scans, 0.1) for _ in range(2)]
    finite = np.concatenate([np.isfinite(scan.ranges) for scan in scans])
    lost = np.concatenate([np.isposinf(d.ranges) for d in dropped[0]]) & finite
    assert lost.sum() / finite.sum() == pytest.approx(0.1, abs=0.01)
    for a, b in zip(*dropped, strict=True):
        np.testing.assert_array_equal(a.ranges, b.ranges)
    kept = np.concatenate([d.ranges for d in dropped[0]])[finite & ~lost]
    np.testing.assert_array_equal(kept, np.concatenate([s.ranges for s in scans])[finite & ~lost])


def test_the_scanner_changes_are_in_the_reports(labelled_file, tmp_path):
    out = tmp_path / "report"
    argv = ["eval-labels", str(labelled_file), "--occluded-reads", "inf", "--dropout", "0.05"]
    assert main([*argv, "--out", str(out)]) == 0
    document = json.loads((out / "report.json").read_text())
    assert document["occluded_reads"] == "inf" and document["dropout_share"] == 0.05
    text = (out / "report.md").read_text()
    assert "Every OCCLUDED beam reads inf." in text and "no echo: 5 %" in text
    improved = filter_entry("improved")
    plain = evaluate_labelled(labelled_file, improved)
    blind = evaluate_labelled(labelled_file, improved, occluded_reads=np.inf)
    assert plain.positives == blind.positives  # OCCLUDED beams never count


def test_a_body_that_returns_in_the_blocked_sector_scatters_with_the_added_noise(
    labelled_file, tmp_path
):
    out = tmp_path / "report"
    argv = ["eval-labels", str(labelled_file), "--occluded-reads", "0.2", "--range-noise"]
    assert main([*argv, "0.01", "--out", str(out)]) == 0
    assert "Every OCCLUDED beam reads 0.2 m (the body)." in (out / "report.md").read_text()
    arrays = dict(np.load(labelled_file))
    scans = scans_from_arrays(arrays)
    body = with_range_noise(with_occluded_reads(scans, arrays["labels"], 0.2), 0.01)
    blocked = arrays["labels"][0] == OCCLUDED
    assert np.std(body[0].ranges[blocked]) == pytest.approx(0.01, rel=0.3)


@pytest.mark.parametrize("value", ["0", "-0.2", "body", "1e400"])
def test_an_occluded_read_that_is_no_range_is_refused(labelled_file, value, capsys):
    assert main(["eval-labels", str(labelled_file), "--occluded-reads", value]) == 2
    assert "--occluded-reads: inf, -inf, nan or a range > 0 m" in capsys.readouterr().err


@pytest.fixture
def file_with_floor_past_the_range(tmp_path):
    """The fixture's file with ten beams a scan past ``range_max`` (``+inf``) labelled
    FLOOR, as generators label a beam by what it would hit: nothing a filter can remove."""
    arrays, _ = labelled_arrays()
    ranges, labels = arrays["ranges"].copy(), arrays["labels"].copy()
    ranges[:, 100:110], labels[:, 100:110] = np.inf, FLOOR
    path = tmp_path / "far.npz"
    np.savez(path, **{**arrays, "ranges": ranges, "labels": labels})
    return path


@pytest.mark.parametrize("reads", [0.0, np.nan, "range_max"])
def test_beams_without_a_return_are_not_scored_however_the_scanner_writes_them(
    file_with_floor_past_the_range, reads
):
    improved = filter_entry("improved")
    plain = evaluate_labelled(file_with_floor_past_the_range, improved)
    written = evaluate_labelled(file_with_floor_past_the_range, improved, no_echo_reads=reads)
    assert (written.positives, written.beams) == (plain.positives, plain.beams)
    if reads in (0.0, "range_max"):  # the filter reads them as no echo too: the same run
        np.testing.assert_array_equal(written.tp, plain.tp)
        np.testing.assert_array_equal(written.fp, plain.fp)


def test_a_zero_range_is_not_scored_where_range_min_is_zero_too(tmp_path):
    arrays, _ = labelled_arrays()
    ranges, labels = arrays["ranges"].copy(), arrays["labels"].copy()
    ranges[:, 100:110], labels[:, 100:110] = 0.0, FLOOR  # no return, written as 0.0
    path = tmp_path / "zero.npz"
    np.savez(path, **{**arrays, "ranges": ranges, "labels": labels, "range_min": 0.0})
    report = evaluate_labelled(path, filter_entry("improved"))
    assert report.positives == np.count_nonzero(labels == FLOOR) - 10 * len(ranges)


class Spy:
    """A stand-in filter that keeps the ranges it was given and removes nothing."""

    seen: ClassVar[list[np.ndarray]] = []

    def __init__(self, params=OracleParams()):
        Spy.seen.clear()

    def process(self, scan, **inputs):
        Spy.seen.append(np.array(scan.ranges))
        nothing = np.zeros(len(scan), bool)
        return type("Result", (), {"removed": nothing, "scores": nothing * 1.0})()

    def reset(self):
        Spy.seen.clear()


@pytest.mark.parametrize(("reads", "expected"), [(0.0, 0.0), ("range_max", 12.0)])
def test_the_filters_get_the_no_echo_as_asked(file_with_floor_past_the_range, reads, expected):
    entry = register_filter(FilterEntry("spy", Spy, OracleParams, "keeps what it sees"))
    try:
        evaluate_labelled(file_with_floor_past_the_range, entry, no_echo_reads=reads)
    finally:
        unregister_filter("spy")
    seen = np.array(Spy.seen)
    assert not np.isposinf(seen).any()
    assert (seen[:, 100:110] == expected).all()


def test_no_echo_reads_as_asked_and_nothing_else_changes():
    scans = room_sequence(3).scans
    scans = [s.with_ranges(np.where(np.arange(len(s)) % 50 == 0, np.inf, s.ranges)) for s in scans]
    for value, expected in ((0.0, 0.0), ("range_max", scans[0].range_max)):
        for scan, new in zip(scans, with_no_echo_reads(scans, value), strict=True):
            silent = scan.ranges == np.inf
            assert (new.ranges[silent] == expected).all()
            np.testing.assert_array_equal(new.ranges[~silent], scan.ranges[~silent])


def test_the_no_echo_reads_are_in_the_reports(labelled_file, tmp_path):
    out = tmp_path / "report"
    argv = ["eval-labels", str(labelled_file), "--no-echo-reads", "range_max", "--out", str(out)]
    assert main(argv) == 0
    assert json.loads((out / "report.json").read_text())["no_echo_reads"] == "range_max"
    assert "Every beam without an echo reads range_max." in (out / "report.md").read_text()
    with pytest.raises(SystemExit) as exit_info:
        main(["eval-labels", str(labelled_file), "--no-echo-reads", "12"])
    assert exit_info.value.code == 2


def test_a_clockwise_file_scores_as_the_same_scans_counter_clockwise(labelled_file, tmp_path):
    arrays = dict(np.load(labelled_file))
    last = arrays["ranges"].shape[1] - 1
    flipped = {k: v[:, ::-1] for k, v in arrays.items() if np.shape(v) == arrays["ranges"].shape}
    start = arrays["angle_min"] + last * arrays["angle_increment"]
    increment = -arrays["angle_increment"]
    path = tmp_path / "clockwise.npz"
    np.savez(path, **(arrays | flipped | {"angle_min": start, "angle_increment": increment}))
    improved = filter_entry("improved")
    plain = evaluate_labelled(labelled_file, improved, counts_per_scan=True)
    turned = evaluate_labelled(path, improved, counts_per_scan=True)
    assert (turned.beams, turned.positives) == (plain.beams, plain.positives)
    np.testing.assert_array_equal(turned.tp, plain.tp)
    np.testing.assert_array_equal(turned.fp, plain.fp)
    assert plain.auc > 0.9
    # scan by scan the same, each at the file's own stamp (the reader moves a clockwise
    # scan's stamp to its first beam's time)
    for field in ("scan", "beams", "positives", "removed", "hits", "static_removed"):
        np.testing.assert_array_equal(
            getattr(turned.per_scan, field), getattr(plain.per_scan, field)
        )
    assert np.all(arrays["time_increment"] > 0.0)
    np.testing.assert_array_equal(turned.per_scan.stamp_s, arrays["stamps"])
    np.testing.assert_array_equal(plain.per_scan.stamp_s, arrays["stamps"])


def cli_report(tmp_path, path, *options):
    """``pvfilter eval-labels path *options --out``, which must succeed: its report.json
    (parsed) and report.md."""
    out = tmp_path / "report"
    assert main(["eval-labels", str(path), *options, "--out", str(out)]) == 0
    return json.loads((out / "report.json").read_text()), (out / "report.md").read_text()


def test_angle_jitter_moves_each_angle_min_within_half_the_beams_the_same_every_run():
    scans = room_sequence(50).scans
    moved = [with_angle_jitter(scans, 1.0) for _ in range(2)]
    shifts = np.array([(m.angle_min - s.angle_min) / s.angle_increment
                       for s, m in zip(scans, moved[0], strict=True)])  # fmt: skip
    assert np.abs(shifts).max() <= 0.5 and np.abs(shifts).max() > 0.4 and np.std(shifts) > 0.2
    for a, b, scan in zip(*moved, scans, strict=True):
        assert a.angle_min == b.angle_min
        np.testing.assert_array_equal(a.ranges, scan.ranges)


def test_the_improved_filter_scores_a_jittered_angle_min_as_the_file(labelled_file, tmp_path):
    improved = filter_entry("improved")
    plain = evaluate_labelled(labelled_file, improved)
    jittered = evaluate_labelled(labelled_file, improved, angle_jitter_beams=1.0)
    assert jittered.auc > plain.auc - 0.02 and plain.auc > 0.9
    document, markdown = cli_report(tmp_path, labelled_file, "--angle-jitter", "1")
    assert document["angle_jitter_beams"] == 1.0
    assert "angle_min moved within 0.5 beam" in markdown
    assert main(["eval-labels", str(labelled_file), "--angle-jitter", "-1"]) == 2


def pitches_seen(path, **options):
    """The IMU pitch a filter gets, scan by scan, from ``evaluate_labelled(path, ...,
    inputs=["imu"], **options)``."""
    seen = []

    class PitchSpy(Spy):
        def process(self, scan, **inputs):
            seen.append(inputs["pitch_rad"])
            return super().process(scan)

    entry = register_filter(
        FilterEntry("pitch_spy", PitchSpy, OracleParams, "", needs=("pitch_rad",))
    )
    try:
        evaluate_labelled(path, entry, inputs=["imu"], **options)
    finally:
        unregister_filter("pitch_spy")
    return seen


def test_the_imu_nose_up_option_negates_the_pitch_the_filters_get(tmp_path):
    arrays, _ = labelled_arrays()
    arrays["pitch_rad"] = np.linspace(-0.1, 0.1, len(arrays["ranges"]))
    arrays["roll_rad"] = np.zeros(len(arrays["ranges"]))
    path = tmp_path / "imu.npz"
    np.savez(path, **arrays)
    np.testing.assert_allclose(pitches_seen(path, imu_nose_up=True), -arrays["pitch_rad"])
    out = tmp_path / "report"
    assert (
        main(["eval-labels", str(path), "--inputs", "imu", "--imu-nose-up", "--out", str(out)]) == 0
    )
    assert json.loads((out / "report.json").read_text())["imu_nose_up"] is True
    assert "pitch is negated" in (out / "report.md").read_text()
    assert main(["eval-labels", str(path), "--imu-nose-up"]) == 2  # without --inputs imu


def test_every_nth_scan_scores_as_the_file_thinned_out(tmp_path):
    # keeping every 3rd scan is the file written with every 3rd scan, labels and robot
    # inputs with it
    arrays, _ = labelled_arrays()
    count = len(arrays["ranges"])
    arrays["pitch_rad"] = np.linspace(-0.1, 0.1, count)
    path, thinned_path = tmp_path / "full.npz", tmp_path / "thinned.npz"
    np.savez(path, **arrays)
    per_scan = {k for k, v in arrays.items() if np.ndim(v) >= 1 and len(v) == count}
    np.savez(thinned_path, **{k: v[::3] if k in per_scan else v for k, v in arrays.items()})
    np.testing.assert_allclose(pitches_seen(path, every=3), arrays["pitch_rad"][::3])
    improved = filter_entry("improved")
    every = evaluate_labelled(path, improved, every=3)
    thinned = evaluate_labelled(thinned_path, improved)
    assert every.scans == thinned.scans == len(range(0, count, 3))
    assert (every.tp, every.fp, every.positives) == (thinned.tp, thinned.fp, thinned.positives)
    # thinned first: the noise is drawn on the scans kept, as on the thinned file
    noisy = evaluate_labelled(path, improved, every=3, range_noise_m=0.03)
    noisy_thinned = evaluate_labelled(thinned_path, improved, range_noise_m=0.03)
    assert (noisy.tp, noisy.fp) == (noisy_thinned.tp, noisy_thinned.fp)
    assert noisy.tp != every.tp or noisy.fp != every.fp
    document, markdown = cli_report(tmp_path, path, "--every", "3")
    assert document["every"] == 3
    assert "Every 3rd scan kept" in markdown
    assert main(["eval-labels", str(path), "--every", "0"]) == 2


def scored_as_written(path, written_path, **options):
    """The improved filter's reports on ``path`` changed by ``options`` and on the file
    written so, which count the same hits, false alarms and positives."""
    improved = filter_entry("improved")
    changed = evaluate_labelled(path, improved, **options)
    written = evaluate_labelled(written_path, improved)
    assert (changed.tp, changed.fp, changed.positives) == (
        written.tp,
        written.fp,
        written.positives,
    )
    return changed, written


def test_every_nth_beam_scores_as_the_file_written_with_a_coarser_spacing(tmp_path):
    # keeping every 2nd beam is the file of a scanner with twice the spacing over the same
    # sweep: the beams kept, their labels, the increments doubled
    arrays, _ = labelled_arrays()
    arrays["time_increment"] = np.float64(0.1 / arrays["ranges"].shape[1])
    path, coarse_path = tmp_path / "full.npz", tmp_path / "coarse.npz"
    np.savez(path, **arrays)
    coarse = dict(arrays, ranges=arrays["ranges"][:, ::2], labels=arrays["labels"][:, ::2])
    coarse["angle_increment"] = arrays["angle_increment"] * 2
    coarse["time_increment"] = arrays["time_increment"] * 2
    np.savez(coarse_path, **coarse)
    improved = filter_entry("improved")
    strided, written = scored_as_written(path, coarse_path, beam_stride=2)
    assert strided.beams == written.beams and strided.scans == written.scans
    assert strided.positives < evaluate_labelled(path, improved).positives
    # after --every: the scans kept, then their beams
    both = evaluate_labelled(path, improved, every=3, beam_stride=2)
    assert both.scans == len(range(0, len(arrays["ranges"]), 3))
    document, markdown = cli_report(tmp_path, path, "--beam-stride", "2")
    assert document["beam_stride"] == 2
    assert "Every 2nd beam kept" in markdown
    assert main(["eval-labels", str(path), "--beam-stride", "0"]) == 2
    with pytest.raises(ValueError, match="--beam-stride 400 leaves fewer than 2"):
        evaluate_labelled(path, improved, beam_stride=400)


def test_a_shorter_reach_scores_as_the_file_written_by_a_shorter_range_scanner(tmp_path):
    # every return beyond 3 m no echo, range_max 3 m: the file a 3 m scanner would write
    arrays, _ = labelled_arrays()
    path, short_path = tmp_path / "full.npz", tmp_path / "short.npz"
    np.savez(path, **arrays)
    ranges = np.where(arrays["ranges"] > 3.0, np.inf, arrays["ranges"])
    np.savez(short_path, **dict(arrays, ranges=ranges, range_max=np.float64(3.0)))
    improved = filter_entry("improved")
    reach, _ = scored_as_written(path, short_path, range_max_m=3.0)
    assert reach.beams < evaluate_labelled(path, improved).beams
    document, markdown = cli_report(tmp_path, path, "--range-max", "3")
    assert document["range_max_m"] == 3.0
    assert "Returns beyond 3 m read no echo" in markdown
    assert main(["eval-labels", str(path), "--range-max", "0"]) == 2
    with pytest.raises(ValueError, match="--range-max 50: its scans reach"):
        evaluate_labelled(path, improved, range_max_m=50.0)
