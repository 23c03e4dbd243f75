"""What a scenario adds to its house: floor features, ceilings, shelves, people, pets,
doors and light furniture (the ``[ceiling]``, ``[[floor_features]]``, ``[[people]]``, ...
tables of a scenario file)."""

from twsb_sim.environment.loader import ENVIRONMENT_KEYS, Environment, environment_from_table
from twsb_sim.environment.world import check_rooms, house_extras, movers

__all__ = [
    "ENVIRONMENT_KEYS",
    "Environment",
    "check_rooms",
    "environment_from_table",
    "house_extras",
    "movers",
]
