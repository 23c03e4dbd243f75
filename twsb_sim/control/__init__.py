"""Balance and motion control of the robot: LQR designed on the MJCF model itself."""

from twsb_sim.control.lqr import (
    LqrConfig,
    LqrController,
    LqrGains,
    UnstableClosedLoopError,
    compute_gains,
    linearize,
)

__all__ = [
    "LqrConfig",
    "LqrController",
    "LqrGains",
    "UnstableClosedLoopError",
    "compute_gains",
    "linearize",
]
