"""What ``twsb tune`` maximizes, measured on runs in one pass per parameter set.

The improved filter's state does not depend on ``p_th``, and a beam is removed exactly
when its score exceeds ``p_th``, so one pass over the runs gives the per-beam counts of
every threshold of the sweep (pooled over the runs, over beams with a finite range, as
the evaluation counts them). From them:

- ``auc``: the area under the precision-recall curve of the ``p_th`` sweep (docs/conventions.md's
  definition: trapezoids over recall, extended to recall 0);
- ``f1``: the best F1 over the thresholds whose precision is at least the target
  precision (0 when none reaches it).

Runs without a single pitch-variation beam give nothing to score: recall, F1 and AUC
over no positive are undefined (NaN, printed ``n/a``), not the 1.0 that the PR curve's
"precision 1 where nothing is removed" convention would read; precision stays defined
(0) only where beams were removed all the same, every one a false alarm.

The operating point written to the parameter file is the threshold with the best F1 among
those at the target precision on the training runs (the highest-precision one when none
reaches it); held-out runs are scored at that threshold, never re-chosen.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np

from pvfilter import ImprovedParams, make_filter
from scaneval.metrics import pr_curve
from twsb_sim.tuning.data import TuningRun

OBJECTIVES = ("auc", "f1")
THRESHOLDS: tuple[float, ...] = (
    *np.round(np.arange(0.0, 0.95, 0.05), 2).tolist(), 0.95, 0.99,
)  # fmt: skip


@dataclasses.dataclass(frozen=True)
class Score:
    """How a parameter set did on some runs.

    Attributes:
        auc: area under the PR curve of the p_th sweep.
        f1: best F1 at or above the target precision (0 if none).
        p_th: the operating point chosen (see the module docstring).
        precision: precision at ``p_th``.
        recall: recall at ``p_th``.
        static_removed_pct: STATIC beams removed at ``p_th``, % of all STATIC beams.
        positives: pitch-variation beams with a finite range in the runs; with none,
            the scores above (but a precision of 0 over false alarms) are NaN.
    """

    auc: float
    f1: float
    p_th: float
    precision: float
    recall: float
    static_removed_pct: float
    positives: int = 0

    @property
    def defined(self) -> bool:
        """Whether the runs held anything to find (the scores are numbers)."""
        return self.positives > 0

    def value(self, objective: str) -> float:
        """The number the search maximizes."""
        return self.auc if objective == "auc" else self.f1


def sweep(
    params: ImprovedParams, runs: Sequence[TuningRun], imu: bool = False
) -> tuple[np.ndarray, np.ndarray]:
    """Counts (tp, fp, fn) per threshold of :data:`THRESHOLDS`, and STATIC beams removed
    per threshold with the total, from one pass over ``runs``.

    Each run is filtered with ``params`` at the run's own LiDAR and axle heights.
    """
    values = np.asarray(THRESHOLDS)[:, None]
    counts = np.zeros((len(THRESHOLDS), 3), dtype=np.int64)
    static = np.zeros(len(THRESHOLDS) + 1, dtype=np.int64)  # removed per threshold, total
    for run in runs:
        pvf = make_filter("improved", params, robot_geometry=run.geometry)
        for k, scan in enumerate(run.scans):
            pitch, roll = run.attitude[k] if imu else (None, None)
            scores = pvf.process(scan, pitch_rad=pitch, roll_rad=roll).scores
            removed = (scores[None, :] > values) & run.finite[k]
            tp = np.count_nonzero(removed & run.positive[k], axis=1)
            fn = np.count_nonzero(run.positive[k]) - tp
            counts += np.stack((tp, removed.sum(axis=1) - tp, fn), axis=1)
            static[:-1] += np.count_nonzero(removed & run.static[k], axis=1)
            static[-1] += np.count_nonzero(run.static[k])
    return counts, static


def score(
    params: ImprovedParams,
    runs: Sequence[TuningRun],
    target_precision: float = 0.9,
    imu: bool = False,
    choose: bool = False,
) -> Score:
    """Score ``params`` on ``runs`` (see the module docstring).

    Args:
        params: the parameters.
        runs: the runs.
        target_precision: the precision the operating point should reach.
        imu: give the filter the IMU's pitch and roll.
        choose: pick the operating point on these runs; otherwise report ``params.p_th``
            (held-out runs must not choose it).
    """
    counts, static = sweep(params, runs, imu)
    curve = pr_curve(THRESHOLDS, *counts.T)
    precision, recall = curve.precision, curve.recall
    f1 = np.where(precision + recall > 0, 2 * precision * recall / (precision + recall + 1e-12), 0)
    reaching = precision >= target_precision
    if not choose:
        best = int(np.argmin(np.abs(np.asarray(THRESHOLDS) - params.p_th)))
    elif reaching.any():
        best = int(np.flatnonzero(reaching)[np.argmax(f1[reaching])])
    else:
        best = int(np.argmax(precision))
    positives = int(counts[0, 0] + counts[0, 2])  # tp + fn: the same at every threshold
    static_pct = 100.0 * float(static[best]) / max(int(static[-1]), 1)
    if positives == 0:  # nothing to find: no score, only false alarms if any
        false_alarms = counts[best, 1] > 0
        return Score(
            auc=math.nan,
            f1=math.nan,
            p_th=float(THRESHOLDS[best]),
            precision=0.0 if false_alarms else math.nan,
            recall=math.nan,
            static_removed_pct=static_pct,
            positives=0,
        )
    return Score(
        auc=float(curve.auc),
        f1=float(np.max(f1[reaching])) if reaching.any() else 0.0,
        p_th=float(THRESHOLDS[best]),
        precision=float(precision[best]),
        recall=float(recall[best]),
        static_removed_pct=static_pct,
        positives=positives,
    )


def count_positives(runs: Sequence[TuningRun]) -> int:
    """Pitch-variation beams with a finite range in ``runs`` (what recall counts over)."""
    return sum(int(np.count_nonzero(run.positive)) for run in runs)
