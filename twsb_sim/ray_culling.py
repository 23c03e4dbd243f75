"""Which geoms a ray from the origin of a cast may hit, found without testing them all.

A 2D LiDAR casts a fan of rays from one point; each ray can only hit geoms in its own
direction. Per cast, :func:`index_geoms` gives each geom a bounding box in world axes
(from its pose and its local extents) and the span of azimuths it covers as seen from
the origin, and files the geoms by azimuth sector, nearest first. Per ray,
:func:`cast_rays` walks only its sector's geoms, tests each one's box first (a slab
test, a few operations), MuJoCo's intersection (:func:`~twsb_sim.ray_shapes.ray_geom`)
only when the box is hit, and stops at the first geom whose box lies beyond the best hit
found. A ray's hit point has the ray's own azimuth, so a geom whose azimuth span misses
it cannot be hit; every test is widened by ``SLACK_M`` (``SLACK_TURN`` for azimuths), far
above the rounding of the numbers tested, so no geom the ray meets is ever skipped.
Azimuths are compared as pseudo-angles (:func:`_pseudo_angle`), which order directions
as their angles do, without the cost of ``atan2``.
A plane is a rectangle of no thickness for MuJoCo's rays (unbounded along an axis whose
size is 0); unbounded planes, and geoms above or below the origin, are in every sector.
"""

from __future__ import annotations

import math

import numpy as np

from twsb_sim.kernel import kernel
from twsb_sim.ray_shapes import MINVAL, ray_geom

SECTORS = 64  # azimuth sectors per cast
SLACK_M = 1e-6  # m, widening of every box and distance test
SLACK_TURN = 1e-9  # widening of every azimuth span, in pseudo-angle (1 = a quarter turn)


@kernel
def _pseudo_angle(x: float, y: float) -> float:
    """The direction of ``(x, y)`` as a number in [0, 4) that grows with its azimuth
    (the "diamond angle": a quarter turn per unit), without a call to ``atan2``; 0 for
    ``(0, 0)``."""
    if y >= 0:
        if x >= 0:
            return y / (x + y) if x + y > 0 else 0.0
        return 1 - x / (y - x)
    if x < 0:
        return 2 - y / (-x - y)
    return 3 + x / (x - y)


@kernel
def _sector(turns: float) -> int:
    """The sector of a pseudo-angle (any multiple of 4 off)."""
    return math.floor(turns * (SECTORS / 4)) % SECTORS


@kernel
def _sorted_by(keys: np.ndarray) -> np.ndarray:
    """The order of ``keys``, smallest first (a Shell sort: a few hundred keys, and far
    less machine code to compile than ``np.argsort``'s)."""
    count = len(keys)
    order = np.arange(count)
    gap = 1
    while gap < count // 3:
        gap = 3 * gap + 1
    while gap > 0:
        for i in range(gap, count):
            item, key = order[i], keys[order[i]]
            j = i
            while j >= gap and keys[order[j - gap]] > key:
                order[j] = order[j - gap]
                j -= gap
            order[j] = item
        gap //= 3
    return order


@kernel
def index_geoms(
    origin: np.ndarray,
    extents: np.ndarray,
    cut: np.ndarray,
    rbound: np.ndarray,
    geoms: np.ndarray,
    xpos: np.ndarray,
    xmat: np.ndarray,
    cutoff: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The geoms of a cast filed by azimuth sector, nearest first.

    Args:
        origin: (3,) where the rays start (m).
        extents: (m, 3) each candidate geom's half extents along its own axes (m); inf
            along an unbounded plane.
        cut, rbound: whether ``mj_multiRay``'s cutoff applies to the geom, and its
            ``geom_rbound`` (m).
        geoms: (m,) the candidates' geom ids.
        xpos, xmat: ``data.geom_xpos`` and ``data.geom_xmat``.
        cutoff: ``mj_multiRay``'s cutoff (m).

    Returns:
        ``order`` (k,) candidate indices by nearest distance, ``near`` (k,) that distance
        less the slack (m), ``low`` and ``high`` (k, 3) each box's corners relative to the
        origin, widened by the slack (m; infinite for planes), ``start`` (SECTORS + 1,)
        and ``items``: sector ``s`` holds positions ``items[start[s]:start[s + 1]]`` of
        ``order``, in order.
    """
    m = len(geoms)
    keep = np.empty(m, np.int64)
    near = np.empty(m)
    low = np.empty((m, 3))
    high = np.empty((m, 3))
    count = 0
    for k in range(m):
        g = geoms[k]
        c0, c1, c2 = xpos[g, 0] - origin[0], xpos[g, 1] - origin[1], xpos[g, 2] - origin[2]
        if cut[k] and rbound[k] > 0:  # mj_multiRay leaves out geoms beyond the cutoff
            if math.sqrt(c0 * c0 + c1 * c1 + c2 * c2) > cutoff + rbound[k]:
                continue
        gap = 0.0
        for i in range(3):
            half = SLACK_M
            for j in range(3):
                turn = abs(xmat[g, 3 * i + j])
                if turn != 0:  # an unbounded plane's extent is inf, and 0 inf is nan
                    half += turn * extents[k, j]
            centre = xpos[g, i] - origin[i]
            low[count, i] = centre - half
            high[count, i] = centre + half
            outside = abs(centre) - half
            if outside > 0:
                gap += outside * outside
        keep[count] = k
        near[count] = math.sqrt(gap) - SLACK_M
        count += 1
    by_near = _sorted_by(near[:count])
    order = np.empty(count, np.int64)
    near_sorted = np.empty(count)
    low_sorted = np.empty((count, 3))
    high_sorted = np.empty((count, 3))
    for j in range(count):
        i = by_near[j]
        order[j], near_sorted[j] = keep[i], near[i]
        low_sorted[j], high_sorted[j] = low[i], high[i]
    near, low, high = near_sorted, low_sorted, high_sorted

    first = np.empty(count, np.int64)  # each geom's sector span, first to last (unwrapped)
    last = np.empty(count, np.int64)
    for j in range(count):
        x0, y0, x1, y1 = low[j, 0], low[j, 1], high[j, 0], high[j, 1]
        if (x0 <= 0 <= x1 and y0 <= 0 <= y1) or not math.isfinite(x1 - x0):
            first[j], last[j] = 0, SECTORS - 1  # around the origin, or unbounded: all
            continue
        centre = _pseudo_angle(0.5 * (x0 + x1), 0.5 * (y0 + y1))
        lo, hi = math.inf, -math.inf
        for cx, cy in ((x0, y0), (x0, y1), (x1, y0), (x1, y1)):
            turn = _pseudo_angle(cx, cy) - centre  # the box spans less than half a turn
            turn -= 4 * math.floor((turn + 2) / 4)  # into [-2, 2)
            lo, hi = min(lo, turn), max(hi, turn)
        a = math.floor((centre + lo - SLACK_TURN) * (SECTORS / 4))
        b = math.floor((centre + hi + SLACK_TURN) * (SECTORS / 4))
        first[j], last[j] = a, min(b, a + SECTORS - 1)
    start = np.zeros(SECTORS + 1, np.int64)
    for j in range(count):
        for s in range(first[j], last[j] + 1):
            start[s % SECTORS + 1] += 1
    for s in range(SECTORS):
        start[s + 1] += start[s]
    fill = start[:-1].copy()
    items = np.empty(start[SECTORS], np.int64)
    for j in range(count):  # nearest first, so each sector's list is in order too
        for s in range(first[j], last[j] + 1):
            items[fill[s % SECTORS]] = j
            fill[s % SECTORS] += 1
    return order, near, low, high, start, items


@kernel
def _box_entry(low: np.ndarray, high: np.ndarray, j: int, u: tuple, inv: tuple) -> float:
    """Where a ray from the origin enters box ``j`` (m from the origin), or -1 if it misses
    it; ``u`` is the ray's direction, ``inv`` its length over each component (0 where
    the component is 0)."""
    enter, leave = 0.0, math.inf
    for i in range(3):
        if u[i] == 0.0:
            if low[j, i] > 0 or high[j, i] < 0:
                return -1.0
            continue
        t0, t1 = low[j, i] * inv[i], high[j, i] * inv[i]
        if t0 > t1:
            t0, t1 = t1, t0
        enter, leave = max(enter, t0), min(leave, t1)
    return enter if enter <= leave else -1.0


@kernel
def cast_rays(
    origin: np.ndarray,
    vec: np.ndarray,
    geoms: np.ndarray,
    types: np.ndarray,
    sizes: np.ndarray,
    extents: np.ndarray,
    cut: np.ndarray,
    rbound: np.ndarray,
    xpos: np.ndarray,
    xmat: np.ndarray,
    cutoff: float,
    geom_ids: np.ndarray,
    distances: np.ndarray,
    normals: np.ndarray,
) -> None:
    """Every ray's nearest hit (see the module): one compiled call per cast.

    Args:
        origin, vec: (3,) where the rays start; (n, 3) their directions.
        geoms, types, sizes: (m,) the geoms rays can see, their types; (m, 3) their
            ``geom_size``.
        extents, cut, rbound, xpos, xmat, cutoff: as :func:`index_geoms` takes them.
        geom_ids, distances, normals: (n,), (n,) and (3 n,) out: the geom hit, its
            distance in units of the ray's length, the unit surface normal there.

    Among equal distances the lowest geom id wins, as in MuJoCo's loop over the geoms. A
    ray without a hit (or of length below MuJoCo's minimum) gets geom -1, distance -1
    and a zero normal.
    """
    index = index_geoms(origin, extents, cut, rbound, geoms, xpos, xmat, cutoff)
    order, near, low, high, start, items = index
    for r in range(len(distances)):
        v = vec[r]
        vv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2]
        best, best_geom, best_m = -1.0, -1, math.inf
        n0 = n1 = n2 = 0.0
        if vv >= MINVAL:
            length = math.sqrt(vv)
            u = (v[0], v[1], v[2])  # only its zeros and, through inv, its direction count
            inv = (length / u[0] if u[0] != 0.0 else 0.0, length / u[1] if u[1] != 0.0 else 0.0,
                   length / u[2] if u[2] != 0.0 else 0.0)  # fmt: skip
            s = _sector(_pseudo_angle(v[0], v[1]))
            for e in range(start[s], start[s + 1]):
                j = items[e]
                if near[j] > best_m:
                    break  # this geom and all after it lie beyond the best hit
                enter = _box_entry(low, high, j, u, inv)
                if enter < 0 or enter > best_m + SLACK_M:
                    continue
                k = order[j]
                g = geoms[k]
                x, h0, h1, h2 = ray_geom(types[k], xpos[g], xmat[g], sizes[k], origin, v)
                if x >= 0 and (best < 0 or x < best or (x == best and g < best_geom)):
                    best, best_geom, best_m = x, g, x * length
                    n0, n1, n2 = h0, h1, h2
        distances[r] = best
        geom_ids[r] = best_geom
        normals[3 * r] = n0
        normals[3 * r + 1] = n1
        normals[3 * r + 2] = n2
