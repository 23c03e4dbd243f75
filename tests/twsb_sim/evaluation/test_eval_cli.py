"""``twsb eval --quick`` runs end to end and writes every report file."""

from __future__ import annotations

import json

import pytest

from twsb_sim.cli import main
from twsb_sim.evaluation.report import REPORT_FILES


@pytest.fixture(scope="module")
def quick_report(tmp_path_factory):
    out = tmp_path_factory.mktemp("eval")
    assert main(["eval", "--quick", "--quiet", "--out", str(out)]) == 0
    return out


def _no_nan(text: str) -> None:
    raise ValueError(f"results.json holds {text}: not strict JSON")


def test_quick_eval_writes_every_report_file(quick_report):
    for name in REPORT_FILES:
        assert (quick_report / name).stat().st_size > 0, name
    results = json.loads((quick_report / "results.json").read_text(), parse_constant=_no_nan)
    for picture in (p for pictures in results["examples"].values() for p in pictures):
        assert (quick_report / picture).is_file()


def test_quick_eval_covers_every_experiment(quick_report):
    results = json.loads((quick_report / "results.json").read_text())
    assert set(results["pr"]) == {"normal_sequence", "disturb_sequence"}
    for curves in results["pr"].values():
        assert set(curves) == {"pvf", "pvf_detection_only", "datmo", "imu_gate", "imu_gate_truth"}
        for curve in curves.values():
            assert 0.0 <= curve["auc"] <= 1.0
    assert set(results["timing"]["methods"]) == {
        "PVF (detection + tracking)", "PVF (detection only)", "DATMO-like", "IMU height gate",
        "IMU height gate (true attitude)",
    }  # fmt: skip
    assert results["timing"]["pvf_over_datmo_rate"] > 0
    assert set(results["scan_matching"]["all"]["onset"]) == {"icp", "ndt", "hsm"}
    for diagnosis in results["diagnosis"].values():
        assert "unexplained" not in diagnosis["misses"], "the diagnosis agrees with the filter"
    report = (quick_report / "report.md").read_text()
    for heading in ("Our numbers next to the paper's", "Throughput", "Scan matching",
                    "Why it misses"):  # fmt: skip
        assert heading in report


def test_a_bad_house_is_a_one_line_usage_error(tmp_path, capsys):
    assert main(["eval", "--quick", "--out", str(tmp_path), "--houses", "castle"]) == 2
    assert "houses" in capsys.readouterr().err
