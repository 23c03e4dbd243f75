"""The search ``twsb tune`` runs: a Latin-hypercube design, then a pattern search.

1. **Design**: the defaults and ``samples`` points of a Latin hypercube
   (``scipy.stats.qmc``) over the box of :data:`SPACE`, each scored on the training runs.
2. **Pattern search** from the best point: each parameter in turn is moved up and down by
   its step (a quarter of its range, in log space where marked); a move is kept when it
   raises the objective; after a sweep without gain the steps halve. It stops after
   ``refine_rounds`` sweeps or when the steps are below an eighth of the first.

Every parameter searched is physical, with bounds a robot of the paper's class can have
(see :class:`pvfilter.ImprovedParams` for what each means); the LiDAR and axle heights are
not searched: they are the robot's and are read from each run. Integers are rounded.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

import numpy as np
from scipy.stats import qmc
from tqdm import tqdm

from pvfilter import ImprovedParams


@dataclasses.dataclass(frozen=True)
class Dimension:
    """One searched parameter: its bounds and whether it is searched in log space."""

    name: str
    low: float
    high: float
    log: bool = False
    integer: bool = False

    def from_unit(self, u: float) -> float | int:
        """The value at ``u`` in [0, 1] of the box."""
        if self.log:
            value = math.exp(math.log(self.low) + u * (math.log(self.high) - math.log(self.low)))
        else:
            value = self.low + u * (self.high - self.low)
        return round(value) if self.integer else float(f"{value:.3g}")  # 3 digits: readable

    def to_unit(self, value: float) -> float:
        """Where ``value`` lies in the box, in [0, 1]."""
        if self.log:
            u = (math.log(value) - math.log(self.low)) / (math.log(self.high) - math.log(self.low))
        else:
            u = (value - self.low) / (self.high - self.low)
        return min(max(u, 0.0), 1.0)


SPACE: tuple[Dimension, ...] = (
    Dimension("free_margin_m", 0.05, 0.4),
    Dimension("free_margin_rel", 0.0, 0.08),
    Dimension("memory_shrink_mps", 0.1, 3.0, log=True),
    Dimension("line_shrink_mps", 0.05, 3.0, log=True),
    Dimension("max_event_s", 0.5, 5.0, log=True),
    Dimension("max_roll_deg", 1.0, 10.0, log=True),
    Dimension("line_angle_deg", 15.0, 50.0),
    Dimension("chord_m", 0.15, 0.6),
    Dimension("break_distance_m", 0.1, 0.5),
    Dimension("min_points", 3, 12, integer=True),
    Dimension("extend_tolerance_m", 0.02, 0.15),
    Dimension("up_side_weight", 0.0, 1.0),
    Dimension("claimed_not_new_weight", 0.0, 1.0),
    Dimension("line_length_m", 0.3, 1.5),
    Dimension("confirm_free_s", 0.1, 0.6),
    Dimension("association_m", 0.1, 0.5),
)


def params_at(base: ImprovedParams, unit: np.ndarray) -> ImprovedParams:
    """``base`` with every searched parameter set from a point of the unit box."""
    return dataclasses.replace(
        base, **{d.name: d.from_unit(float(u)) for d, u in zip(SPACE, unit, strict=True)}
    )


def unit_of(params: ImprovedParams) -> np.ndarray:
    """Where ``params`` lie in the unit box."""
    return np.array([d.to_unit(getattr(params, d.name)) for d in SPACE])


@dataclasses.dataclass
class SearchLog:
    """Every point scored: (objective value, parameters), in order."""

    tried: list = dataclasses.field(default_factory=list)

    @property
    def best(self) -> tuple[float, ImprovedParams]:
        return max(self.tried, key=lambda t: t[0])


def search(
    evaluate: Callable[[ImprovedParams], float],
    base: ImprovedParams,
    samples: int,
    refine_rounds: int,
    seed: int = 0,
    progress: bool = True,
) -> SearchLog:
    """Maximize ``evaluate`` over :data:`SPACE` (see the module docstring).

    Args:
        evaluate: the objective of a parameter set (on the training runs).
        base: the defaults: the first point, and the values of what is not searched.
        samples: Latin-hypercube points after the defaults.
        refine_rounds: pattern-search sweeps at most.
        seed: seed of the Latin hypercube.
        progress: show progress bars.
    """
    log = SearchLog()
    design = qmc.LatinHypercube(d=len(SPACE), seed=seed).random(samples)
    points = [unit_of(base), *design]
    for unit in tqdm(points, desc="design", unit="point", disable=not progress):
        params = params_at(base, unit)
        log.tried.append((evaluate(params), params))
    best_value, best_params = log.best
    best_unit, step = unit_of(best_params), 0.25
    bar = tqdm(total=refine_rounds, desc="pattern search", unit="sweep", disable=not progress)
    for _ in range(refine_rounds):
        gained = False
        for i in range(len(SPACE)):
            for sign in (1.0, -1.0):
                trial = best_unit.copy()
                trial[i] = min(max(trial[i] + sign * step, 0.0), 1.0)
                params = params_at(base, trial)
                if params == best_params:
                    continue  # an integer that did not move, or a bound
                value = evaluate(params)
                log.tried.append((value, params))
                if value > best_value:
                    best_value, best_params, best_unit, gained = value, params, trial, True
                    break
        bar.update()
        if not gained:
            step /= 2.0
            if step < 0.25 / 8:
                break
    bar.close()
    return log
