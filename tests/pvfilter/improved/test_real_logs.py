"""The improved filter on real logs that never pitch into the floor: every removed beam is
a false alarm. The logs are not part of the repository: set ``PVFILTER_REAL_LOGS`` to
their folder (by default ``../shared/realdata`` beside the repository is tried)."""

import os
from pathlib import Path

import pytest

from pvfilter import ImprovedPitchVariationFilter
from pvfilter.logs import WORST_SCAN_LIMIT, evaluate_log

DEFAULT = Path(__file__).resolve().parents[3] / ".." / "shared" / "realdata"
FOLDER = Path(os.environ.get("PVFILTER_REAL_LOGS", DEFAULT))
# the share of valid beams the filter may remove, by log: a wheeled rover at 10 Hz, a
# hand-held and a flying scanner, and logs subsampled to one scan every 0.6-3 s
TARGETS = {
    "mines_exp1": 0.0005,
    "mines_exp2": 0.0005,
    "hokuyo_bag_2021": 0.003,
    "flying_rsise": 0.003,
    "intel_lab": 0.005,
    "mit_csail": 0.005,
}

pytestmark = pytest.mark.skipif(
    not FOLDER.is_dir(),
    reason=f"real logs not found at {FOLDER}: set PVFILTER_REAL_LOGS to the folder of the "
    "real scan files to run these tests",
)


@pytest.mark.parametrize("log", sorted(TARGETS))
def test_false_alarms_on_a_real_log_stay_under_its_target(log):
    path = FOLDER / f"{log}.npz"
    if not path.is_file():
        pytest.skip(f"{path}: not found")
    report = evaluate_log(path, "improved", ImprovedPitchVariationFilter)
    assert report.removed_share <= TARGETS[log], report
    assert report.worst_scan_share <= WORST_SCAN_LIMIT, report
