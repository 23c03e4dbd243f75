"""From a ray cast to a scan: labels, reading errors, REP-117 encoding, all beams in order.

One compiled pass (:mod:`twsb_sim.kernel`) over the useful beams of a cast does what a
frame needs of them; it replaced about forty numpy calls per scan, and gives the same
numbers to the bit. :class:`~twsb_sim.lidar.Lidar` prepares the arguments once.
"""

from __future__ import annotations

import numpy as np

from twsb_sim.kernel import kernel
from twsb_sim.labels import BeamLabel
from twsb_sim.sensors.lidar_errors import dropped, mix_edges, noisy, quantised

_STATIC, _HORIZONTAL = int(BeamLabel.STATIC), int(BeamLabel.HORIZONTAL)
_OCCLUDED = int(BeamLabel.OCCLUDED)
# the scanner's numbers, in this order, in ``read_beams``'s ``params``
PARAMS = (
    "range_min_m",
    "range_max_m",
    "dropout_probability",
    "cos_grazing_start",  # cosine of grazing_dropout_start_deg
    "horizontal_normal_min_z",
    "range_noise_std_m",
    "range_noise_fraction",
    "mixed_pixel_probability",
    "mixed_pixel_min_jump_m",
    "range_resolution_m",
)


@kernel
def read_beams(
    distance_m: np.ndarray,
    geom_ids: np.ndarray,
    normals: np.ndarray,
    along: np.ndarray,
    normal_draws: np.ndarray,
    uniforms: np.ndarray,
    label_by_geom: np.ndarray,
    adjacent: np.ndarray,
    origins: np.ndarray,
    dirs: np.ndarray,
    useful_beams: np.ndarray,
    num_beams: int,
    params: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Every beam's range, label, hit point and geom id from a cast of the useful beams.

    Labels come from the noiseless hit: the class of the geom hit (``label_by_geom``, its
    last entry for no hit), HORIZONTAL for a STATIC one whose normal is steep enough. The
    errors (:mod:`twsb_sim.sensors.lidar_errors`) change the ranges only, and a true hit
    in [range_min, range_max] that is not lost keeps a finite range, clipped to it.

    Args:
        distance_m, geom_ids: ``(m,)`` the cast: range from each beam's own origin (m),
            geom hit (-1: none).
        normals: ``(3 m,)`` the surface normals at the hits; ``along``: ``(m,)`` each
            normal dotted with its beam's direction.
        normal_draws: ``(m,)`` N(0, 1) draws; ``uniforms``: ``(5, m)`` uniform draws (two
            for dropouts, three for mixed pixels).
        label_by_geom: ``uint8`` label of a hit per geom id, and one more for no hit.
        adjacent: ``(m - 1,)`` bool, useful beams ``j`` and ``j + 1`` neighbours in angle.
        origins, dirs: ``(m, 3)`` each beam's origin and direction in the world.
        useful_beams: ``(m,)`` the beam numbers of the useful beams, in order.
        num_beams: beams in the whole scan; the others are blocked by the robot's body.
        params: the scanner's numbers in the order of ``PARAMS``.

    Returns:
        ``(num_beams,)`` ranges (REP-117: ``+inf`` no return, ``-inf`` closer than
        range_min and blocked), ``uint8`` labels (OCCLUDED where blocked), ``(num_beams,
        3)`` noiseless hit points (NaN without a return), ``int32`` geom ids (-1 without).
    """
    range_min, range_max, dropout, cos_start = params[0], params[1], params[2], params[3]
    min_z, noise_std, noise_fraction = params[4], params[5], params[6]
    mix_probability, mix_jump, resolution = params[7], params[8], params[9]
    m = len(distance_m)
    no_return = np.empty(m, np.bool_)
    readings = np.empty(m)
    for j in range(m):
        miss = geom_ids[j] < 0 or distance_m[j] > range_max
        lost = dropped(uniforms[0, j], uniforms[1, j], abs(along[j]), dropout, cos_start)
        no_return[j] = miss or lost  # a miss that is also "lost" is a miss all the same
        readings[j] = noisy(distance_m[j], normal_draws[j], noise_std, noise_fraction)
    pairs = uniforms[2:, :-1]
    mix_edges(readings, distance_m, no_return, adjacent, pairs, mix_probability, mix_jump)

    ranges = np.full(num_beams, -np.inf)  # blocked: the leg is closer than range_min
    labels = np.full(num_beams, np.uint8(_OCCLUDED))
    geoms = np.full(num_beams, np.int32(-1))
    points = np.full((num_beams, 3), np.nan)
    for j in range(m):
        beam = useful_beams[j]
        reading = quantised(readings[j], resolution)
        reading = np.minimum(np.maximum(reading, range_min), range_max)
        if distance_m[j] < range_min:
            reading = -np.inf
        if no_return[j]:
            ranges[beam] = np.inf  # after -inf: a miss reports a distance of -1
            labels[beam] = label_by_geom[-1]
            continue
        ranges[beam] = reading
        geoms[beam] = geom_ids[j]
        label = label_by_geom[geom_ids[j]]
        if label == _STATIC and abs(normals[3 * j + 2]) >= min_z:
            label = _HORIZONTAL
        labels[beam] = label
        for k in range(3):
            points[beam, k] = origins[j, k] + dirs[j, k] * distance_m[j]
    return ranges, labels, points, geoms


@kernel
def from_beam_origins(
    distance_m: np.ndarray,
    geom_ids: np.ndarray,
    normals: np.ndarray,
    along: np.ndarray,
    origins: np.ndarray,
    dirs: np.ndarray,
    cast_from: np.ndarray,
) -> None:
    """Each hit normal dotted with its beam's direction, and ranges moved to the beams'
    own origins.

    A beam cast from another beam's origin (its group's middle one) hit a surface; a
    plane ``n.x = c`` hit from ``p0`` at range ``r`` is hit from ``p0 + d`` at ``r - n.d
    / n.u`` (``u`` the beam's direction), exact for flat surfaces. The sums are taken in
    the order ``np.einsum`` took them, so the numbers are those of the numpy code this
    replaced.

    Args:
        distance_m: ``(m,)`` the cast's ranges, changed in place (m).
        geom_ids, normals: ``(m,)`` the geoms hit (-1: none); ``(3 m,)`` their normals.
        along: ``(m,)`` out: each normal dotted with its beam's direction.
        origins, dirs: ``(m, 3)`` each beam's origin and direction in the world.
        cast_from: ``(m,)`` the beam whose origin each beam was cast from, or empty when
            all were cast from their own origin.
    """
    for j in range(len(distance_m)):
        n0, n1, n2 = normals[3 * j], normals[3 * j + 1], normals[3 * j + 2]
        a = (n0 * dirs[j, 0] + n2 * dirs[j, 2]) + n1 * dirs[j, 1]
        along[j] = a
        if len(cast_from) == 0:
            continue
        mid = cast_from[j]
        d0 = origins[j, 0] - origins[mid, 0]
        d1 = origins[j, 1] - origins[mid, 1]
        d2 = origins[j, 2] - origins[mid, 2]
        shift = (n0 * d0 + n2 * d2) + n1 * d1
        if geom_ids[j] >= 0 and abs(a) > 1e-9:
            distance_m[j] = distance_m[j] - shift / a
