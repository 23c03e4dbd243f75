"""The Hough Scan Matcher (Censi, Iocchi and Grisetti 2005, ref. 27).

The Hough transform ``HT(theta, rho)`` counts the points whose projection on the
direction ``theta`` (in ``[0, pi)``) is ``rho``. Its spectrum ``HS(theta) = sum_rho
HT(theta, rho)^2`` does not change when the scan translates, and shifts circularly when it
rotates. So:

1. **rotation**: the circular cross-correlation of the two spectra peaks at the rotation
   (modulo pi); its highest local maxima, each also taken plus pi, are the hypotheses;
2. **translation**: for each hypothesis the rotated source's projection on a few
   dominant directions ``n_k`` (peaks of the target's spectrum, spread apart) is
   cross-correlated with the target's; the peak lag is ``t . n_k``, and least squares over
   the directions gives ``t``;
3. the hypothesis whose pose brings the most source points within ``inlier_m`` of the
   target wins.

Peaks are refined below one bin by a parabola through the peak and its neighbours.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike
from scipy.signal import correlate
from scipy.spatial import cKDTree

from scaneval.geometry import compose, transform_points
from scaneval.match_result import MatchResult, finite_points, result

MIN_DIRECTION_SPREAD = math.radians(30.0)  # rad, translation directions this far apart


def hough_transform(
    points: np.ndarray, directions: np.ndarray, rho_resolution: float, rho_max: float
) -> np.ndarray:
    """Vote counts ``HT[direction, rho bin]`` over ``rho`` in ``[-rho_max, rho_max]``."""
    bins = math.ceil(2.0 * rho_max / rho_resolution) + 1
    rho = points @ np.vstack((np.cos(directions), np.sin(directions)))  # (n, d)
    index = np.rint((rho + rho_max) / rho_resolution).astype(np.intp)
    inside = (index >= 0) & (index < bins)
    flat = (np.arange(directions.size) * bins + index)[inside]
    return np.bincount(flat, minlength=directions.size * bins).reshape(directions.size, bins)


def refine_peak(values: np.ndarray, peak: int, circular: bool = False) -> float:
    """Sub-bin position of a peak: vertex of the parabola through it and its neighbours."""
    n = values.size
    if not circular and (peak == 0 or peak == n - 1):
        return float(peak)
    left, centre, right = values[(peak - 1) % n], values[peak], values[(peak + 1) % n]
    curvature = left - 2.0 * centre + right
    return float(peak) if curvature >= 0.0 else peak + 0.5 * (left - right) / curvature


def circular_maxima(values: np.ndarray, count: int) -> np.ndarray:
    """Indices of the ``count`` highest local maxima of a circular signal, best first."""
    peaks = np.flatnonzero((values >= np.roll(values, 1)) & (values > np.roll(values, -1)))
    return peaks[np.argsort(values[peaks])[::-1][:count]]


def spread_directions(spectrum: np.ndarray, resolution: float, count: int) -> np.ndarray:
    """Indices of up to ``count`` spectrum peaks, greedily at least 30 degrees apart."""
    chosen: list[int] = []
    for peak in circular_maxima(spectrum, spectrum.size):
        gaps = [abs(peak - c) * resolution for c in chosen]
        if all(min(gap, math.pi - gap) >= MIN_DIRECTION_SPREAD for gap in gaps):
            chosen.append(int(peak))
        if len(chosen) == count:
            break
    return np.array(chosen, dtype=np.intp)


def translation(
    source_ht: np.ndarray,
    target_ht: np.ndarray,
    directions: np.ndarray,
    rows: np.ndarray,
    rho_resolution: float,
    max_lag: int,
) -> np.ndarray | None:
    """Least-squares ``t`` from the projection shifts on the direction rows ``rows``."""
    normals, shifts, weights = [], [], []
    centre = source_ht.shape[1] - 1  # lag 0 in the full correlation
    for row in rows:
        corr = correlate(target_ht[row], source_ht[row], mode="full", method="fft")
        window = corr[centre - max_lag : centre + max_lag + 1]
        peak = int(np.argmax(window))
        if window[peak] <= 0.0:
            continue
        shifts.append((refine_peak(window, peak) - max_lag) * rho_resolution)
        normals.append((math.cos(directions[row]), math.sin(directions[row])))
        weights.append(math.sqrt(window[peak]))
    if len(normals) < 2:
        return None
    w = np.array(weights)[:, None]
    solution, *_ = np.linalg.lstsq(np.array(normals) * w, np.array(shifts) * w[:, 0])
    return solution


def hsm(
    source_xy: ArrayLike,
    target_xy: ArrayLike,
    initial_pose: ArrayLike = (0.0, 0.0, 0.0),
    angle_resolution_rad: float = math.radians(0.5),
    rho_resolution_m: float = 0.02,
    max_translation_m: float = 1.0,
    rotation_hypotheses: int = 3,
    translation_directions: int = 4,
    inlier_m: float = 0.05,
    max_correspondence_m: float = 1.0,
) -> MatchResult:
    """Hough Scan Matcher: rotation from Hough spectra, translation from projections.

    A global matcher: it needs no initial guess, and searches every rotation and
    translations up to ``max_translation_m`` along each direction (from the initial
    pose, when one is given).

    Args:
        source_xy: points to align, m, shape ``(n, 2)``.
        target_xy: reference points, m, shape ``(m, 2)``.
        initial_pose: ``(x, y, theta)`` applied to the source first, m, m, rad; the
            search is for the pose that remains.
        angle_resolution_rad: bin width of the Hough directions, rad.
        rho_resolution_m: bin width of the projections, m.
        max_translation_m: largest projected translation searched, m.
        rotation_hypotheses: rotation peaks tried (each also plus pi).
        translation_directions: spectrum peaks used to solve for the translation.
        inlier_m: distance, m, within which a source point counts when the hypotheses
            are compared.
        max_correspondence_m: only for the reported fitness (see
            :mod:`scaneval.match_result`).

    Returns:
        The :class:`MatchResult`; ``iterations`` is the number of poses compared;
        ``converged`` is False when no hypothesis gave a translation (fewer than two
        distinct directions with votes in common).
    """
    initial_pose = np.asarray(initial_pose, dtype=np.float64)
    original, target = finite_points(source_xy), finite_points(target_xy)
    source = transform_points(original, initial_pose)
    tree = cKDTree(target)
    if len(source) < 2 or len(target) < 2:
        return result(initial_pose, original, tree, 0, False, max_correspondence_m)
    count = round(math.pi / angle_resolution_rad)
    resolution = math.pi / count
    directions = resolution * np.arange(count)
    rho_max = max(np.abs(source).max(), np.abs(target).max()) * math.sqrt(2.0) + max_translation_m
    source_spectrum = (hough_transform(source, directions, rho_resolution_m, rho_max) ** 2).sum(1)
    target_ht = hough_transform(target, directions, rho_resolution_m, rho_max)
    target_spectrum = (target_ht.astype(np.float64) ** 2).sum(axis=1)
    # circular cross-correlation: c[k] = sum_j HS_target[j + k] HS_source[j]
    spectra = np.fft.irfft(
        np.fft.rfft(target_spectrum) * np.conj(np.fft.rfft(source_spectrum)), n=count
    )
    rows = spread_directions(target_spectrum, resolution, translation_directions)
    max_lag = math.ceil(max_translation_m / rho_resolution_m)
    best, best_inliers, tried = np.zeros(3), -1, 0
    for peak in circular_maxima(spectra, rotation_hypotheses):
        for theta in refine_peak(spectra, int(peak), circular=True) * resolution + np.array(
            [0.0, math.pi]
        ):
            rotated = transform_points(source, (0.0, 0.0, theta))
            source_ht = hough_transform(rotated, directions, rho_resolution_m, rho_max)
            t = translation(source_ht, target_ht, directions, rows, rho_resolution_m, max_lag)
            if t is None:
                continue
            tried += 1
            pose = np.array([t[0], t[1], theta])
            distance, _ = tree.query(transform_points(source, pose), distance_upper_bound=inlier_m)
            inliers = int(np.isfinite(distance).sum())
            if inliers > best_inliers:
                best, best_inliers = pose, inliers
    pose = compose(best, initial_pose)
    return result(pose, original, tree, tried, tried > 0, max_correspondence_m)
