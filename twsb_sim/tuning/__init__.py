"""``twsb tune``: fit the improved filter's parameters to a robot from generated data.

Training and held-out episodes are simulated as ``twsb generate`` draws them
(:mod:`~twsb_sim.tuning.data`); the objective is measured in one pass per parameter set
(:mod:`~twsb_sim.tuning.objective`); a Latin-hypercube design and a pattern search look
for the best set (:mod:`~twsb_sim.tuning.search`); the command line writes the parameter
file (:mod:`~twsb_sim.tuning.cli`). The names below load on first use.
"""

from __future__ import annotations

from twsb_sim.lazy_exports import lazy_exports

_HOMES = {  # public name -> the module that holds it
    "TuningRun": "data",
    "episodes": "data",
    "simulate_episode": "data",
    "OBJECTIVES": "objective",
    "Score": "objective",
    "score": "objective",
    "sweep": "objective",
    "SPACE": "search",
    "Dimension": "search",
    "search": "search",
}
__getattr__, __all__ = lazy_exports(__name__, _HOMES)
