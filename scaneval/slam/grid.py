"""A log-odds occupancy grid: bilinear map values with gradients, and ray-traced updates.

The grid is the map of the Hector-style SLAM (Kohlbrecher et al. 2011). Cell ``(i, j)``
covers ``x`` in ``[origin_x + i r, origin_x + (i + 1) r)`` and ``y`` likewise, ``r`` the
resolution; its value is stored as log-odds (0 = unknown) and read as the occupancy
probability ``M = 1 / (1 + exp(-l))``, sampled at the cell centre. Points outside the grid
read as unknown (0.5) with a zero gradient and are left out of updates.
"""

from __future__ import annotations

import math

import numpy as np


def log_odds(probability: float) -> float:
    """``log(p / (1 - p))`` of a probability in (0, 1)."""
    return math.log(probability / (1.0 - probability))


class OccupancyGrid:
    """A square log-odds occupancy grid in a world frame (m).

    Args:
        resolution_m: cell size, m.
        size_m: side of the square grid, m (rounded up to whole cells).
        center_xy: world position of the grid's centre, m.
        p_free: occupancy probability a ray passing through a cell stands for (< 0.5);
            each pass adds ``log(p_free / (1 - p_free))`` to the cell.
        p_occupied: the same for the cell a beam ends in (> 0.5).
        log_odds_limit: cells are clamped to ``[-limit, +limit]`` so that a wall seen
            for a long time can still be cleared.
    """

    def __init__(
        self,
        resolution_m: float,
        size_m: float,
        center_xy: tuple[float, float] = (0.0, 0.0),
        p_free: float = 0.4,
        p_occupied: float = 0.9,
        log_odds_limit: float = 10.0,
    ) -> None:
        if resolution_m <= 0.0 or size_m <= resolution_m:
            raise ValueError(
                f"resolution_m, size_m: need 0 < resolution < size, got {resolution_m}, {size_m}"
            )
        if not 0.0 < p_free < 0.5 < p_occupied < 1.0:
            raise ValueError("p_free, p_occupied: need 0 < p_free < 0.5 < p_occupied < 1")
        self.resolution_m = float(resolution_m)
        self.cells = math.ceil(size_m / resolution_m)
        half = 0.5 * self.cells * self.resolution_m
        self.origin_xy = np.array([center_xy[0] - half, center_xy[1] - half], dtype=np.float64)
        self.log_odds = np.zeros((self.cells, self.cells), dtype=np.float64)
        self.free_update = log_odds(p_free)
        self.occupied_update = log_odds(p_occupied)
        self.log_odds_limit = float(log_odds_limit)
        self.updates = 0  # scans integrated so far
        # kept in step with the log-odds, cell by cell, by every update
        self._probability = np.full((self.cells, self.cells), 0.5)

    # --- reading -------------------------------------------------------------------------

    def probability(self) -> np.ndarray:
        """Occupancy probability of every cell, shape ``(cells, cells)``, index ``[i_x, i_y]``.

        The grid's own array, updated in place by :meth:`update` (do not modify it). After
        writing ``log_odds`` directly, call :meth:`refresh`.
        """
        return self._probability

    def refresh(self) -> None:
        """Recompute every cell's probability from ``log_odds``."""
        self._probability = 1.0 / (1.0 + np.exp(-self.log_odds))

    def extent_m(self) -> tuple[float, float, float, float]:
        """``(x_min, x_max, y_min, y_max)`` of the grid in the world, m."""
        size = self.cells * self.resolution_m
        x0, y0 = self.origin_xy
        return float(x0), float(x0 + size), float(y0), float(y0 + size)

    def interpolate(self, points_xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Bilinear occupancy probability and its gradient at world points.

        Args:
            points_xy: points in the world frame, m, shape ``(n, 2)``.

        Returns:
            ``(values, gradients)``: ``M`` in [0, 1], shape ``(n,)``, and ``dM/dx, dM/dy``
            in 1/m, shape ``(n, 2)``. Points whose four neighbouring cell centres are not
            all inside the grid get 0.5 and a zero gradient.
        """
        # continuous cell coordinates with cell centres at integers
        uv = (points_xy - self.origin_xy) / self.resolution_m - 0.5
        corner = np.floor(uv)
        frac = uv - corner
        corner = corner.astype(np.intp)
        inside = np.all((corner >= 0) & (corner < self.cells - 1), axis=1)
        i = np.where(inside, corner[:, 0], 0)
        j = np.where(inside, corner[:, 1], 0)
        # probabilities are interpolated, not log-odds, as Hector does: the map is a
        # probability surface that saturates at walls and in free space
        probability = self.probability()
        m00, m10 = probability[i, j], probability[i + 1, j]
        m01, m11 = probability[i, j + 1], probability[i + 1, j + 1]
        fx, fy = frac[:, 0], frac[:, 1]
        values = (1.0 - fy) * ((1.0 - fx) * m00 + fx * m10) + fy * ((1.0 - fx) * m01 + fx * m11)
        gradients = (
            np.column_stack(
                (
                    (1.0 - fy) * (m10 - m00) + fy * (m11 - m01),
                    (1.0 - fx) * (m01 - m00) + fx * (m11 - m10),
                )
            )
            / self.resolution_m
        )
        values = np.where(inside, values, 0.5)
        gradients[~inside] = 0.0
        return values, gradients

    # --- writing -------------------------------------------------------------------------

    def update(
        self, sensor_xy: np.ndarray, endpoints_xy: np.ndarray, step_cells: float = 0.5
    ) -> None:
        """Integrate one scan: cells crossed by a beam get freer, cells a beam ends in get
        more occupied (each cell at most once per scan; occupied wins, as in Hector).

        Beams are traced by sampling each segment every ``step_cells`` cells (all beams at
        once, no loop over points), which visits the cells Bresenham's line would, give
        or take a corner cell.

        Args:
            sensor_xy: the sensor's position in the world, m, shape ``(2,)``.
            endpoints_xy: beam end points in the world, m, shape ``(n, 2)``; non-finite
                rows are skipped, end points off the grid free the cells up to its edge.
            step_cells: sampling step along a beam, in cells (<= 1).
        """
        start = (np.asarray(sensor_xy, dtype=np.float64) - self.origin_xy) / self.resolution_m
        ends = (np.asarray(endpoints_xy, dtype=np.float64) - self.origin_xy) / self.resolution_m
        ends = ends.reshape(-1, 2)[np.all(np.isfinite(ends.reshape(-1, 2)), axis=1)]
        self.updates += 1
        if len(ends) == 0:
            return
        delta = ends - start
        # a beam longer than the grid's diagonal is traced only that far
        length = np.hypot(delta[:, 0], delta[:, 1])
        longest = 1.5 * self.cells
        delta *= np.minimum(1.0, longest / np.maximum(length, 1e-12))[:, None]
        samples = np.maximum(np.ceil(np.minimum(length, longest) / step_cells), 1)
        samples = samples.astype(np.intp)
        ray = np.repeat(np.arange(len(ends)), samples)
        first = np.repeat(np.cumsum(samples) - samples, samples)
        t = (np.arange(ray.size) - first) / samples[ray]  # in [0, 1): the end cell excluded
        free = self._linear_index(start + t[:, None] * delta[ray])
        occupied = self._linear_index(ends)
        free, occupied = free[free >= 0], occupied[occupied >= 0]
        # indices repeat (many samples per cell, beams sharing cells): a fancy-indexed
        # ``+=`` applies once per distinct cell, which is the once-per-scan rule; cells
        # both crossed and hit end as hit: their value before the scan plus the hit
        flat = self.log_odds.reshape(-1)
        before_hit = flat[occupied]
        flat[free] += self.free_update
        flat[occupied] = before_hit + self.occupied_update
        touched = np.concatenate((free, occupied))
        flat[touched] = np.clip(flat[touched], -self.log_odds_limit, self.log_odds_limit)
        self._probability.reshape(-1)[touched] = 1.0 / (1.0 + np.exp(-flat[touched]))

    def _linear_index(self, cell_xy: np.ndarray) -> np.ndarray:
        """Flat index of the cell holding each continuous cell coordinate, -1 outside."""
        ij = np.floor(cell_xy).astype(np.intp)
        inside = np.all((ij >= 0) & (ij < self.cells), axis=1)
        return np.where(inside, ij[:, 0] * self.cells + ij[:, 1], -1)
