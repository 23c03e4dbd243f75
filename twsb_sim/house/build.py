"""A house by name or seed, with its own extras and any a scenario adds."""

from __future__ import annotations

from twsb_sim.house.extras import HouseExtras, merge_extras, with_extras
from twsb_sim.house.model import House
from twsb_sim.house.named import make_house, named_house_extras, plain_house
from twsb_sim.house.random_plan import random_house, random_house_extras, random_plain_house


def house_with(name: str | None, seed: int | None, extras: HouseExtras | None = None) -> House:
    """A named layout (``name``) or a random house (``seed``), with its own extras and
    ``extras`` on top (the cached house when there are none).

    Raises:
        ValueError: an unknown name.
        KeyError: an extra names a room the house does not have.
    """
    if not extras:
        return make_house(name) if name is not None else random_house(seed)
    if name is not None:
        plain, own = plain_house(name), named_house_extras(name)
    else:
        plain, own = random_plain_house(seed), random_house_extras(seed)
    return with_extras(plain, merge_extras(own, extras))
