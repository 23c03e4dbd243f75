"""Where a ray meets one primitive geom: MuJoCo's own formulas, compiled.

Each function is the intersection MuJoCo 4 computes for its geom type (``mju_rayGeom``
and the functions it calls: plane, sphere, capsule, ellipsoid, cylinder, box), written
operation for operation in the same order, so that the distances and normals are the
same floating-point numbers (the kernels are compiled without fast-math and without
fused multiply-adds, as MuJoCo's library is). :mod:`twsb_sim.raycast` picks the geoms a
ray may hit and calls :func:`ray_geom` on them.

The ray is ``p + x v`` for ``x >= 0``; the distance ``x`` is in units of ``|v|``. Every
function returns ``(x, nx, ny, nz)``: the nearest intersection at ``x >= 0`` and the
unit surface normal there in the world frame, or ``(-1, 0, 0, 0)`` without one. A ray
that starts inside a closed geom meets its surface from the inside (at ``x >= 0``).
Geoms are given by their world pose: ``pos`` (3) and ``mat`` (row-major 3 x 3, local to
world), and ``size`` (3) as in ``model.geom_size``.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from twsb_sim.kernel import kernel

MINVAL = 1e-15  # MuJoCo's mjMINVAL
PLANE = int(mujoco.mjtGeom.mjGEOM_PLANE)
SPHERE = int(mujoco.mjtGeom.mjGEOM_SPHERE)
CAPSULE = int(mujoco.mjtGeom.mjGEOM_CAPSULE)
ELLIPSOID = int(mujoco.mjtGeom.mjGEOM_ELLIPSOID)
CYLINDER = int(mujoco.mjtGeom.mjGEOM_CYLINDER)
BOX = int(mujoco.mjtGeom.mjGEOM_BOX)
SHAPES = (PLANE, SPHERE, CAPSULE, ELLIPSOID, CYLINDER, BOX)  # the types handled here
_MISS = (-1.0, 0.0, 0.0, 0.0)


@kernel
def _local(
    pos: np.ndarray, mat: np.ndarray, p: np.ndarray, v: np.ndarray
) -> tuple[float, float, float, float, float, float]:
    """The ray in the geom's frame: ``mat' (p - pos)`` and ``mat' v``."""
    d0, d1, d2 = p[0] - pos[0], p[1] - pos[1], p[2] - pos[2]
    lp0 = mat[0] * d0 + mat[3] * d1 + mat[6] * d2
    lp1 = mat[1] * d0 + mat[4] * d1 + mat[7] * d2
    lp2 = mat[2] * d0 + mat[5] * d1 + mat[8] * d2
    lv0 = mat[0] * v[0] + mat[3] * v[1] + mat[6] * v[2]
    lv1 = mat[1] * v[0] + mat[4] * v[1] + mat[7] * v[2]
    lv2 = mat[2] * v[0] + mat[5] * v[1] + mat[8] * v[2]
    return lp0, lp1, lp2, lv0, lv1, lv2


@kernel
def _world_normal(mat: np.ndarray, n0: float, n1: float, n2: float) -> tuple[float, float, float]:
    """A local vector normalised as ``mju_normalize3`` does, then turned into the world."""
    norm = math.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
    if norm < MINVAL:
        n0, n1, n2 = 1.0, 0.0, 0.0
    else:
        inv = 1 / norm
        n0, n1, n2 = n0 * inv, n1 * inv, n2 * inv
    return _rotate(mat, n0, n1, n2)


@kernel
def _rotate(mat: np.ndarray, n0: float, n1: float, n2: float) -> tuple[float, float, float]:
    """``mat n`` (``mju_mulMatVec3``)."""
    return (
        mat[0] * n0 + mat[1] * n1 + mat[2] * n2,
        mat[3] * n0 + mat[4] * n1 + mat[5] * n2,
        mat[6] * n0 + mat[7] * n1 + mat[8] * n2,
    )


@kernel
def _quad(a: float, b: float, c: float) -> tuple[float, float, float]:
    """Roots of ``a x^2 + 2 b x + c = 0``: (smallest non-negative or -1, x0, x1)."""
    det = b * b - a * c
    if det < 0 or a < MINVAL:
        return -1.0, -1.0, -1.0
    det = math.sqrt(det)
    x0 = (-b - det) / a
    x1 = (-b + det) / a
    if x0 >= 0:
        return x0, x0, x1
    if x1 >= 0:
        return x1, x0, x1
    return -1.0, x0, x1


@kernel
def sphere_distance(pos: np.ndarray, dist_sqr: float, p: np.ndarray, v: np.ndarray) -> float:
    """Distance to a sphere of squared radius ``dist_sqr`` (also MuJoCo's bounding test)."""
    d0, d1, d2 = p[0] - pos[0], p[1] - pos[1], p[2] - pos[2]
    a = v[0] * v[0] + v[1] * v[1] + v[2] * v[2]
    b = v[0] * d0 + v[1] * d1 + v[2] * d2
    c = d0 * d0 + d1 * d1 + d2 * d2 - dist_sqr
    return _quad(a, b, c)[0]


@kernel
def _plane(
    pos: np.ndarray, mat: np.ndarray, size: np.ndarray, p: np.ndarray, v: np.ndarray
) -> tuple[float, float, float, float]:
    lp0, lp1, lp2, lv0, lv1, lv2 = _local(pos, mat, p, v)
    if lv2 > -MINVAL:  # not towards the front face
        return _MISS
    x = -lp2 / lv2
    if x < 0:
        return _MISS
    p0 = lp0 + x * lv0
    p1 = lp1 + x * lv1
    if (size[0] <= 0 or abs(p0) <= size[0]) and (size[1] <= 0 or abs(p1) <= size[1]):
        return x, mat[2], mat[5], mat[8]
    return _MISS


@kernel
def _sphere(
    pos: np.ndarray, size: np.ndarray, p: np.ndarray, v: np.ndarray
) -> tuple[float, float, float, float]:
    x = sphere_distance(pos, size[0] * size[0], p, v)
    if x < 0:
        return _MISS
    n0 = (p[0] + x * v[0]) - pos[0]
    n1 = (p[1] + x * v[1]) - pos[1]
    n2 = (p[2] + x * v[2]) - pos[2]
    norm = math.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
    if norm < MINVAL:
        return x, 1.0, 0.0, 0.0
    inv = 1 / norm
    return x, n0 * inv, n1 * inv, n2 * inv


@kernel
def _capsule(
    pos: np.ndarray, mat: np.ndarray, size: np.ndarray, p: np.ndarray, v: np.ndarray
) -> tuple[float, float, float, float]:
    ssz = size[0] + size[1]
    if sphere_distance(pos, ssz * ssz, p, v) < 0:
        return _MISS
    lp0, lp1, lp2, lv0, lv1, lv2 = _local(pos, mat, p, v)
    x, kind = -1.0, 0  # kind: -1 bottom cap, 0 side, 1 top cap
    a = lv0 * lv0 + lv1 * lv1
    b = lv0 * lp0 + lv1 * lp1
    c = lp0 * lp0 + lp1 * lp1 - size[0] * size[0]
    sol = _quad(a, b, c)[0]
    if sol >= 0 and abs(lp2 + sol * lv2) <= size[1]:
        x, kind = sol, 0
    a = lv0 * lv0 + lv1 * lv1 + lv2 * lv2
    for cap in (1, -1):
        ld2 = lp2 - size[1] if cap == 1 else lp2 + size[1]
        b = lv0 * lp0 + lv1 * lp1 + lv2 * ld2
        c = lp0 * lp0 + lp1 * lp1 + ld2 * ld2 - size[0] * size[0]
        _, x0, x1 = _quad(a, b, c)
        for root in (x0, x1):
            z = lp2 + root * lv2
            on_cap = z >= size[1] if cap == 1 else z <= -size[1]
            if root >= 0 and on_cap and (x < 0 or root < x):
                x, kind = root, cap
    if x < 0:
        return _MISS
    n2 = 0.0 if kind == 0 else lp2 + lv2 * x - size[1] * kind
    n = _world_normal(mat, lp0 + lv0 * x, lp1 + lv1 * x, n2)
    return x, n[0], n[1], n[2]


@kernel
def _ellipsoid(
    pos: np.ndarray, mat: np.ndarray, size: np.ndarray, p: np.ndarray, v: np.ndarray
) -> tuple[float, float, float, float]:
    lp0, lp1, lp2, lv0, lv1, lv2 = _local(pos, mat, p, v)
    s0, s1, s2 = 1 / (size[0] * size[0]), 1 / (size[1] * size[1]), 1 / (size[2] * size[2])
    a = s0 * lv0 * lv0 + s1 * lv1 * lv1 + s2 * lv2 * lv2
    b = s0 * lv0 * lp0 + s1 * lv1 * lp1 + s2 * lv2 * lp2
    c = s0 * lp0 * lp0 + s1 * lp1 * lp1 + s2 * lp2 * lp2 - 1
    x = _quad(a, b, c)[0]
    if x < 0:
        return _MISS
    n = _world_normal(mat, s0 * (lp0 + x * lv0), s1 * (lp1 + x * lv1), s2 * (lp2 + x * lv2))
    return x, n[0], n[1], n[2]


@kernel
def _cylinder(
    pos: np.ndarray, mat: np.ndarray, size: np.ndarray, p: np.ndarray, v: np.ndarray
) -> tuple[float, float, float, float]:
    if sphere_distance(pos, size[0] * size[0] + size[1] * size[1], p, v) < 0:
        return _MISS
    lp0, lp1, lp2, lv0, lv1, lv2 = _local(pos, mat, p, v)
    x, kind = -1.0, 0  # kind: -1 bottom, 0 round side, 1 top
    if abs(lv2) > MINVAL:
        for side in (-1, 1):
            sol = (side * size[1] - lp2) / lv2
            if sol >= 0:
                p0 = lp0 + sol * lv0
                p1 = lp1 + sol * lv1
                if p0 * p0 + p1 * p1 <= size[0] * size[0] and (x < 0 or sol < x):
                    x, kind = sol, side
    a = lv0 * lv0 + lv1 * lv1
    b = lv0 * lp0 + lv1 * lp1
    c = lp0 * lp0 + lp1 * lp1 - size[0] * size[0]
    sol = _quad(a, b, c)[0]
    if sol >= 0 and abs(lp2 + sol * lv2) <= size[1] and (x < 0 or sol < x):
        x, kind = sol, 0
    if x < 0:
        return _MISS
    if kind == 0:
        n = _world_normal(mat, lp0 + lv0 * x, lp1 + lv1 * x, 0.0)
    else:
        n = _rotate(mat, 0.0, 0.0, float(kind))
    return x, n[0], n[1], n[2]


@kernel
def _box(
    pos: np.ndarray, mat: np.ndarray, size: np.ndarray, p: np.ndarray, v: np.ndarray
) -> tuple[float, float, float, float]:
    if sphere_distance(pos, size[0] * size[0] + size[1] * size[1] + size[2] * size[2], p, v) < 0:
        return _MISS
    lp = _local(pos, mat, p, v)
    x, axis, face = -1.0, -1, 0
    for i in range(3):
        lpi, lvi = lp[i], lp[3 + i]
        if abs(lvi) > MINVAL:
            j, k = (1, 2) if i == 0 else ((0, 2) if i == 1 else (0, 1))
            for side in (-1, 1):
                sol = (side * size[i] - lpi) / lvi
                if sol >= 0:
                    p0 = lp[j] + sol * lp[3 + j]
                    p1 = lp[k] + sol * lp[3 + k]
                    inside = abs(p0) <= size[j] and abs(p1) <= size[k]
                    if inside and (x < 0 or sol < x):
                        x, axis, face = sol, i, side
    if x < 0:
        return _MISS
    side = float(face)
    n = _rotate(
        mat, side if axis == 0 else 0.0, side if axis == 1 else 0.0, side if axis == 2 else 0.0
    )
    return x, n[0], n[1], n[2]


@kernel
def ray_geom(
    kind: int, pos: np.ndarray, mat: np.ndarray, size: np.ndarray, p: np.ndarray, v: np.ndarray
) -> tuple[float, float, float, float]:
    """``(x, nx, ny, nz)`` of the ray ``p + x v`` on a geom of type ``kind`` (one of
    ``SHAPES``), as ``mju_rayGeom`` computes them; ``(-1, 0, 0, 0)`` without a hit."""
    if kind == BOX:
        return _box(pos, mat, size, p, v)
    if kind == CYLINDER:
        return _cylinder(pos, mat, size, p, v)
    if kind == PLANE:
        return _plane(pos, mat, size, p, v)
    if kind == SPHERE:
        return _sphere(pos, size, p, v)
    if kind == CAPSULE:
        return _capsule(pos, mat, size, p, v)
    if kind == ELLIPSOID:
        return _ellipsoid(pos, mat, size, p, v)
    return _MISS
