"""Per-beam precision and recall, PR curves and their area (the project's AUC rule).

Here, in the filter's own package, so a robot that installs the filter alone can score
it on labelled scan files (``pvfilter eval-labels``); :mod:`scaneval.metrics` re-exports
it for the evaluations.

Counts run over beams whose input range is finite. A beam is positive when its label is a
pitch-variation label (FLOOR, CEILING or HORIZONTAL) and predicted positive when the
method removed it. Precision is 1 where nothing is removed; recall is 1 where there is
nothing to find. Sum :func:`confusion_counts` over a whole sequence to get one PR point.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from numpy.typing import ArrayLike


def confusion_counts(
    removed: np.ndarray, labels_positive: np.ndarray, finite: np.ndarray
) -> tuple[int, int, int]:
    """True positives, false positives and false negatives over the finite beams.

    Args:
        removed: bool per beam, True where the method removed the beam.
        labels_positive: bool per beam, True where the beam is a pitch-variation point.
        finite: bool per beam, True where the input range is finite.

    Returns:
        ``(tp, fp, fn)``, beam counts.
    """
    removed, positive, finite = (
        np.asarray(a, dtype=bool) for a in (removed, labels_positive, finite)
    )
    if not removed.shape == positive.shape == finite.shape:
        raise ValueError(
            "removed, labels_positive, finite: must have the same shape, got "
            f"{removed.shape}, {positive.shape}, {finite.shape}"
        )
    predicted, positive = removed & finite, positive & finite
    tp = int(np.count_nonzero(predicted & positive))
    return tp, int(np.count_nonzero(predicted)) - tp, int(np.count_nonzero(positive)) - tp


def precision_recall_from_counts(tp: ArrayLike, fp: ArrayLike, fn: ArrayLike):
    """Precision and recall from counts (scalars or arrays): 1 where undefined."""
    tp, fp, fn = (np.asarray(a, dtype=np.float64) for a in (tp, fp, fn))
    with np.errstate(divide="ignore", invalid="ignore"):
        precision = np.where(tp + fp > 0, tp / (tp + fp), 1.0)
        recall = np.where(tp + fn > 0, tp / (tp + fn), 1.0)
    return precision, recall


def precision_recall(
    removed: np.ndarray, labels_positive: np.ndarray, finite: np.ndarray
) -> tuple[float, float]:
    """Per-beam precision and recall of one mask (or of masks stacked over a sequence).

    Args:
        removed: bool per beam, True where the method removed the beam.
        labels_positive: bool per beam, True where the beam is a pitch-variation point.
        finite: bool per beam, True where the input range is finite; other beams do not
            count.

    Returns:
        ``(precision, recall)``; precision is 1 when nothing is removed, recall is 1 when
        no finite beam is positive.
    """
    precision, recall = precision_recall_from_counts(
        *confusion_counts(removed, labels_positive, finite)
    )
    return float(precision), float(recall)


@dataclasses.dataclass(frozen=True)
class PrCurve:
    """A precision-recall curve from a threshold sweep.

    Attributes:
        thresholds: the swept parameter value of every point (P_th, a speed, a band...).
        precision: precision at every threshold.
        recall: recall at every threshold.
        auc: area under the curve by :func:`auc_pr`.
        tp, fp, fn: the beam counts behind every point.
    """

    thresholds: np.ndarray
    precision: np.ndarray
    recall: np.ndarray
    auc: float
    tp: np.ndarray
    fp: np.ndarray
    fn: np.ndarray

    def at(self, operating_point: float) -> dict[str, float]:
        """The curve's AUC and its precision and recall at one swept value (which must be
        one of :attr:`thresholds`), as a report states a method's operating point."""
        found = np.flatnonzero(self.thresholds == operating_point)
        if found.size == 0:
            raise ValueError(f"operating_point: {operating_point!r} is not a swept value")
        k = int(found[0])
        return {
            "auc": self.auc,
            "operating_point": operating_point,
            "precision": float(self.precision[k]),
            "recall": float(self.recall[k]),
        }


def pr_curve(thresholds: ArrayLike, tp: ArrayLike, fp: ArrayLike, fn: ArrayLike) -> PrCurve:
    """A :class:`PrCurve` from per-threshold beam counts (summed over the sequence).

    Args:
        thresholds: the swept values, shape ``(k,)`` (or ``(k, 2)`` for a band).
        tp, fp, fn: counts per threshold, shape ``(k,)``.
    """
    tp, fp, fn = (np.asarray(a, dtype=np.int64).reshape(-1) for a in (tp, fp, fn))
    thresholds = np.asarray(thresholds)
    if not len(thresholds) == tp.size == fp.size == fn.size:
        raise ValueError(
            "thresholds, tp, fp, fn: must have one entry per threshold, got "
            f"{len(thresholds)}, {tp.size}, {fp.size}, {fn.size}"
        )
    precision, recall = precision_recall_from_counts(tp, fp, fn)
    return PrCurve(thresholds, precision, recall, auc_pr(precision, recall), tp, fp, fn)


def auc_pr(precision: ArrayLike, recall: ArrayLike) -> float:
    """Area under a PR curve by the project's rule.

    The points are sorted by recall (ties: higher precision first, so the curve steps
    down), the curve is extended to recall 0 at the precision of its lowest-recall point,
    and the area is the trapezoid rule over recall. It is not extended beyond the
    highest recall reached. Points with a non-finite coordinate are ignored.

    Returns:
        The area, in ``[0, 1]`` for precisions and recalls in ``[0, 1]``; NaN when no
        point is left.
    """
    precision = np.asarray(precision, dtype=np.float64).reshape(-1)
    recall = np.asarray(recall, dtype=np.float64).reshape(-1)
    if precision.shape != recall.shape:
        raise ValueError(
            f"precision, recall: must have the same length, got {precision.size}, {recall.size}"
        )
    keep = np.isfinite(precision) & np.isfinite(recall)
    precision, recall = precision[keep], recall[keep]
    if precision.size == 0:
        return float("nan")
    order = np.lexsort((-precision, recall))
    recall = np.concatenate(([0.0], recall[order]))
    precision = np.concatenate((precision[order[:1]], precision[order]))
    # the trapezoid rule, written out: np.trapezoid needs numpy 2, and a robot may have 1.x
    return float(np.sum(np.diff(recall) * (precision[1:] + precision[:-1])) / 2.0)
