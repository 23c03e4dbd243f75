"""Robot classes: the default robot and robots that pitch differently.

A class is a balance controller (LQR or cascaded PID), an optional stop brake, and a few
physical or controller settings, as the tables of a scenario file (``[balance]``,
``[robot]``, ``[controller]``). Which way a hard stop tips the body depends on the class:

| class | balance | a hard stop from 1 m/s tips it |
|---|---|---|
| ``lqr`` | the default LQR, 3 N·m motors | nose up (leans back) |
| ``soft_lqr`` | LQR weights x0.05, torque weight 100 | nose up, less |
| ``torque_limited`` | the LQR on 1.5 N·m motors | nose up |
| ``pid`` | a hand-tuned cascaded PID | nose up, less |
| ``lqr_brake`` | the LQR behind a stop brake | nose down first, then up |
| ``pid_brake`` | the PID behind a stop brake | nose down first, then up |

``twsb envelope`` measures each (docs/envelope.md gives the angles). The data-set
generator draws a class per episode (``[robot_classes]`` weights of a ranges file) and,
for the braking classes, the brake's torque and hold time within ``BRAKE_*`` ranges.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

BRAKE_TORQUE_NM = (2.0, 3.0)  # N·m, drawn per episode for the braking classes
BRAKE_HOLD_S = (0.06, 0.14)  # s, beyond ~0.2 s a 1 m/s stop tips the robot over


@dataclass(frozen=True)
class RobotClass:
    """A kind of robot, as scenario-file tables.

    Attributes:
        name: the class's name.
        description: one line for people.
        tables: ``balance``, ``robot`` and ``controller`` tables of a scenario file.
    """

    name: str
    description: str
    tables: dict[str, dict[str, Any]] = field(default_factory=dict)

    @property
    def brakes(self) -> bool:
        return self.tables.get("balance", {}).get("brake_torque_nm", 0.0) > 0.0


ROBOT_CLASSES: dict[str, RobotClass] = {
    c.name: c
    for c in (
        RobotClass("lqr", "the default LQR balance, 3 N·m motors"),
        RobotClass(
            "soft_lqr",
            "a softer LQR: state weights x0.05, torque weight 100",
            {"controller": {"aggressiveness": 0.05, "torque_weight": 100.0}},
        ),
        RobotClass(
            "torque_limited", "the LQR on 1.5 N·m motors", {"robot": {"wheel_torque_limit_nm": 1.5}}
        ),
        RobotClass("pid", "a hand-tuned cascaded PID balance", {"balance": {"kind": "pid"}}),
        RobotClass(
            "lqr_brake",
            "the LQR behind a stop brake (3 N·m, 0.12 s)",
            {"balance": {"brake_torque_nm": 3.0, "brake_s": 0.12}},
        ),
        RobotClass(
            "pid_brake",
            "the PID behind a stop brake (3 N·m, 0.12 s)",
            {"balance": {"kind": "pid", "brake_torque_nm": 3.0, "brake_s": 0.12}},
        ),
    )
}


def robot_class(name: str) -> RobotClass:
    """The class called ``name``.

    Raises:
        ValueError: for an unknown name.
    """
    if name not in ROBOT_CLASSES:
        raise ValueError(f"robot_class: expected one of {sorted(ROBOT_CLASSES)}, got {name!r}")
    return ROBOT_CLASSES[name]


def draw_class_tables(rng: np.random.Generator, name: str) -> dict[str, dict[str, Any]]:
    """A class's tables for one episode: a braking class's brake drawn in its ranges."""
    tables = {key: dict(values) for key, values in robot_class(name).tables.items()}
    if robot_class(name).brakes:
        tables["balance"]["brake_torque_nm"] = round(float(rng.uniform(*BRAKE_TORQUE_NM)), 3)
        tables["balance"]["brake_s"] = round(float(rng.uniform(*BRAKE_HOLD_S)), 3)
    return tables
