"""Detection module (paper III-D, Algorithm 1): which seed clusters are pitch variation.

Per cluster C of the scan at time t:

- eq. 1, perpendicular variance ratio ``v_C = v_y / (v_x + v_y)``
  (:func:`pvfilter.clusters.perpendicular_variance_ratio`); clusters with
  ``v_C < v_th`` are skipped (Algorithm 1, line 4);
- eq. 2, angular confidence ``P(theta_C) = exp(-cos^2(theta_C) / (2 sigma_theta^2))``,
  with ``theta_C`` the bearing of the centroid from the sensor origin;
- eq. 3-4, likelihood ``P(L_C)``: the mean over the cluster's points of
  ``exp(-d^2 / (2 sigma_l^2))``, ``d`` the distance to the nearest point of the previous
  scan ``z^{t-1}`` (found in its KD-tree, so no likelihood grid is built);
- eq. 5, ``P(C_pv) = 1 - P(theta_C) P(L_C)``; detected when ``P(C_pv) > p_th``.

Choices the paper leaves open:

- A cluster whose points all coincide has no direction: ``v_C = 0`` (skipped).
- Skipped clusters get no likelihood: their ``P(L_C)`` and ``P(C_pv)`` are NaN.
- With no previous scan, or a previous scan without a valid point, there is no
  likelihood field: ``P(L_C) = 1`` (no evidence of change), so nothing is detected.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from scipy.spatial import cKDTree

from pvfilter.clusters import perpendicular_variance_ratio
from pvfilter.paper.clustering import SeedClusters
from pvfilter.paper.params import FilterParams


def angular_confidence(centroids: np.ndarray, sigma_theta: float) -> np.ndarray:
    """Eq. 2: ``P(theta_C) = exp(-cos^2(theta_C) / (2 sigma_theta^2))`` per cluster.

    Args:
        centroids: (x_C, y_C) per cluster in the sensor frame, m, shape ``(k, 2)``.
        sigma_theta: spread of the angular distribution, 1.
    """
    cos_theta = np.cos(np.arctan2(centroids[:, 1], centroids[:, 0]))
    return np.exp(-(cos_theta**2) / (2.0 * sigma_theta**2))


def point_likelihood(distances: np.ndarray, sigma_l: float) -> np.ndarray:
    """Eq. 3: ``L(p) = exp(-d^2 / (2 sigma_l^2))`` for nearest-neighbour distances ``d``, m."""
    return np.exp(-(distances**2) / (2.0 * sigma_l**2))


def cluster_likelihood(likelihoods: np.ndarray, labels: np.ndarray, k: int) -> np.ndarray:
    """Eq. 4: ``P(L_C)``, the mean point likelihood of each of ``k`` clusters.

    Args:
        likelihoods: eq. 3 per point.
        labels: cluster id (0..k-1) per point.
        k: number of clusters; a cluster without points gets NaN.
    """
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.bincount(labels, likelihoods, k) / np.bincount(labels, minlength=k)


def pitch_variation_probability(p_theta: np.ndarray, p_likelihood: np.ndarray) -> np.ndarray:
    """Eq. 5: ``P(C_pv) = 1 - P(theta_C) P(L_C)``."""
    return 1.0 - p_theta * p_likelihood


@dataclasses.dataclass(frozen=True, eq=False)
class Detection:
    """Algorithm 1's output for one scan, with every intermediate value per cluster.

    Attributes:
        clusters: the seed clusters S_C^t.
        v_c: eq. 1 per cluster, shape ``(k,)``.
        p_theta: eq. 2 per cluster.
        p_likelihood: eq. 4 per cluster; NaN where skipped by the ``v_th`` gate.
        p_pv: eq. 5 per cluster; NaN where skipped by the ``v_th`` gate.
        detected: ``P(C_pv) > p_th`` per cluster (the set S_pv^t).
        new_sequence: this scan starts a sequence (first scan, reset, stamp went back):
            the tracker forgets its queue.
    """

    clusters: SeedClusters
    v_c: np.ndarray
    p_theta: np.ndarray
    p_likelihood: np.ndarray
    p_pv: np.ndarray
    detected: np.ndarray
    new_sequence: bool = False


def detect_clusters(
    clusters: SeedClusters,
    previous_tree: cKDTree | None,
    params: FilterParams,
    new_sequence: bool = False,
) -> Detection:
    """Algorithm 1: score every cluster and detect the pitch-variation clusters.

    Args:
        clusters: the seed clusters of the current scan.
        previous_tree: KD-tree T_kd^{t-1} of the previous scan, ``None`` if there is none.
        params: ``v_th``, ``sigma_theta``, ``sigma_l`` and ``p_th`` are used.
        new_sequence: passed on to the result (see :class:`Detection`).

    Returns:
        The per-cluster values and the detected set.
    """
    k = len(clusters)
    v_c = perpendicular_variance_ratio(clusters.variances)
    p_theta = angular_confidence(clusters.centroids, params.sigma_theta)
    gated = v_c >= params.v_th  # Algorithm 1, line 4: only these are scored
    p_likelihood = np.full(k, np.nan)
    if previous_tree is None or previous_tree.n == 0:
        p_likelihood[gated] = 1.0  # no likelihood field: no evidence of change
    elif gated.any():
        labels = clusters.labels
        scored = np.flatnonzero(gated[labels] & (labels >= 0))
        distances = previous_tree.query(clusters.points[scored])[0]
        likelihoods = point_likelihood(distances, params.sigma_l)
        p_likelihood[gated] = cluster_likelihood(likelihoods, labels[scored], k)[gated]
    p_pv = pitch_variation_probability(p_theta, p_likelihood)
    with np.errstate(invalid="ignore"):
        detected = p_pv > params.p_th  # NaN (skipped) compares False
    return Detection(clusters, v_c, p_theta, p_likelihood, p_pv, detected, new_sequence)
