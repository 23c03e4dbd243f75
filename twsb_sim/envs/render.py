"""Offscreen pictures of the robot for ``render_mode="rgb_array"``.

A camera follows the robot from behind and above, the ceiling is hidden so the rooms can
be seen, and the latest scan's true hit points are drawn as small dots coloured by their
ground-truth label (pitch-variation points stand out in orange, blue and purple).

MuJoCo picks its OpenGL backend when ``mujoco`` is first imported, from ``MUJOCO_GL``.
A machine without a display needs ``MUJOCO_GL=egl`` (GPU or Mesa) or ``MUJOCO_GL=osmesa``
(software) set before that import; :class:`OffscreenUnavailableError` says so when no
context can be made.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from twsb_sim.frame import Frame
from twsb_sim.house.floorplan import CEILING_GROUP
from twsb_sim.labels import BeamLabel
from twsb_sim.robot import ROBOT_GEOM_GROUP

POINT_RADIUS_M = 0.025  # m, size of a drawn scan point
HEADLIGHT_AMBIENT = 0.35  # intensity of the camera's headlight in rendered pictures
HEADLIGHT_DIFFUSE = 0.6
MAX_POINTS = 720  # scan points drawn at most (one revolution at the default resolution)
LABEL_RGBA = {
    BeamLabel.STATIC: (0.85, 0.85, 0.85, 1.0),
    BeamLabel.FLOOR: (1.0, 0.55, 0.0, 1.0),
    BeamLabel.CEILING: (0.2, 0.5, 1.0, 1.0),
    BeamLabel.HORIZONTAL: (0.75, 0.2, 0.9, 1.0),
    BeamLabel.DYNAMIC: (0.1, 0.8, 0.3, 1.0),
}


class OffscreenUnavailableError(RuntimeError):
    """No OpenGL context for offscreen rendering on this machine (see the module docstring)."""


class TrackingRenderer:
    """Renders RGB pictures of one model from a camera that follows the robot's base.

    Args:
        model: the compiled model (robot in a house).
        base_body_id: the body the camera follows.
        width, height: picture size in pixels.
        distance_m: camera distance from the robot, m.
        elevation_deg: camera elevation, negative = looking down.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        base_body_id: int,
        width: int = 640,
        height: int = 480,
        distance_m: float = 4.5,
        elevation_deg: float = -60.0,
    ) -> None:
        self.model = model
        try:
            self._renderer = mujoco.Renderer(model, height=height, width=width)
        except Exception as error:  # the backend raises several types (FatalError, Attribute...)
            raise OffscreenUnavailableError(
                "offscreen rendering needs an OpenGL context: set MUJOCO_GL=egl (or osmesa) "
                f"before mujoco is imported; the backend said: {error}"
            ) from error
        self.base_body_id = base_body_id
        # a free camera re-aimed at every picture: MuJoCo's tracking camera smooths its
        # motion over successive frames, so a picture would depend on when the last was taken
        self.camera = mujoco.MjvCamera()
        self.camera.type = mujoco.mjtCamera.mjCAMERA_FREE
        self.camera.distance = distance_m
        self.camera.elevation = elevation_deg
        self.options = mujoco.MjvOption()
        self.options.geomgroup[CEILING_GROUP] = 0
        self.options.geomgroup[ROBOT_GEOM_GROUP] = 1  # MuJoCo shows groups 0-2 by default

    def render(self, data: mujoco.MjData, yaw_rad: float, frame: Frame | None) -> np.ndarray:
        """A picture (uint8[height, width, 3]) of the current state, the camera behind the
        robot's heading ``yaw_rad``, with ``frame``'s hit points when given."""
        self.camera.lookat[:] = data.xpos[self.base_body_id]
        self.camera.azimuth = math.degrees(yaw_rad)
        self._renderer.update_scene(data, camera=self.camera, scene_option=self.options)
        self._brighten_headlight()
        if frame is not None:
            self._add_points(frame)
        return self._renderer.render()

    def _brighten_headlight(self) -> None:
        # the houses' lamps light rooms for the eye; seen from above, a stronger headlight
        # keeps floor and furniture apart (changes this picture only, not the model)
        scene = self._renderer.scene
        for light in (scene.lights[i] for i in range(scene.nlight)):
            if light.headlight:
                light.ambient[:] = HEADLIGHT_AMBIENT
                light.diffuse[:] = HEADLIGHT_DIFFUSE

    def _add_points(self, frame: Frame) -> None:
        scene = self._renderer.scene
        size = np.full(3, POINT_RADIUS_M)
        identity = np.eye(3).ravel()
        hits = np.flatnonzero(np.isfinite(frame.hit_points_world[:, 0]))[:MAX_POINTS]
        for i in hits:
            rgba = LABEL_RGBA.get(BeamLabel(int(frame.labels[i])))
            if rgba is None or scene.ngeom >= scene.maxgeom:
                continue
            mujoco.mjv_initGeom(
                scene.geoms[scene.ngeom],
                mujoco.mjtGeom.mjGEOM_SPHERE,
                size,
                frame.hit_points_world[i],
                identity,
                np.array(rgba, dtype=np.float32),
            )
            scene.ngeom += 1

    def close(self) -> None:
        self._renderer.close()
