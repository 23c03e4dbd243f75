"""Rerun recordings of runs, read back: entities, scans, labels, decisions, CLI flags."""

from __future__ import annotations

import dataclasses
import math
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest
import rerun as rr
from rerun.chunk import RrdReader

from pvfilter import FilterParams, PitchVariationFilter
from twsb_sim.cli import EXIT_USAGE, main
from twsb_sim.labels import BeamLabel, is_pitch_variation
from twsb_sim.rerun_log import (
    APPLICATION_ID,
    BeamDecision,
    RerunLogger,
    beam_decisions,
    paths,
    rerun_sink,
)
from twsb_sim.rerun_log.events import SHOVE_ARROW_M_PER_N
from twsb_sim.runner import run_scenario
from twsb_sim.scenario import load_scenario
from twsb_sim.sinks import NullSink

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"
# with the default (cheap, rotating) sensors, Table I's P_th of 0.8 removes nothing in the
# 3.2 s of hard stop the recordings hold; 0.6 removes some floor beams, which the
# decision and cluster tests need
P_TH = 0.6
# no usage data from tests: Rerun's tools send none when CI is set (checked in its source)
OFFLINE = {**os.environ, "CI": "1"}


@pytest.fixture(autouse=True, scope="module")
def _offline():
    """Whatever in this module starts Rerun code, it sends no usage data."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("CI", "1")
        yield


class Collect(NullSink):
    """Keeps the frames and the filter's results, to compare with what was recorded."""

    def __init__(self) -> None:
        self.frames, self.results = [], []

    def on_frame(self, frame, filter_result):
        self.frames.append(frame)
        self.results.append(filter_result)


def shortened(name: str, duration_s: float):
    """A shipped scenario cut to ``duration_s`` (what starts later is dropped)."""
    scenario = load_scenario(SCENARIOS / f"{name}.toml")
    return dataclasses.replace(
        scenario,
        duration_s=duration_s,
        commands=tuple(c for c in scenario.commands if c.t_s <= duration_s),
        shoves=tuple(s for s in scenario.shoves if s.end_s <= duration_s),
    )


def record(path: Path, scenario, **logger_options) -> Collect:
    """Run ``scenario`` with the filter, a RerunLogger writing ``path`` and a collector."""
    rec = rr.RecordingStream(APPLICATION_ID)
    rec.save(path)
    collect = Collect()
    logger = RerunLogger(rec, p_th=P_TH, close_recording=True, **logger_options)
    scan_filter = PitchVariationFilter(FilterParams(p_th=P_TH))
    run_scenario(scenario, seed=0, scan_filter=scan_filter, sinks=[logger, collect])
    return collect


def entity_rows(path: Path, entity: str, component: str) -> dict[int, list]:
    """Per frame index, the value of one component of one entity (time-indexed rows)."""
    rows = {}
    for chunk in RrdReader(path).stream().to_chunks():
        if chunk.entity_path != "/" + entity or chunk.is_static:
            continue
        batch = chunk.to_record_batch()
        if "frame" not in batch.schema.names or component not in batch.schema.names:
            continue
        for frame, value in zip(
            batch.column("frame").to_pylist(), batch.column(component).to_pylist(), strict=True
        ):
            rows[frame] = value
    return rows


@pytest.fixture(scope="module")
def hard_stop_recording(tmp_path_factory):
    """3.2 s of the hard-stop scenario: floor hits while accelerating, a few removals."""
    scenario = shortened("hard_stop", 3.2)
    path = tmp_path_factory.mktemp("rerun") / "hard_stop.rrd"
    # batches that do not divide the run; robot states at 50 Hz between the frames
    collect = record(path, scenario, flush_every=7, state_rate_hz=50.0)
    return path, collect


def test_recording_holds_the_expected_entity_paths(hard_stop_recording):
    path, _ = hard_stop_recording
    entities = {str(chunk.entity_path) for chunk in RrdReader(path).stream().to_chunks()}
    expected = [
        paths.HOUSE_FLOOR, paths.HOUSE_WALLS, f"{paths.HOUSE_FURNITURE}/boxes",
        f"{paths.ROBOT_BODY}/boxes", paths.ROBOT, paths.ROBOT_LIDAR, paths.TRAJECTORY,
        paths.LIDAR_HITS, paths.SENSOR_FRAME, paths.SENSOR_DECISION,
        paths.SENSOR_REMOVED, paths.SENSOR_CLUSTERS, paths.SENSOR_CLUSTER_BOXES,
        paths.SENSOR_CLUSTER_IDS, paths.PLOT_PITCH, paths.PLOT_WHEEL_TORQUE, paths.PLOT_BEAMS,
        paths.PLOT_PRECISION_RECALL, paths.PLOT_P_PV, paths.EVENTS,
    ]  # fmt: skip
    assert not [e for e in expected if "/" + e not in entities]
    assert RrdReader(path).blueprints, "the default blueprint travels with the file"


def test_one_scan_per_frame_with_one_point_per_valid_beam(hard_stop_recording):
    path, collect = hard_stop_recording
    scans = entity_rows(path, paths.SENSOR_DECISION, "Points2D:positions")
    hits = entity_rows(path, paths.LIDAR_HITS, "Points3D:positions")
    assert sorted(scans) == sorted(hits) == [f.index for f in collect.frames]
    for frame in collect.frames:
        valid = frame.scan.valid_mask()
        assert len(scans[frame.index]) == np.count_nonzero(valid)
        np.testing.assert_allclose(scans[frame.index], frame.scan.points()[valid], atol=1e-5)
        assert len(hits[frame.index]) == np.count_nonzero(np.isfinite(frame.hit_points_world[:, 0]))


def test_label_class_ids_are_the_simulators_labels(hard_stop_recording):
    path, collect = hard_stop_recording
    world = entity_rows(path, paths.LIDAR_HITS, "Points3D:class_ids")
    floor_seen = False
    for frame in collect.frames:
        hit = np.isfinite(frame.hit_points_world[:, 0])
        np.testing.assert_array_equal(world[frame.index], frame.labels[hit])
        floor_seen |= BeamLabel.FLOOR in world[frame.index]
    assert floor_seen, "the run should hold pitch-variation hits"


def test_without_a_filter_the_sensor_view_shows_the_labels(tmp_path):
    rec = rr.RecordingStream(APPLICATION_ID)
    rec.save(tmp_path / "no_filter.rrd")
    collect = Collect()
    logger = RerunLogger(rec, close_recording=True)
    run_scenario(shortened("hard_stop", 2.0), seed=0, sinks=[logger, collect])
    sensor = entity_rows(tmp_path / "no_filter.rrd", paths.SENSOR_LABELS, "Points2D:class_ids")
    assert not entity_rows(tmp_path / "no_filter.rrd", paths.SENSOR_DECISION, "Points2D:class_ids")
    for frame in collect.frames:
        np.testing.assert_array_equal(sensor[frame.index], frame.labels[frame.scan.valid_mask()])


def test_filter_decisions_are_the_mask_the_filter_returned(hard_stop_recording):
    path, collect = hard_stop_recording
    decisions = entity_rows(path, paths.SENSOR_DECISION, "Points2D:class_ids")
    removed_points = entity_rows(path, paths.SENSOR_REMOVED, "Points2D:positions")
    removed_any = False
    for frame, result in zip(collect.frames, collect.results, strict=True):
        valid = frame.scan.valid_mask()
        recorded = np.array(decisions[frame.index])
        removed = np.isin(recorded, [BeamDecision.TRUE_POSITIVE, BeamDecision.FALSE_POSITIVE])
        np.testing.assert_array_equal(removed, result.removed[valid])
        positive = np.isin(recorded, [BeamDecision.TRUE_POSITIVE, BeamDecision.FALSE_NEGATIVE])
        np.testing.assert_array_equal(positive, is_pitch_variation(frame.labels[valid]))
        assert len(removed_points[frame.index]) == np.count_nonzero(result.removed)
        removed_any |= bool(result.removed.any())
    assert removed_any, "the run should hold frames where the filter removed beams"


def test_clusters_carry_their_ids_and_removed_ones_a_box_and_label(hard_stop_recording):
    path, collect = hard_stop_recording
    points = entity_rows(path, paths.SENSOR_CLUSTERS, "Points2D:class_ids")
    boxes = entity_rows(path, paths.SENSOR_CLUSTER_BOXES, "Boxes2D:half_sizes")
    labels = entity_rows(path, paths.SENSOR_CLUSTER_IDS, "Points2D:labels")
    boxed = 0
    for frame, result in zip(collect.frames, collect.results, strict=True):
        expected_ids = np.full(len(frame.scan), -1)
        for k, record in enumerate(result.clusters):
            expected_ids[record.indices] = k
        np.testing.assert_array_equal(points[frame.index], expected_ids[expected_ids >= 0])
        removed = [(k, c) for k, c in enumerate(result.clusters) if c.detected or c.tracked]
        assert len(boxes[frame.index]) == len(labels[frame.index]) == len(removed)
        for label, (k, record) in zip(labels[frame.index], removed, strict=True):
            assert label.startswith(f"#{k} P=")
            assert label.endswith("detected" if record.detected else "tracked")
        boxed += len(removed)
    assert boxed, "the run should hold clusters the filter removed"


def test_robot_state_is_sampled_between_frames(hard_stop_recording):
    path, collect = hard_stop_recording
    sim_time_rows = 0
    for chunk in RrdReader(path).stream().to_chunks():
        if chunk.entity_path == "/" + paths.PLOT_PITCH and not chunk.is_static:
            sim_time_rows += chunk.num_rows
    frame_rows = entity_rows(path, paths.PLOT_PITCH, "Scalars:scalars")
    assert len(frame_rows) == len(collect.frames)
    # 50 Hz over 3.2 s, both ends included, and the first scan's revolution before time 0
    assert sim_time_rows == 160 + 1 + 1
    for frame in collect.frames:
        assert frame_rows[frame.index] == pytest.approx([np.degrees(frame.truth.pitch_rad)])


def test_rerun_rrd_verify_accepts_the_file(hard_stop_recording):
    path, _ = hard_stop_recording
    result = subprocess.run(
        ["rerun", "rrd", "verify", str(path)], env=OFFLINE, capture_output=True, text=True
    )
    assert result.returncode == 0, result.stderr


def test_a_recording_does_not_change_the_run(hard_stop_recording):
    _, recorded = hard_stop_recording
    plain = Collect()
    run_scenario(
        shortened("hard_stop", 3.2),
        seed=0,
        scan_filter=PitchVariationFilter(FilterParams(p_th=P_TH)),
        sinks=[plain],
    )
    for a, b in zip(plain.frames, recorded.frames, strict=True):
        np.testing.assert_array_equal(a.scan.ranges, b.scan.ranges)
        assert a.truth.pitch_rad == b.truth.pitch_rad


def test_a_fall_ends_the_run_at_the_same_time_with_a_recording(tmp_path):
    shove = dataclasses.replace(
        shortened("shove", 2.5).shoves[0], force_n=(150.0, 0.0, 0.0), duration_s=0.3
    )
    scenario = dataclasses.replace(shortened("shove", 4.0), shoves=(shove,))
    plain = run_scenario(scenario, seed=0)
    rec = rr.RecordingStream(APPLICATION_ID)
    rec.save(tmp_path / "fall.rrd")
    recorded = run_scenario(scenario, seed=0, sinks=[RerunLogger(rec, close_recording=True)])
    assert plain.fell and recorded.fell
    assert (recorded.end_reason, recorded.frames) == (plain.end_reason, plain.frames)
    events = entity_rows(tmp_path / "fall.rrd", paths.EVENTS, "TextLog:text")
    assert events[plain.frames - 1][0] == f"ended: {plain.end_reason}"


def test_shove_shows_as_an_arrow_while_it_acts(tmp_path):
    scenario = shortened("shove", 2.5)
    (shove,) = scenario.shoves
    path = tmp_path / "shove.rrd"
    record(path, scenario)
    arrows = entity_rows(path, paths.SHOVES, "Arrows3D:vectors")
    assert list(arrows) == [round(shove.t_s * 10)]  # at the frame the shove starts
    (vector,) = arrows[round(shove.t_s * 10)]
    assert np.linalg.norm(vector) == pytest.approx(
        np.linalg.norm(shove.force_n) * SHOVE_ARROW_M_PER_N, rel=1e-5
    )
    cleared = entity_rows(path, paths.SHOVES, "Clear:is_recursive")
    assert list(cleared) == [math.ceil(shove.end_s * 10)]  # the first frame after it ends
    events = entity_rows(path, paths.EVENTS, "TextLog:text")
    assert events[round(shove.t_s * 10)][0].startswith("shove")


def test_runs_logged_one_after_the_other_follow_each_other_on_the_timelines(tmp_path):
    rec = rr.RecordingStream(APPLICATION_ID)
    rec.save(tmp_path / "two.rrd")
    logger = RerunLogger(rec)  # e.g. the episodes of an env
    scenario = shortened("hard_stop", 1.0)
    for _ in range(2):
        run_scenario(scenario, seed=0, scan_filter=PitchVariationFilter(), sinks=[logger])
    rec.disconnect()
    times = {}
    for chunk in RrdReader(tmp_path / "two.rrd").stream().to_chunks():
        if chunk.entity_path == "/" + paths.SENSOR_DECISION and not chunk.is_static:
            batch = chunk.to_record_batch()
            times.update(
                zip(
                    batch.column("frame").to_pylist(),
                    batch.column("sim_time").to_pylist(),
                    strict=True,
                )
            )
    assert sorted(times) == list(range(22))  # 11 frames per run
    stamps = [times[k].total_seconds() for k in sorted(times)]
    assert np.all(np.diff(stamps) > 0)


def test_beam_decisions_are_the_four_classes():
    labels = np.array([BeamLabel.STATIC, BeamLabel.FLOOR, BeamLabel.STATIC, BeamLabel.CEILING])
    removed = np.array([False, True, True, False])
    assert list(beam_decisions(labels, removed)) == [
        BeamDecision.TRUE_NEGATIVE,
        BeamDecision.TRUE_POSITIVE,
        BeamDecision.FALSE_POSITIVE,
        BeamDecision.FALSE_NEGATIVE,
    ]


@pytest.fixture
def short_scenario(tmp_path) -> Path:
    path = tmp_path / "short.toml"
    path.write_text(
        'name = "short"\nduration_s = 1.0\n\n[house]\nname = "house1"\n\n'
        "[[commands]]\nt_s = 0.0\nvelocity_mps = 0.5\nramp_s = 0.5\n"
    )
    return path


def test_twsb_run_rrd_writes_a_recording(short_scenario, tmp_path):
    path = tmp_path / "out.rrd"
    assert main(["run", str(short_scenario), "--quiet", "--rrd", str(path)]) == 0
    frames = entity_rows(path, paths.SENSOR_DECISION, "Points2D:positions")
    assert sorted(frames) == list(range(11))


def test_logging_off_writes_no_file_and_the_run_works(short_scenario, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["run", str(short_scenario), "--quiet"]) == 0
    assert not list(tmp_path.rglob("*.rrd"))
    args = type("Args", (), {"rrd": None, "save": None, "spawn": False, "connect": False,
                             "url": None, "serve": False, "stdout": False, "headless": False,
                             "state_rate": 50.0})()  # fmt: skip
    assert isinstance(rerun_sink(args), NullSink)


def test_contradictory_flags_are_a_usage_error(short_scenario, capsys):
    assert main(["run", str(short_scenario), "--quiet", "--headless", "--spawn"]) == EXIT_USAGE
    assert "--headless" in capsys.readouterr().err


def test_the_improved_filter_s_clusters_are_logged_too(tmp_path):
    from rerun.chunk import RrdReader

    from twsb_sim.cli import main

    path = tmp_path / "improved.rrd"
    assert main(["run", "hard_stop", "--quiet", "--filter", "improved", "--rrd", str(path)]) == 0
    entities = {chunk.entity_path for chunk in RrdReader(path).stream().to_chunks()}
    assert any("clusters" in str(entity) for entity in entities), sorted(map(str, entities))


def test_the_improved_filter_s_level_view_is_drawn_along_each_beam(tmp_path):
    # the view each scan was compared with: one point per beam where it is known and
    # within range, at the view's range along the beam, in the sensor frame
    from pvfilter import make_filter

    path = tmp_path / "improved.rrd"
    rec = rr.RecordingStream(APPLICATION_ID)
    rec.save(path)
    collect = Collect()
    logger = RerunLogger(rec, p_th=0.5, close_recording=True)
    scenario = shortened("hard_stop", 2.0)
    run_scenario(scenario, seed=0, scan_filter=make_filter("improved"), sinks=[logger, collect])
    rows = entity_rows(path, paths.SENSOR_LEVEL_VIEW, "Points2D:positions")
    assert sorted(rows) == [f.index for f in collect.frames]
    for frame, result in zip(collect.frames, collect.results, strict=True):
        view = result.level_view_m
        shown = np.isfinite(view)
        angles = frame.scan.angles()[shown]
        expected = np.stack((np.cos(angles), np.sin(angles)), axis=1) * view[shown, None]
        np.testing.assert_allclose(np.array(rows[frame.index]).reshape(-1, 2), expected, atol=1e-4)
    assert not rows[collect.frames[0].index]  # the first scan has no view yet
    assert max(len(r) for r in rows.values()) > 100


def test_imu_estimate_and_odometry_are_plotted_against_the_truth(hard_stop_recording):
    path, collect = hard_stop_recording
    estimate_rows = 0
    for chunk in RrdReader(path).stream().to_chunks():
        if chunk.entity_path == "/" + paths.PLOT_PITCH_ESTIMATE and not chunk.is_static:
            estimate_rows += chunk.num_rows
    assert estimate_rows == sum(len(f.sensors.imu) for f in collect.frames)  # every sample
    errors = entity_rows(path, paths.PLOT_ODOMETRY_ERROR, "Scalars:scalars")
    assert len(errors) == len(collect.frames)
    first, last = collect.frames[0].truth, collect.frames[-1]
    c, s = math.cos(first.yaw_rad), math.sin(first.yaw_rad)
    odom_in_world = (
        first.position_base_in_world[:2]
        + np.array([[c, -s], [s, c]]) @ last.sensors.pose_base_in_odom[:2]
    )
    assert errors[last.index][0] == pytest.approx(
        np.linalg.norm(last.truth.position_base_in_world[:2] - odom_in_world), abs=1e-6
    )
    assert len(entity_rows(path, paths.ODOMETRY, "Points3D:positions")) == len(collect.frames)
