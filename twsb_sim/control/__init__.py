"""Balance and motion control of the robot: LQR designed on the MJCF model itself."""

from twsb_sim.control.gains import LqrConfig, LqrGains, UnstableClosedLoopError, compute_gains
from twsb_sim.control.linearization import LinearModel, linearize
from twsb_sim.control.lqr import LqrController

__all__ = [
    "LinearModel",
    "LqrConfig",
    "LqrController",
    "LqrGains",
    "UnstableClosedLoopError",
    "compute_gains",
    "linearize",
]
