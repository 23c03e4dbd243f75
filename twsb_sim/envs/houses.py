"""Which house an episode runs in, and the simulations kept for recently used houses.

A house option is a named layout (``"house1"``), the seed of a random layout (``7``),
``"random"`` (a new random layout per reset, its seed drawn from the env's generator),
or a list of those (one drawn per reset). Building a house and compiling the model takes
~0.15 s, so the simulations of the last few houses are kept and reused.
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Callable, Sequence

import numpy as np

from twsb_sim.house import NAMED_HOUSES, House, make_house, random_house
from twsb_sim.simulation import Simulation

HouseKey = str | int
HouseOption = HouseKey | Sequence[HouseKey]
RANDOM = "random"
RANDOM_SEED_LIMIT = 2**31  # random layouts' seeds are drawn in [0, this)


def check_house_option(option: HouseOption) -> None:
    """Raise ``ValueError`` naming the entry when ``option`` is not a valid house option."""
    entries = [option] if isinstance(option, str | int) else list(option)
    if not entries:
        raise ValueError("house: expected a name, a seed, 'random' or a non-empty list of those")
    for entry in entries:
        if isinstance(entry, bool) or not isinstance(entry, str | int):
            raise ValueError(f"house: expected a name, a seed or 'random', got {entry!r}")
        if isinstance(entry, str) and entry != RANDOM and entry not in NAMED_HOUSES:
            raise ValueError(
                f"house: unknown name {entry!r}; expected one of {sorted(NAMED_HOUSES)}, "
                f"a seed or {RANDOM!r}"
            )
        if isinstance(entry, int) and entry < 0:
            raise ValueError(f"house: a random layout's seed must be >= 0, got {entry}")


def choose_house(option: HouseOption, rng: np.random.Generator) -> HouseKey:
    """The house of one episode: a name or a random layout's seed."""
    if not isinstance(option, str | int):
        option = option[int(rng.integers(len(option)))]
    if option == RANDOM:
        return int(rng.integers(RANDOM_SEED_LIMIT))
    return option


def build_house(key: HouseKey) -> House:
    return make_house(key) if isinstance(key, str) else random_house(key)


class SimulationCache:
    """The simulations of the last ``size`` houses used, built on demand.

    Args:
        build: makes the simulation of a house.
        size: how many to keep.
    """

    def __init__(self, build: Callable[[House], Simulation], size: int = 8) -> None:
        self._build = build
        self._size = size
        self._sims: OrderedDict[HouseKey, Simulation] = OrderedDict()

    def get(self, key: HouseKey) -> Simulation:
        sim = self._sims.pop(key, None)
        if sim is None:
            sim = self._build(build_house(key))
        self._sims[key] = sim
        while len(self._sims) > self._size:
            self._sims.popitem(last=False)
        return sim
