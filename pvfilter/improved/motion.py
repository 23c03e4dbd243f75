"""Ego-motion: how the sensor moved since the reference scan, from the scans and a prior.

The level-view memory (:mod:`pvfilter.improved.memory`) must follow the sensor as it
turns and drives, or every turn makes the world look new. The motion comes from the two
scans in two steps, both cheap on 720 beams:

1. **Turn, to the nearest beam**: the reference ranges shifted by ``s`` beams are
   compared with the current ones (sum of the clipped absolute differences), first for
   every shift near the prior's turn on every other beam, and only if that fails for
   every shift the fastest turn allows on every fourth beam.
2. **Fine turn and translation**: a point-to-line least-squares step, solved twice with
   the worst residuals dropped in between. Beam ``i`` of the current scan (point ``p``,
   local line normal ``n``) and the reference point the coarse turn puts on it (``q``) lie
   on the same surface, so ``n . (R(d_theta) q + t - p) = 0``, linear in
   ``(d_theta, t)``. The prior enters as pseudo-observations with its spread: wheel
   odometry when the robot gives it (slip makes its spread grow with the step), else the
   previous motion (constant velocity), which decides what the scans do not constrain
   (along a corridor, or while floor lines hide the walls ahead).

Convention: a static point at ``q`` in the reference sensor frame is at ``R(theta) q + t``
in the current one. The caller leaves out beams that may be pitch variation; pairs
farther apart than ``association_m`` after the coarse turn take no part.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from pvfilter.improved.beams import BeamLayout, indices

MIN_PAIRS = 20  # fewer usable beam pairs: the fit is not trusted (the prior stands)
CLIP_M = 0.5  # m: range differences are clipped here in the coarse search
NEAR_SHIFTS = 3  # beams: the turn is first sought this close to the prior's
ROW_NOISE_M = 0.02  # m: the spread of one point-to-line row (range noise, line fit)


@dataclasses.dataclass(frozen=True)
class Motion:
    """The sensor's motion between two scans (see the module docstring for the convention).

    Attributes:
        theta_rad: rotation, rad.
        tx_m: translation along the current x axis, m.
        ty_m: translation along the current y axis, m.
        pairs: beam pairs used in the fine step (0: no fit).
        residual_m: median absolute point-to-line residual of the fit, m (NaN: no fit).
        weak_rows: the fit's support along its least constrained direction of
            translation, in point-to-line rows (the squared shares of their normals
            along it, the turn taken out; inf: no fit). Walls all parallel (a corridor,
            or what a pitched plane still meets) leave the drive along them to a few
            rows of clutter and the prior.
        weak_axis_rad: that direction in the current sensor frame, rad (mod pi).
    """

    theta_rad: float = 0.0
    tx_m: float = 0.0
    ty_m: float = 0.0
    pairs: int = 0
    residual_m: float = math.nan
    weak_rows: float = math.inf
    weak_axis_rad: float = 0.0

    def apply(self, points: np.ndarray) -> np.ndarray:
        """Points of the reference sensor frame in the current one, m, ``(k, 2)``."""
        c, s = math.cos(self.theta_rad), math.sin(self.theta_rad)
        # a matrix product, not x c - y s by hand: BLAS fuses multiply and add (dot: the
        # same BLAS call as @, without the matmul ufunc's layers)
        moved = points.dot(np.array([[c, s], [-s, c]]))
        # the translation added to each row as one complex number x + iy: complex addition
        # is the two float additions, in one pass over the rows (two strided passes, or a
        # pair broadcast over the rows, cost twice as much)
        as_complex = moved.view(np.complex128)
        as_complex += complex(self.tx_m, self.ty_m)
        return moved

    def then(self, after: Motion) -> Motion:
        """This motion followed by ``after`` (frames a -> b -> c)."""
        c, s = math.cos(after.theta_rad), math.sin(after.theta_rad)
        return motion_of(
            self.theta_rad + after.theta_rad,
            c * self.tx_m - s * self.ty_m + after.tx_m,
            s * self.tx_m + c * self.ty_m + after.ty_m,
        )

    def inverse(self) -> Motion:
        """The motion back (frames b -> a)."""
        c, s = math.cos(self.theta_rad), math.sin(self.theta_rad)
        return motion_of(
            -self.theta_rad, -(c * self.tx_m + s * self.ty_m), s * self.tx_m - c * self.ty_m
        )

    def scaled(self, factor: float) -> Motion:
        """The same rate of motion over ``factor`` times the time (constant velocity)."""
        return motion_of(self.theta_rad * factor, self.tx_m * factor, self.ty_m * factor)

    @property
    def translation_m(self) -> float:
        """Length of the translation, m."""
        return math.hypot(self.tx_m, self.ty_m)


STILL = Motion()  # no motion (a Motion is immutable: one serves everywhere)


def motion_of(
    theta_rad: float, tx_m: float, ty_m: float, pairs: int = 0, residual_m: float = math.nan
) -> Motion:
    """``Motion(theta_rad, tx_m, ty_m, pairs, residual_m)``, made at half the cost.

    A frozen dataclass sets each field through ``object.__setattr__``; a scan makes a
    dozen motions (composed, inverted, scaled), so they are made by filling the new
    object's ``__dict__`` directly: the same object, as ``==``, ``repr`` and pickling see it.
    """
    motion = object.__new__(Motion)
    fields = motion.__dict__
    fields["theta_rad"], fields["tx_m"], fields["ty_m"] = theta_rad, tx_m, ty_m
    fields["pairs"], fields["residual_m"] = pairs, residual_m
    return motion


def odometry_motion(previous: np.ndarray, current: np.ndarray) -> Motion:
    """The motion between two odometry poses of the sensor ``(x, y, yaw)`` (REP-105).

    The turn is the yaw difference wrapped to ``[-pi, pi]``: odometry reports yaw wrapped
    (ROS to ``(-pi, pi]``), so a robot turning through pi would otherwise read a turn
    of nearly a whole revolution, which points the scan match's turn search a full
    revolution off (and a beam shift past every beam of the scan).
    """
    dx, dy = previous[0] - current[0], previous[1] - current[1]
    c, s = math.cos(current[2]), math.sin(current[2])
    turn = math.remainder(previous[2] - current[2], math.tau)
    return Motion(turn, c * dx + s * dy, -s * dx + c * dy)


def coarse_turn(
    ranges: np.ndarray, previous: np.ndarray, max_shift: int, layout: BeamLayout, expected: int
) -> int:
    """The beam shift of ``previous`` that best matches ``ranges`` (NaN: not compared).

    The shifts next to the ``expected`` one are tried first on every other beam; only when
    the best of them is at the edge of that window are all shifts up to ``max_shift``
    tried, on every fourth beam.
    """
    best = _best_shift(ranges, previous, expected - NEAR_SHIFTS, 2 * NEAR_SHIFTS + 1, layout, 2)
    if abs(best - expected) < NEAR_SHIFTS:
        return best
    best = _best_shift(ranges, previous, -max_shift, 2 * max_shift + 1, layout, 4)
    return _best_shift(ranges, previous, best - 2, 5, layout, 1)


def _best_shift(
    ranges: np.ndarray,
    previous: np.ndarray,
    first: int,
    count: int,
    layout: BeamLayout,
    stride: int,
) -> int:
    """Of the shifts ``first .. first + count - 1``, the one with the least clipped range
    difference over every ``stride``-th beam."""
    _, source = layout.shift_table(first, count, stride)
    values = previous if layout.ring else np.concatenate((previous, [np.nan]))  # -1: outside, NaN
    cost = values.take(source)
    cost -= ranges[::stride]  # beams 0, stride, 2 stride, ...: the table's, as a view
    np.fmin(np.abs(cost, out=cost), CLIP_M, out=cost)
    return first + int(np.add.reduce(cost, axis=1).argmin())  # ties: the lowest shift


def prior_weights(spread: tuple[float, float]) -> tuple[float, float]:
    """Pseudo-observation weights of a prior with spreads (turn rad, translation m): the
    diagonal of the weight matrix, (turn, translation; the same for x and y)."""
    turn = ROW_NOISE_M / max(spread[0], 1e-4)
    shift = ROW_NOISE_M / max(spread[1], 1e-3)
    return turn * turn, shift * shift


def estimate_motion(
    points: np.ndarray,
    directions: np.ndarray,
    reference_points: np.ndarray,
    layout: BeamLayout,
    shift: int,
    association_m: float,
    prior: Motion,
    spread: tuple[float, float],
) -> Motion:
    """The sensor's motion from the reference scan to this one, refined from a coarse turn.

    Args:
        points: this scan's points per beam, sensor frame, m, ``(n, 2)``; NaN rows where
            the beam has no usable return.
        directions: local line direction per beam, rad, ``(n,)``, within (-pi/2, pi/2] (the
            normals' cosine is worked out from their sine); NaN where unknown.
        reference_points: the reference scan's points per beam, NaN rows where unusable.
        layout: the beams of both scans.
        shift: the coarse turn, beams (:func:`coarse_turn`).
        association_m: pairs farther apart than this after the coarse turn are unused, m.
        prior: the motion expected (odometry, or the previous motion at constant velocity).
        spread: the prior's spread: (turn, rad; translation, m).

    Returns:
        The motion; ``pairs`` 0 and the prior itself when too few pairs were usable.
    """
    # the coarse turn from the ranges; the translation from the prior, so that the pairs
    # are found where the prior puts the reference points
    coarse = motion_of(shift * layout.increment, prior.tx_m, prior.ty_m)
    q = coarse.apply(layout.shifted(reference_points, shift))
    step = points - q
    # NaN (no return, or a direction-less point) compares False: those beams sit out
    usable = nearer_than(step[:, 0], step[:, 1], association_m)
    usable &= directions == directions
    rows = indices(usable)
    if rows.size < MIN_PAIRS:
        return prior
    angle = directions.take(rows)
    # the line normals (-sin, cos), their sign folded into the sums below (a float's
    # negation is exact: x - (-y) is x + y), so no negated copy is made. The directions
    # lie in (-pi/2, pi/2], where the cosine is sqrt(1 - sin^2): it errs by at most 1.1e-8
    # (near +-pi/2, from the sine's rounding), a point-to-line row by 1.1e-7 m at 10 m, for
    # half the cost of np.cos
    sine = np.sin(angle)
    cosine = np.sqrt(1.0 - sine * sine)
    a, d = q.take(rows, axis=0), step.take(rows, axis=0)
    design = np.empty((rows.size, 3))  # columns written in place (np.stack is slower)
    np.add(cosine * a[:, 0], sine * a[:, 1], out=design[:, 0])
    np.negative(sine, out=design[:, 1])
    design[:, 2] = cosine
    target = cosine * d[:, 1] - sine * d[:, 0]
    weights = prior_weights(spread)
    expected_turn = prior.theta_rad - coarse.theta_rad  # the prior's change (turn only)
    solution = _solve(design, target, expected_turn, weights)
    # drop the worst fits (occlusion edges, moving things) once, and solve again
    residual = _residuals(design, solution, target)
    keep = indices(residual <= max(3.0 * _median(residual), 0.01))
    if keep.size < MIN_PAIRS:
        return prior
    design, target = design.take(keep, axis=0), target.take(keep)
    normal = design.T.dot(design).tolist()  # (once: the solve and the weak direction)
    solution = _solve(design, target, expected_turn, weights, normal)
    median = _median(_residuals(design, solution, target), scratch=True)
    motion = coarse.then(motion_of(*solution))
    fields = motion.__dict__  # (a Motion of its own, just made: see motion_of)
    fields["pairs"], fields["residual_m"] = int(keep.size), median
    fields["weak_rows"], fields["weak_axis_rad"], _ = weak_direction(normal)
    return motion


def weak_direction(normal: list[list[float]]) -> tuple[float, float, float]:
    """The least constrained direction of translation of a point-to-line fit: the smaller
    eigenvalue of its translation's information with the turn taken out (the Schur
    complement of the normal equations), in rows, its direction, rad (mod pi), and the
    larger eigenvalue (the support across it), in rows.

    Args:
        normal: the fit's normal matrix ``design^T design`` as nested lists, its rows
            ``(n x p - n y q..., n_x, n_y)``.
    """
    (a, b, c), (_, e, f), (_, _, i) = normal
    if a > 0.0:  # the turn's share taken out: a turn can explain part of a shift
        e, f, i = e - b * b / a, f - b * c / a, i - c * c / a
    half_sum, half_diff = 0.5 * (e + i), 0.5 * (e - i)
    spread = math.hypot(half_diff, f)
    # the strong axis lies at atan2(2 f, e - i) / 2; the weak one across it
    axis = 0.5 * math.atan2(2.0 * f, e - i) + 0.5 * math.pi
    return max(half_sum - spread, 0.0), axis, half_sum + spread


def _residuals(design: np.ndarray, solution: tuple[float, ...], target: np.ndarray) -> np.ndarray:
    """Absolute point-to-line residuals of a solution, m."""
    residual = design.dot(solution)  # design @ solution (the same BLAS call, fewer layers)
    residual -= target
    return np.abs(residual, out=residual)


def _median(values: np.ndarray, scratch: bool = False) -> float:
    """The upper median of ``values`` (the middle element when sorted); ``scratch``:
    ``values`` may be reordered (else a copy is, as ``np.partition`` does)."""
    middle = values.size // 2
    part = values if scratch else values.copy()
    part.partition(middle)
    return float(part[middle])


def nearer_than(x: np.ndarray, y: np.ndarray, limit: float) -> np.ndarray:
    """Per point: ``np.hypot(x, y) < limit``, decided the same for every point.

    The squared distance errs by under 3e-16 of itself and ``hypot`` by under an ulp, so a
    squared distance more than a 1e-9 share away from ``limit**2`` decides the same as
    ``hypot`` would, for a fraction of its cost; the few nearer the limit get ``hypot``
    itself. NaN and infinite points compare False both ways. Limits so extreme that the
    squares over- or underflow take ``hypot`` for every point.
    """
    if not 1e-100 < limit < 1e100:
        return np.hypot(x, y) < limit
    squared = x * x
    squared += y * y
    near = squared < (limit * (1.0 - 1e-9)) ** 2
    unsure = indices((squared <= (limit * (1.0 + 1e-9)) ** 2) ^ near)
    if unsure.size:
        near[unsure] = np.hypot(x.take(unsure), y.take(unsure)) < limit
    return near


def _solve(
    design: np.ndarray,
    target: np.ndarray,
    expected_turn: float,
    weights: tuple[float, float],
    normal: list[list[float]] | None = None,
) -> tuple[float, ...]:
    """Least squares with the prior's pseudo-observations (normal equations, 3 x 3).

    The prior keeps the matrix positive definite; Cramer's rule on nine floats is cheaper
    than a LAPACK call at this size. The prior's weights are diagonal and only its turn
    is non-zero: they are added as floats (``+ 0.0`` where the weight matrix adds a zero,
    which turns a -0.0 into 0.0 as the matrix sum did), not as 3 x 3 arrays. ``normal``:
    ``design^T design`` as nested lists, where the caller has it already.
    """
    w_turn, w_shift = weights
    # dot: the same BLAS calls as @ (syrk, gemv), without the matmul ufunc's layers
    if normal is None:
        normal = design.T.dot(design).tolist()
    (a, b, c), (_, e, f), (_, _, i) = normal
    a, b, c, e, f, i = a + w_turn, b + 0.0, c + 0.0, e + w_shift, f + 0.0, i + w_shift
    r0, r1, r2 = design.T.dot(target).tolist()
    r0, r1, r2 = r0 + (w_turn * expected_turn + 0.0), r1 + 0.0, r2 + 0.0
    det = a * (e * i - f * f) - b * (b * i - f * c) + c * (b * f - e * c)
    x0 = r0 * (e * i - f * f) - b * (r1 * i - f * r2) + c * (r1 * f - e * r2)
    x1 = a * (r1 * i - f * r2) - r0 * (b * i - f * c) + c * (b * r2 - r1 * c)
    x2 = a * (e * r2 - r1 * f) - b * (b * r2 - r1 * c) + r0 * (b * f - e * c)
    return x0 / det, x1 / det, x2 / det
