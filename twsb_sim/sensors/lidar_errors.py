"""The imperfections of a cheap 2D LiDAR, applied to the exact ranges of a ray cast.

Each effect is one compiled function (:mod:`twsb_sim.kernel`) on one beam, or on a pair
of neighbouring beams, and each is switched off by a zero in
:class:`~twsb_sim.lidar.LidarConfig` (``LidarConfig.ideal()`` switches off all):

- **dropouts**: a return is lost at random (``dropout_probability``), and more and more
  often as the beam meets its surface at a grazing angle: beyond
  ``grazing_dropout_start_deg`` from the surface normal the loss probability rises
  to 1 at 90 deg, linearly in the incidence's cosine (too little light comes back). A
  lost return reads ``+inf``;
- **range noise** growing with range: Gaussian, ``std = range_noise_std_m +
  range_noise_fraction * range``;
- **mixed pixels**: where two neighbouring beams' true ranges differ by more than
  ``mixed_pixel_min_jump_m`` (a depth edge), the beam's spot straddles the edge with
  probability ``mixed_pixel_probability``, and one of the two beams reads a range
  between the foreground and the background (a point floating in free space);
- **quantisation** of the reading to ``range_resolution_m``.

The minimum range is the scanner's ``range_min_m`` (REP-117: ``-inf`` below it).
:func:`twsb_sim.lidar_reading.read_beams` applies them all in one pass over a scan.
"""

from __future__ import annotations

import numpy as np

from twsb_sim.kernel import kernel


@kernel
def dropped(
    uniform: float,
    uniform_grazing: float,
    cos_incidence: float,
    probability: float,
    cos_start: float,
) -> bool:
    """Whether a return is lost: at random, or at grazing incidence.

    Args:
        uniform, uniform_grazing: two uniform draws in [0, 1) for this beam.
        cos_incidence: |cos| of the angle between the beam and the surface normal.
        probability: ``dropout_probability``.
        cos_start: cosine of ``grazing_dropout_start_deg``.
    """
    lost = uniform < probability
    if cos_start > 1e-12:
        # linear in the cosine: within the last few degrees before 90, the same as linear
        # in the angle to 0.1 %, without an arccos per beam
        lost = lost or uniform_grazing < 1.0 - cos_incidence / cos_start
    return lost


@kernel
def noisy(distance_m: float, normal: float, std_m: float, fraction: float) -> float:
    """``distance_m`` plus Gaussian noise (``normal`` is an N(0, 1) draw) whose std grows
    with range: ``std_m + fraction * distance_m``."""
    return distance_m + (std_m + fraction * distance_m) * normal


@kernel
def mix_edges(
    ranges_m: np.ndarray,
    distance_m: np.ndarray,
    no_return: np.ndarray,
    adjacent: np.ndarray,
    uniforms: np.ndarray,
    probability: float,
    min_jump_m: float,
) -> None:
    """Mixed pixels: at depth edges, one of the two beams reads between the two surfaces.

    Args:
        ranges_m: ``(m,)`` readings so far, changed in place.
        distance_m: ``(m,)`` true ranges (the edges are where the geometry jumps).
        no_return: ``(m,)`` bool, beams without a return.
        adjacent: ``(m - 1,)`` bool, beams ``j`` and ``j + 1`` are neighbours in angle.
        uniforms: ``(3, m - 1)`` uniform draws per pair: edge straddled, which beam,
            where between (pairs in order: a beam two edges share reads the second's).
        probability, min_jump_m: ``mixed_pixel_probability``, ``mixed_pixel_min_jump_m``.
    """
    if probability <= 0 or len(ranges_m) < 2:
        return
    for j in range(len(ranges_m) - 1):
        near = np.minimum(distance_m[j], distance_m[j + 1])
        far = np.maximum(distance_m[j], distance_m[j + 1])
        edge = adjacent[j] and not no_return[j] and not no_return[j + 1]
        if edge and far - near > min_jump_m and uniforms[0, j] < probability:
            beam = j + 1 if uniforms[1, j] < 0.5 else j  # the left or the right beam
            ranges_m[beam] = near + uniforms[2, j] * (far - near)


@kernel
def quantised(range_m: float, step_m: float) -> float:
    """A reading rounded to a multiple of ``step_m`` (unchanged when 0)."""
    return np.rint(range_m / step_m) * step_m if step_m > 0 else range_m
