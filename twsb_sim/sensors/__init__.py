"""The robot's sensors as cheap hardware gives them: IMU, attitude estimate, wheel odometry,
the rotating LiDAR's timing and its reading errors (see ``docs/sensors.md``).

Names load on first use: :mod:`twsb_sim.frame` needs the readings' types without the
simulator.
"""

from __future__ import annotations

from twsb_sim.lazy_exports import lazy_exports

_MODULES = {  # public name: the module that defines it
    "Attitude": "readings",
    "AttitudeFilterConfig": "attitude",
    "ComplementaryFilter": "attitude",
    "EncoderOdometry": "odometry",
    "ImuConfig": "imu",
    "ImuModel": "imu",
    "ImuSamples": "readings",
    "OdometryConfig": "odometry",
    "OdometrySamples": "readings",
    "PoseHistory": "sweep",
    "SensorReadings": "readings",
    "SensorSuite": "suite",
}

__getattr__, __all__ = lazy_exports(__name__, _MODULES)
