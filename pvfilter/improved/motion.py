"""Ego-motion between consecutive scans, from the scans alone.

The level-view memory (:mod:`pvfilter.improved.memory`) must follow the sensor as it
turns and drives, or every turn makes the world look new. No odometry is assumed: the
motion comes from the two scans in two steps, both cheap on 720 beams:

1. **Turn, to the nearest beam**: the previous ranges shifted by ``s`` beams are compared
   with the current ones (sum of the clipped absolute differences), first for every shift
   near the previous turn on every other beam (the turn rate changes little between scans), and
   only if that fails for every shift the fastest turn allows on every fourth beam; the
   best ``s`` gives ``theta_0 = s * angle_increment``.
2. **Fine turn and translation**: a point-to-line least-squares step, solved twice with the
   worst residuals dropped in between. Beam ``i`` of the current scan (point ``p``, local
   line normal ``n``) and the previous point the coarse turn puts on it (``q``) lie on the
   same surface, so ``n . (R(d_theta) q + t - p) = 0``, linear in ``(d_theta, t)``. The
   previous motion (constant velocity) enters as a weak prior: it decides directions the
   scans do not constrain (along a corridor).

Convention: a static point at ``q`` in the previous sensor frame is at ``R(theta) q + t``
in the current one. The caller leaves out beams that may be pitch variation; pairs
farther apart than ``association_m`` after the coarse turn take no part.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from pvfilter.improved.beams import BeamLayout, indices

MIN_PAIRS = 20  # fewer usable beam pairs: keep the coarse turn, no translation
CLIP_M = 0.5  # m: range differences are clipped here in the coarse search
NEAR_SHIFTS = 3  # beams: the turn is first sought this close to the previous one
# The prior as pseudo-observations: (row noise / prior spread)^2 per unknown, with a row
# noise of 2 cm and spreads of 0.01 rad and 3 cm per scan
PRIOR_WEIGHTS = np.diag([(0.02 / 0.01) ** 2, (0.02 / 0.03) ** 2, (0.02 / 0.03) ** 2])


@dataclasses.dataclass(frozen=True)
class Motion:
    """The sensor's motion between two scans (see the module docstring for the convention).

    Attributes:
        theta_rad: rotation, rad.
        tx_m: translation along the current x axis, m.
        ty_m: translation along the current y axis, m.
        pairs: beam pairs used in the fine step (0: coarse turn only, or no motion).
    """

    theta_rad: float = 0.0
    tx_m: float = 0.0
    ty_m: float = 0.0
    pairs: int = 0

    def apply(self, points: np.ndarray) -> np.ndarray:
        """Points of the previous sensor frame in the current one, m, ``(k, 2)``."""
        c, s = math.cos(self.theta_rad), math.sin(self.theta_rad)
        # a matrix product, not x c - y s by hand: BLAS fuses multiply and add, and the
        # filter's results are kept bit for bit
        moved = points @ np.array([[c, s], [-s, c]])
        moved[:, 0] += self.tx_m  # per column: broadcasting a pair over rows is slower
        moved[:, 1] += self.ty_m
        return moved


def coarse_turn(
    ranges: np.ndarray, previous: np.ndarray, max_shift: int, layout: BeamLayout, expected: int
) -> int:
    """The beam shift of ``previous`` that best matches ``ranges`` (NaN: not compared).

    The turn rate changes little between scans, so the shifts next to the ``expected``
    one are tried first on every other beam; only when the best of them is at the edge of
    that window are all shifts up to ``max_shift`` tried, on every fourth beam.
    """
    near = np.arange(expected - NEAR_SHIFTS, expected + NEAR_SHIFTS + 1)
    best = _best_shift(ranges, previous, near, layout, 2)
    if abs(best - expected) < NEAR_SHIFTS:
        return best
    best = _best_shift(ranges, previous, np.arange(-max_shift, max_shift + 1), layout, 4)
    return _best_shift(ranges, previous, np.arange(best - 2, best + 3), layout, 1)


def _best_shift(
    ranges: np.ndarray, previous: np.ndarray, shifts: np.ndarray, layout: BeamLayout, stride: int
) -> int:
    """The shift with the least clipped range difference over every ``stride``-th beam."""
    beams, source = layout.shift_table(int(shifts[0]), len(shifts), stride)
    values = previous if layout.ring else np.concatenate((previous, [np.nan]))  # -1: outside, NaN
    # |previous - ranges| clipped at CLIP_M, in one buffer (fmin: NaN -> CLIP_M)
    cost = values.take(source)
    cost -= ranges.take(beams)
    np.fmin(np.abs(cost, out=cost), CLIP_M, out=cost)
    return int(shifts[np.add.reduce(cost, axis=1).argmin()])  # ties: the lowest shift


def estimate_motion(
    points: np.ndarray,
    directions: np.ndarray,
    previous_points: np.ndarray,
    layout: BeamLayout,
    max_shift: int,
    association_m: float,
    prior: Motion | None = None,
) -> Motion:
    """The sensor's motion from the previous scan to this one.

    Args:
        points: this scan's points per beam, sensor frame, m, ``(n, 2)``; NaN rows where
            the beam has no usable return.
        directions: local line direction per beam, rad, ``(n,)``; NaN where unknown.
        previous_points: the previous scan's points per beam, NaN rows where unusable.
        layout: the beams of both scans.
        max_shift: largest turn searched, beams.
        association_m: pairs farther apart than this after the coarse turn are unused, m.
        prior: the motion expected (the previous one), or None for no motion.
    """
    ranges = np.hypot(points[:, 0], points[:, 1])
    previous_ranges = np.hypot(previous_points[:, 0], previous_points[:, 1])
    expected = round(prior.theta_rad / layout.increment) if prior is not None else 0
    expected = min(max(expected, -max_shift), max_shift)
    shift = coarse_turn(ranges, previous_ranges, max_shift, layout, expected)
    coarse = Motion(theta_rad=shift * layout.increment)
    q = coarse.apply(layout.shifted(previous_points, shift))
    step = points - q
    # NaN (no return, or a direction-less point) compares False: those beams sit out
    usable = np.hypot(step[:, 0], step[:, 1]) < association_m
    usable &= directions == directions
    rows = indices(usable)
    if rows.size < MIN_PAIRS:
        return coarse
    angle = directions.take(rows)
    normal_x, normal_y = -np.sin(angle), np.cos(angle)
    # rows by take(): fancy indexing of 2-D rows costs several times more
    a, d = q.take(rows, axis=0), step.take(rows, axis=0)
    design = np.empty((rows.size, 3))  # columns written in place (np.stack is slower)
    np.subtract(normal_y * a[:, 0], normal_x * a[:, 1], out=design[:, 0])
    design[:, 1], design[:, 2] = normal_x, normal_y
    target = normal_x * d[:, 0] + normal_y * d[:, 1]
    expected = np.zeros(3)
    if prior is not None:
        expected = np.array([prior.theta_rad - coarse.theta_rad, prior.tx_m, prior.ty_m])
    solution = _solve(design, target, expected)
    # drop the worst fits (occlusion edges, moving things) once, and solve again
    residual = np.abs(design @ solution - target)
    middle = residual.size // 2
    keep = indices(residual <= max(3.0 * float(np.partition(residual, middle)[middle]), 0.01))
    if keep.size >= MIN_PAIRS:
        solution = _solve(design.take(keep, axis=0), target.take(keep), expected)
    d_theta, tx, ty = solution
    return Motion(coarse.theta_rad + d_theta, tx, ty, int(keep.size))


def _solve(design: np.ndarray, target: np.ndarray, expected: np.ndarray) -> tuple[float, ...]:
    """Least squares with the prior's pseudo-observations (normal equations, 3 x 3).

    The prior keeps the matrix positive definite; Cramer's rule on nine floats is cheaper
    than a LAPACK call at this size.
    """
    (a, b, c), (_, e, f), (_, _, i) = (design.T @ design + PRIOR_WEIGHTS).tolist()
    r0, r1, r2 = (design.T @ target + PRIOR_WEIGHTS @ expected).tolist()
    det = a * (e * i - f * f) - b * (b * i - f * c) + c * (b * f - e * c)
    x0 = r0 * (e * i - f * f) - b * (r1 * i - f * r2) + c * (r1 * f - e * r2)
    x1 = a * (r1 * i - f * r2) - r0 * (b * i - f * c) + c * (b * r2 - r1 * c)
    x2 = a * (e * r2 - r1 * f) - b * (b * r2 - r1 * c) + r0 * (b * f - e * c)
    return x0 / det, x1 / det, x2 / det
