"""People, pets, doors and light furniture: what moves in a house besides the robot.

Kinematic movers (people, pets, door leaves) are MuJoCo mocap bodies without contacts,
posed by :class:`MoverSet` whenever the LiDAR casts (so they cost nothing per physics
step). Light furniture is a free body the robot can bump into. Every geom of a mover sits
on a body that moves, so the LiDAR labels its beams DYNAMIC.
"""

from twsb_sim.movers.doors import SwingingDoor
from twsb_sim.movers.light_furniture import LIGHT_FURNITURE_KINDS, LightFurniture
from twsb_sim.movers.mover_set import Mover, MoverSet
from twsb_sim.movers.paths import WalkPath, WalkState
from twsb_sim.movers.people import MOVER_GROUP, Person
from twsb_sim.movers.pets import Pet

__all__ = [
    "LIGHT_FURNITURE_KINDS",
    "MOVER_GROUP",
    "LightFurniture",
    "Mover",
    "MoverSet",
    "Person",
    "Pet",
    "SwingingDoor",
    "WalkPath",
    "WalkState",
]
