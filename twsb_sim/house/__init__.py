"""Procedural house-like floor plans for the simulator: rooms, doorways, furniture.

``make_house("house1")`` and ``make_house("house2")`` are fixed layouts;
``random_house(seed)`` draws a new one from a seed; both come with their extras (floor
features, ceilings, stairs: ``house_with`` adds more). ``add_house_to_spec`` puts a house
into a ``mujoco.MjSpec``; ``surface_classes`` tells, per geom of the compiled model,
what it is (floor, ceiling, structure, furniture, robot).
"""

from twsb_sim.house.build import house_with
from twsb_sim.house.extras import HouseExtras, merge_extras, with_extras
from twsb_sim.house.floor_features import FLOOR_FEATURE_KINDS, FloorFeature
from twsb_sim.house.floorplan import WALL_THICKNESS_M
from twsb_sim.house.furniture import FURNITURE_KINDS
from twsb_sim.house.mjspec import add_house_to_spec, house_spec
from twsb_sim.house.model import Doorway, Furniture, House, Part, Room, SpawnPose
from twsb_sim.house.named import NAMED_HOUSES, make_house
from twsb_sim.house.random_plan import random_house
from twsb_sim.house.spawn import ROBOT_RADIUS_M
from twsb_sim.house.surfaces import (
    ROBOT_GEOM_GROUP,
    SurfaceClass,
    surface_class_of_name,
    surface_classes,
)

__all__ = [
    "FLOOR_FEATURE_KINDS",
    "FURNITURE_KINDS",
    "NAMED_HOUSES",
    "ROBOT_GEOM_GROUP",
    "ROBOT_RADIUS_M",
    "WALL_THICKNESS_M",
    "Doorway",
    "FloorFeature",
    "Furniture",
    "House",
    "HouseExtras",
    "Part",
    "Room",
    "SpawnPose",
    "SurfaceClass",
    "add_house_to_spec",
    "house_spec",
    "house_with",
    "make_house",
    "merge_extras",
    "random_house",
    "surface_class_of_name",
    "surface_classes",
    "with_extras",
]
