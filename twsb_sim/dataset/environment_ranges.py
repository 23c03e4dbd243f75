"""What ``twsb generate`` draws for an episode's surroundings and robot class.

Tables of a ranges file (each optional; ``twsb generate --show-ranges`` prints them):

- ``[floor]``: floor features laid across the robot's lane (thresholds, ramps, rugs,
  cables), on top of those its house has in its doorways;
- ``[ceiling]``: a lower ceiling than the house's (a basement);
- ``[movers]``: people walking across the robot's view, a pet, doors swinging in the
  start room, a light piece of furniture on the lane to bump into;
- ``[robot_classes]``: the weight of each robot class (:mod:`twsb_sim.robot_classes`).

Ranges are ``[low, high]`` drawn uniformly (counts as integers); a single number fixes the
value.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from twsb_sim.dataset.ranges_checks import Range, normalize, within


@dataclass(frozen=True)
class FloorRanges:
    """Floor features across the robot's lane."""

    probability: float = 0.5  # an episode has features on its lane
    count: Range | float = (1.0, 3.0)  # features on the lane
    threshold_weight: float = 0.35  # relative weights of the kinds
    ramp_weight: float = 0.2
    rug_weight: float = 0.25
    cable_weight: float = 0.2
    threshold_height_m: Range | float = (0.01, 0.03)  # m
    ramp_height_m: Range | float = (0.03, 0.08)  # m
    ramp_slope_deg: Range | float = (4.0, 8.0)  # deg
    rug_height_m: Range | float = (0.005, 0.02)  # m
    rug_friction: Range | float = (0.8, 1.4)  # sliding friction of the rug under the tyres
    cable_height_m: Range | float = (0.008, 0.024)  # m, the cable's diameter

    def __post_init__(self) -> None:
        normalize(self)
        within("probability", self.probability, 0.0, 1.0)
        within("count", self.count, 0.0, 10.0)
        for name in ("threshold_weight", "ramp_weight", "rug_weight", "cable_weight"):
            within(name, getattr(self, name), 0.0, 100.0)
        within("threshold_height_m", self.threshold_height_m, 0.002, 0.06)
        within("ramp_height_m", self.ramp_height_m, 0.005, 0.2)
        within("ramp_slope_deg", self.ramp_slope_deg, 1.0, 15.0)
        within("rug_height_m", self.rug_height_m, 0.002, 0.05)
        within("rug_friction", self.rug_friction, 0.1, 3.0)
        within("cable_height_m", self.cable_height_m, 0.002, 0.05)

    def weights(self) -> dict[str, float]:
        """Kind -> weight."""
        return {k: getattr(self, f"{k}_weight") for k in ("threshold", "ramp", "rug", "cable")}


@dataclass(frozen=True)
class CeilingRanges:
    """A lower ceiling than the house's."""

    low_probability: float = 0.15  # the episode's house gets a low ceiling
    height_m: Range | float = (2.0, 2.3)  # m

    def __post_init__(self) -> None:
        normalize(self)
        within("low_probability", self.low_probability, 0.0, 1.0)
        within("height_m", self.height_m, 1.9, 4.0)


@dataclass(frozen=True)
class MoverRanges:
    """People, a pet, doors and light furniture."""

    people_probability: float = 0.3  # an episode has people walking across the view
    people: Range | float = (1.0, 3.0)
    person_speed_mps: Range | float = (0.5, 1.5)  # m/s
    person_height_m: Range | float = (1.5, 1.95)  # m
    stand_s: Range | float = (0.0, 2.0)  # s, standing and turning at each end of a path
    pet_probability: float = 0.15
    pet_speed_mps: Range | float = (0.3, 1.5)  # m/s
    pet_shoulder_height_m: Range | float = (0.2, 0.5)  # m
    door_probability: float = 0.3  # the start room's doorways get swinging leaves
    door_swings: Range | float = (1.0, 4.0)  # swings of each leaf in an episode
    light_furniture_probability: float = 0.15  # a stool or box on the lane ahead
    light_furniture_mass_kg: Range | float = (1.0, 5.0)  # kg

    def __post_init__(self) -> None:
        normalize(self)
        for name in ("people_probability", "pet_probability", "door_probability",
                     "light_furniture_probability"):  # fmt: skip
            within(name, getattr(self, name), 0.0, 1.0)
        within("people", self.people, 0.0, 10.0)
        within("person_speed_mps", self.person_speed_mps, 0.05, 3.0)
        within("person_height_m", self.person_height_m, 1.0, 2.2)
        within("stand_s", self.stand_s, 0.0, 60.0)
        within("pet_speed_mps", self.pet_speed_mps, 0.05, 5.0)
        within("pet_shoulder_height_m", self.pet_shoulder_height_m, 0.15, 0.8)
        within("door_swings", self.door_swings, 0.0, 50.0)
        within("light_furniture_mass_kg", self.light_furniture_mass_kg, 0.2, 30.0)


@dataclass(frozen=True)
class RobotClassWeights:
    """Relative weight of each robot class (:data:`twsb_sim.robot_classes.ROBOT_CLASSES`)."""

    lqr: float = 0.5
    soft_lqr: float = 0.1
    torque_limited: float = 0.1
    pid: float = 0.1
    lqr_brake: float = 0.1
    pid_brake: float = 0.1

    def __post_init__(self) -> None:
        for name, weight in self.weights().items():
            within(name, weight, 0.0, 100.0)
        if sum(self.weights().values()) <= 0.0:
            raise ValueError("lqr: the robot class weights must not all be 0")

    def weights(self) -> dict[str, float]:
        """Class name -> weight."""
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}
