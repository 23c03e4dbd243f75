"""Scoring a SLAM trajectory: ATE after the stated alignment, and what a tracking failure is."""

import numpy as np

from scaneval.geometry import compose
from scaneval.slam import FAILURE_DISTANCE_M, score_trajectory


def _square(count: int = 80) -> np.ndarray:
    t = np.linspace(0.0, 4.0, count)
    return np.column_stack((np.minimum(t, 2.0), np.maximum(t - 2.0, 0.0), np.zeros(count)))


def test_a_rigidly_moved_estimate_scores_zero():
    truth = _square()
    moved = np.array([compose((1.0, -2.0, 0.7), pose) for pose in truth])
    score = score_trajectory(moved, truth)
    assert not score.failed
    assert score.rmse_m < 1e-9


def test_a_jump_beyond_the_threshold_is_a_divergence():
    truth = _square()
    estimate = truth.copy()
    estimate[40:, 0] += 2.5 * FAILURE_DISTANCE_M
    score = score_trajectory(estimate, truth, stamps_s=0.1 * np.arange(len(truth)))
    assert score.failed and score.failure.startswith("diverged")
    assert " at t=" in score.failure
    assert np.isfinite(score.rmse_m)  # the ATE is still reported


def test_a_reported_loss_or_a_crash_is_a_failure_even_when_close():
    truth = _square()
    assert score_trajectory(truth, truth, lost_at_scan=12).failed
    crashed = truth.copy()
    crashed[30:] = np.nan
    score = score_trajectory(crashed, truth, error="RuntimeError: boom")
    assert score.failed and "50 of 80 poses" in score.failure
    assert score.rmse_m < 1e-9  # over the poses it did give


def test_no_estimate_at_all_is_a_failure_without_an_ate():
    truth = _square()
    score = score_trajectory(np.full_like(truth, np.nan), truth)
    assert score.failed and score.ate is None and np.isnan(score.rmse_m)
