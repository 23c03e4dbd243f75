"""The project's per-beam precision, recall and AUC rule (pvfilter.precision_recall)."""

import numpy as np
import pytest

import scaneval.metrics
from pvfilter import precision_recall as pr
from pvfilter.precision_recall import (
    auc_pr,
    confusion_counts,
    pr_curve,
    precision_recall,
)


def test_precision_is_one_when_nothing_is_removed():
    positive = np.array([True, True, False, False])
    precision, recall = precision_recall(np.zeros(4, bool), positive, np.ones(4, bool))
    assert (precision, recall) == (1.0, 0.0)


def test_precision_recall_count_only_finite_beams():
    removed = np.array([True, True, False, True, False])
    positive = np.array([True, False, True, True, True])
    finite = np.array([True, True, True, False, False])
    assert confusion_counts(removed, positive, finite) == (1, 1, 1)
    assert precision_recall(removed, positive, finite) == (0.5, 0.5)


def test_auc_of_perfect_curve_is_one():
    assert auc_pr([1.0, 1.0], [0.5, 1.0]) == pytest.approx(1.0)
    assert auc_pr([1.0], [1.0]) == pytest.approx(1.0)


def test_auc_of_flat_curve_at_half_is_half():
    assert auc_pr([0.5, 0.5, 0.5], [0.1, 0.6, 1.0]) == pytest.approx(0.5)


def test_auc_sorts_unsorted_points_by_recall():
    precision, recall = [0.4, 1.0, 0.8], [1.0, 0.2, 0.6]
    expected = 0.2 * 1.0 + 0.4 * (1.0 + 0.8) / 2 + 0.4 * (0.8 + 0.4) / 2
    assert auc_pr(precision, recall) == pytest.approx(expected)


def test_auc_extends_to_recall_zero_at_lowest_recall_precision_and_not_beyond_last():
    # one point: a rectangle from recall 0 to 0.5 at its precision, nothing past 0.5
    assert auc_pr([0.6], [0.5]) == pytest.approx(0.3)
    assert auc_pr([0.6, 0.2], [0.5, 0.0]) == pytest.approx(0.5 * (0.2 + 0.6) / 2)


def test_pr_curve_from_counts():
    curve = pr_curve([0.9, 0.5, 0.1], tp=[0, 5, 10], fp=[0, 0, 10], fn=[10, 5, 0])
    np.testing.assert_allclose(curve.precision, [1.0, 1.0, 0.5])
    np.testing.assert_allclose(curve.recall, [0.0, 0.5, 1.0])
    assert curve.auc == pytest.approx(0.5 + 0.5 * 0.75)


def test_a_curve_states_its_operating_point():
    curve = pr_curve([0.0, 0.5, 0.8], tp=[10, 6, 2], fp=[10, 2, 0], fn=[0, 4, 8])
    figures = curve.at(0.5)
    assert figures == {"auc": curve.auc, "operating_point": 0.5, "precision": 0.75, "recall": 0.6}
    with pytest.raises(ValueError, match=r"0\.3 is not a swept value"):
        curve.at(0.3)


def test_the_trapezoids_are_numpys_over_the_extended_curve():
    rng = np.random.default_rng(7)
    for _ in range(20):
        precision, recall = rng.uniform(size=9), rng.uniform(size=9)
        order = np.lexsort((-precision, recall))
        extended_recall = np.concatenate(([0.0], recall[order]))
        extended_precision = np.concatenate((precision[order[:1]], precision[order]))
        expected = np.trapezoid(extended_precision, extended_recall)
        assert auc_pr(precision, recall) == pytest.approx(expected, rel=1e-12)


def test_the_evaluations_use_the_same_rule():
    for name in ("PrCurve", "auc_pr", "confusion_counts", "pr_curve", "precision_recall"):
        assert getattr(scaneval.metrics, name) is getattr(pr, name)
