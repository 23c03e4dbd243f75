"""twsb tune: the search, the objective's one pass, held-out episodes, the command end to end."""

from __future__ import annotations

import contextlib
import dataclasses
import math

import numpy as np
import pytest

from pvfilter import ImprovedParams, ImprovedPitchVariationFilter, load_params
from pvfilter.synthetic import room_sequence
from twsb_sim.cli import main
from twsb_sim.tuning.cli import _report, _undefined_warnings
from twsb_sim.tuning.data import TuningRun
from twsb_sim.tuning.objective import THRESHOLDS, score, sweep
from twsb_sim.tuning.search import SPACE, params_at, search, unit_of


def synthetic_run(count: int = 60) -> TuningRun:
    sequence = room_sequence(count)
    finite = np.array([np.isfinite(s.ranges) for s in sequence.scans])
    positive = np.array(sequence.truth) & finite
    return TuningRun(
        name="synthetic", house="room", scans=tuple(sequence.scans), positive=positive,
        finite=finite, static=finite & ~positive, attitude=np.zeros((count, 2)),
        geometry={"lidar_height_m": 0.25, "axle_height_m": 0.08, "lidar_ahead_m": 0.0},
    )  # fmt: skip


def test_one_pass_counts_equal_fresh_filters_at_each_threshold():
    run = synthetic_run()
    counts, _ = sweep(ImprovedParams(), [run])
    for i in (0, 5, 10, len(THRESHOLDS) - 1):
        params = ImprovedParams(p_th=THRESHOLDS[i])
        pvf = ImprovedPitchVariationFilter(params)
        removed = np.array([pvf.process(s).removed for s in run.scans]) & run.finite
        tp = int((removed & run.positive).sum())
        assert counts[i].tolist() == [tp, int(removed.sum()) - tp, int(run.positive.sum()) - tp]


def test_scores_of_a_clean_sequence_and_the_held_out_threshold():
    run = synthetic_run()
    chosen = score(ImprovedParams(), [run], 0.9, choose=True)
    assert chosen.auc > 0.9 and chosen.precision >= 0.9
    fixed = score(dataclasses.replace(ImprovedParams(), p_th=0.3), [run], 0.9)
    assert fixed.p_th == 0.3  # not re-chosen


def test_runs_with_nothing_to_find_have_no_score():
    run = synthetic_run()
    level = dataclasses.replace(run, positive=np.zeros_like(run.positive), static=run.finite)
    empty = score(ImprovedParams(), [level], 0.9)
    assert empty.positives == 0 and not empty.defined
    assert np.isnan(empty.auc) and np.isnan(empty.f1) and np.isnan(empty.recall)
    # the filter still removes beams here (the scans pitch): all false alarms, precision 0
    assert empty.precision == 0.0 and empty.static_removed_pct > 0
    assert score(ImprovedParams(), [run], 0.9).positives == int(run.positive.sum())


def test_the_unit_box_maps_both_ways():
    params = ImprovedParams()
    back = params_at(params, unit_of(params))
    for d in SPACE:
        assert getattr(back, d.name) == pytest.approx(getattr(params, d.name), rel=5e-3)


def test_search_climbs_to_the_best_point_of_a_toy_objective():
    target = {"free_margin_m": 0.3, "min_points": 4}

    def closeness(params: ImprovedParams) -> float:
        return -abs(params.free_margin_m - 0.3) - abs(params.min_points - 4) / 10

    log = search(closeness, ImprovedParams(), samples=8, refine_rounds=6, progress=False)
    value, best = log.best
    assert value > -0.05 and best.min_points == target["min_points"]


@pytest.fixture(scope="module")
def quick_tune(tmp_path_factory):
    out = tmp_path_factory.mktemp("tune") / "robot.toml"
    printed = tmp_path_factory.mktemp("tune") / "printed.txt"
    with open(printed, "w") as stream, contextlib.redirect_stdout(stream):
        assert main(["tune", "--quick", "--quiet", "--out", str(out)]) == 0
    return out, printed.read_text()


def test_held_out_episodes_without_pitch_variation_are_not_scored():
    run = synthetic_run()
    level = dataclasses.replace(run, positive=np.zeros_like(run.positive))  # nothing to find
    rows = {
        "tuned, training": score(ImprovedParams(), [run]),
        "tuned, held-out": score(ImprovedParams(), [level]),
    }
    heldout = rows["tuned, held-out"]
    assert heldout.positives == 0 and not heldout.defined
    assert math.isnan(heldout.auc) and math.isnan(heldout.recall)
    assert rows["tuned, training"].defined and rows["tuned, training"].auc > 0.5
    (warning,) = _undefined_warnings(rows)
    assert "held-out episodes hold no pitch-variation beam" in warning
    tuning = {
        "objective": "auc",
        "target_precision": 0.9,
        "points_scored": 1,
        "wall_s": 0.0,
        "validation_scores": {"defaults": 0.5, "best of the search": 0.5},
        "defaults_kept": True,
    }
    printed = _report(rows, ImprovedParams(), ImprovedParams(), None, tuning)
    row = next(line for line in printed.splitlines() if line.startswith("tuned, held-out"))
    assert row.split()[2:4] == ["n/a", "n/a"] and "1.000" not in row


def test_quick_tune_writes_a_file_pvfilter_loads(quick_tune):
    quick_tune, printed = quick_tune
    assert "--quick is a smoke run" in printed
    params = load_params(quick_tune)
    assert isinstance(params, ImprovedParams)
    text = quick_tune.read_text()
    assert "[tuning]" in text and 'objective = "auc"' in text
    assert "held-out" in text


def test_a_bad_output_name_is_a_usage_error(tmp_path, capsys):
    assert main(["tune", "--quick", "--out", str(tmp_path / "robot.txt")]) == 2
    assert ".toml or .json" in capsys.readouterr().err
