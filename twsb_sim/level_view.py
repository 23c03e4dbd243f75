"""What a level scanner at the same place would have seen: the rule that makes a hit on a
ramp, a sloped ceiling or a stair soffit a pitch-variation point or not.

A beam is a pitch-variation point when a level scanner at the same place would not have
hit that surface. On a flat floor and under a flat ceiling the geom class says it all (a
level scanner above a floor never hits it). On a surface that is neither level nor
vertical (a ramp, a threshold's bevel, an attic slope, the soffit under a flight of
stairs) the answer depends on where the beam goes, so the scanner is cast a second time
for the beams that ended on such a surface:

- the **level scanner** sits at the sensor's origin, turned to the sensor's heading (the
  yaw of its x axis), its plane horizontal, and casts the same beam angles;
- the beam is **seen level** when that level beam ends on the same geom, at a range within
  ``LEVEL_RANGE_TOLERANCE`` of the tilted beam's (a wall seen 25 deg off level reads
  1 / cos(25 deg) = 1.10 times farther; a soffit hit higher up by a tilted beam, far more);
- a beam seen level is a surface like a wall: it is relabeled STATIC. The others keep
  their FLOOR or CEILING label.

Only beams that ended on a floor or ceiling surface other than the flat ``floor`` and
``ceiling`` themselves are cast again, so a scan without such hits costs nothing extra.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from twsb_sim.house.surfaces import SurfaceClass, surface_classes
from twsb_sim.labels import BeamLabel
from twsb_sim.lidar import Lidar, LidarReading

LEVEL_RANGE_TOLERANCE = 0.10  # relative: a tilted beam within 10 % of the level beam's range
_FLAT = ("floor", "ceiling")  # a level scanner never hits these


class LevelView:
    """Relabels the hits on sloped floor and ceiling surfaces that a level scanner sees.

    Args:
        model: the compiled model (house, robot, movers).
        lidar: the scanner whose readings are checked.
    """

    def __init__(self, model: mujoco.MjModel, lidar: Lidar) -> None:
        classes = surface_classes(model)
        names = [
            mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, i) or "" for i in range(model.ngeom)
        ]
        sloped = np.isin(classes, (SurfaceClass.FLOOR, SurfaceClass.CEILING))
        sloped &= ~np.isin(np.array(names, dtype=object), _FLAT)
        self._checked = np.append(sloped, False)  # the last entry serves geom id -1
        self.model = model
        self.lidar = lidar
        self.active = bool(sloped.any())

    def relabel(self, data: mujoco.MjData, reading: LidarReading) -> np.ndarray:
        """The reading's labels, with the sloped hits a level scanner sees made STATIC.

        Args:
            data: the state the reading was cast in (kinematics current).
            reading: the scanner's reading.

        Returns:
            uint8 labels (the reading's own array when nothing changes).
        """
        if not self.active:
            return reading.labels
        beams = np.flatnonzero(self._checked[reading.geom_ids])
        if beams.size == 0:
            return reading.labels
        origin = reading.position_sensor_in_world
        rotation = reading.rotation_sensor_to_world
        heading = math.atan2(rotation[1, 0], rotation[0, 0])
        angles = heading + self.lidar.angles[beams]
        directions = np.stack((np.cos(angles), np.sin(angles), np.zeros_like(angles)), -1)
        geom = np.empty(beams.size, dtype=np.int32)
        dist = np.empty(beams.size, dtype=np.float64)
        self.lidar.caster.cast(data, origin, directions, geom, dist, None, self.lidar.range_max)
        tilted = np.linalg.norm(reading.hit_points_world[beams] - origin, axis=1)
        seen = (geom == reading.geom_ids[beams]) & (
            np.abs(tilted - dist) <= LEVEL_RANGE_TOLERANCE * dist
        )
        if not seen.any():
            return reading.labels
        labels = reading.labels.copy()
        labels[beams[seen]] = BeamLabel.STATIC
        return labels
