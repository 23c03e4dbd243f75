"""The imperfections of a cheap 2D LiDAR, applied to the exact ranges of a ray cast.

Each effect is one function working on all beams at once, and each is switched off by a
zero in :class:`~twsb_sim.lidar.LidarConfig` (``LidarConfig.ideal()`` switches off all):

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
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from twsb_sim.lidar import LidarConfig


def dropped_returns(
    cos_incidence: np.ndarray, uniforms: np.ndarray, config: LidarConfig
) -> np.ndarray:
    """Which returns are lost: at random, or at grazing incidence.

    Args:
        cos_incidence: ``(m,)`` |cos| of the angle between beam and surface normal.
        uniforms: ``(2, m)`` uniform draws in [0, 1).
        config: the scanner.

    Returns:
        ``(m,)`` bool, True where the return is lost.
    """
    lost = uniforms[0] < config.dropout_probability
    cos_start = math.cos(math.radians(config.grazing_dropout_start_deg))
    if cos_start > 1e-12:
        # linear in the cosine: within the last few degrees before 90, the same as linear
        # in the angle to 0.1 %, without an arccos per beam
        lost |= uniforms[1] < 1.0 - cos_incidence / cos_start
    return lost


def noisy_ranges(distance_m: np.ndarray, normals: np.ndarray, config: LidarConfig) -> np.ndarray:
    """``distance_m`` plus Gaussian noise whose std grows with range; ``normals`` are N(0, 1)."""
    std = config.range_noise_std_m + config.range_noise_fraction * distance_m
    return distance_m + std * normals


def mix_edges(
    ranges_m: np.ndarray,
    distance_m: np.ndarray,
    returned: np.ndarray,
    adjacent: np.ndarray,
    uniforms: np.ndarray,
    config: LidarConfig,
) -> np.ndarray:
    """Mixed pixels: at depth edges, one of the two beams reads between the two surfaces.

    Args:
        ranges_m: ``(m,)`` readings so far (changed in place and returned).
        distance_m: ``(m,)`` true ranges (the edges are where the geometry jumps).
        returned: ``(m,)`` bool, beams with a return.
        adjacent: ``(m - 1,)`` bool, beams ``j`` and ``j + 1`` are neighbours in angle.
        uniforms: ``(3, m - 1)`` uniform draws: edge straddled, which beam, where between.
        config: the scanner.
    """
    if config.mixed_pixel_probability <= 0 or len(ranges_m) < 2:
        return ranges_m
    left, right = distance_m[:-1], distance_m[1:]
    near, far = np.minimum(left, right), np.maximum(left, right)
    edge = adjacent & returned[:-1] & returned[1:] & (far - near > config.mixed_pixel_min_jump_m)
    edge &= uniforms[0] < config.mixed_pixel_probability
    j = np.flatnonzero(edge)
    beam = j + (uniforms[1, j] < 0.5)  # the left or the right beam of the pair
    ranges_m[beam] = near[j] + uniforms[2, j] * (far[j] - near[j])
    return ranges_m


def quantised(ranges_m: np.ndarray, step_m: float) -> np.ndarray:
    """Readings rounded to multiples of ``step_m`` (unchanged when 0)."""
    return np.rint(ranges_m / step_m) * step_m if step_m > 0 else ranges_m  # = np.round, faster
