"""Static geometry: the house, the robot's body, the LiDAR mount, the sensor view's furniture.

All of it is logged once with ``static=True``: it never changes during a run. The robot's
body is logged in its base frame under ``world/robot``, whose pose the per-sample
transforms then move.
"""

from __future__ import annotations

import math
from collections import defaultdict

import mujoco
import numpy as np
import rerun as rr

from twsb_sim.house import House, Part
from twsb_sim.rerun_log import paths
from twsb_sim.robot import ROBOT_GEOM_GROUP

FLOOR_THICKNESS_M = 0.01  # the floor plane is drawn as a thin slab below z = 0
WALL_ALPHA = 0.35  # see-through walls: the robot stays visible from any side
SCAN_PLANE_RADIUS_M = 1.0  # the disc that shows how the scan plane tilts
RING_STEP_M = 2.0  # range rings in the sensor view


def _rgba(rgba: tuple[float, ...], alpha: float | None = None) -> tuple[int, int, int, int]:
    r, g, b, a = (round(255 * c) for c in rgba)
    return r, g, b, a if alpha is None else round(255 * alpha)


def _yaw_quaternion(yaw_rad: float) -> rr.Quaternion:
    half = yaw_rad / 2
    return rr.Quaternion(xyzw=[0.0, 0.0, math.sin(half), math.cos(half)])


def _parts_as_boxes(parts: list[Part], alpha: float | None = None) -> rr.Boxes3D:
    """Boxes (planes become thin slabs whose top is the plane)."""
    centers, half_sizes = [], []
    for part in parts:
        if part.shape == "plane":
            half_sizes.append((part.size[0], part.size[1], FLOOR_THICKNESS_M / 2))
            centers.append((part.pos[0], part.pos[1], part.pos[2] - FLOOR_THICKNESS_M / 2))
        else:
            half_sizes.append(part.size)
            centers.append(part.pos)
    return rr.Boxes3D(
        centers=centers,
        half_sizes=half_sizes,
        quaternions=[_yaw_quaternion(p.yaw_rad) for p in parts],
        colors=[_rgba(p.rgba, alpha) for p in parts],
        labels=[p.name for p in parts],
        show_labels=False,
        fill_mode="solid",
    )


def _parts_as_cylinders(parts: list[Part]) -> rr.Cylinders3D:
    return rr.Cylinders3D(
        centers=[p.pos for p in parts],
        radii=[p.size[0] for p in parts],
        lengths=[2 * p.size[1] for p in parts],
        colors=[_rgba(p.rgba) for p in parts],
        labels=[p.name for p in parts],
        show_labels=False,
        fill_mode="solid",
    )


def log_house(rec: rr.RecordingStream, house: House) -> None:
    """Floor, ceiling, walls (see-through) and furniture, static, in the world frame."""
    rec.log(paths.WORLD, rr.ViewCoordinates.RIGHT_HAND_Z_UP, static=True)
    rec.log(paths.HOUSE_FLOOR, _parts_as_boxes([house.floor]), static=True)
    rec.log(paths.HOUSE_CEILING, _parts_as_boxes([house.ceiling]), static=True)
    rec.log(paths.HOUSE_WALLS, _parts_as_boxes(list(house.walls), WALL_ALPHA), static=True)
    parts = [part for piece in house.furniture for part in piece.parts]
    boxes = [p for p in parts if p.shape == "box"]
    cylinders = [p for p in parts if p.shape == "cylinder"]
    if boxes:
        rec.log(f"{paths.HOUSE_FURNITURE}/boxes", _parts_as_boxes(boxes), static=True)
    if cylinders:
        rec.log(f"{paths.HOUSE_FURNITURE}/cylinders", _parts_as_cylinders(cylinders), static=True)


def _pose_in(
    base_pos: np.ndarray, base_mat: np.ndarray, pos: np.ndarray, mat: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """A world pose (position, 3x3) expressed in a base frame: (position, quaternion xyzw)."""
    rel_mat = base_mat.T @ mat
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, rel_mat.ravel())
    return base_mat.T @ (pos - base_pos), np.roll(quat, -1)  # MuJoCo's wxyz to xyzw


def log_robot_body(
    rec: rr.RecordingStream, model: mujoco.MjModel, base_body_id: int, lidar_site_id: int
) -> None:
    """The robot's geoms in its base frame, and the LiDAR frame in the base frame (static).

    The geoms are taken from the compiled model at its reference pose; the wheels spin
    about their axis of symmetry, so their shape in the base frame does not change.
    """
    data = mujoco.MjData(model)  # a scratch state: the run's own data stays untouched
    mujoco.mj_kinematics(model, data)
    base_pos, base_mat = data.xpos[base_body_id], data.xmat[base_body_id].reshape(3, 3)
    shapes = defaultdict(lambda: defaultdict(list))
    for g in np.flatnonzero(model.geom_group == ROBOT_GEOM_GROUP):
        pos, quat = _pose_in(base_pos, base_mat, data.geom_xpos[g], data.geom_xmat[g].reshape(3, 3))
        mat_id = model.geom_matid[g]
        rgba = model.mat_rgba[mat_id] if mat_id >= 0 else model.geom_rgba[g]
        kind = mujoco.mjtGeom(model.geom_type[g])
        shape = shapes[kind]
        shape["centers"].append(pos)
        shape["quaternions"].append(rr.Quaternion(xyzw=quat))
        shape["colors"].append(_rgba(tuple(rgba)))
        shape["labels"].append(model.geom(g).name)
        size = model.geom_size[g]
        if kind == mujoco.mjtGeom.mjGEOM_CYLINDER:
            shape["radii"].append(size[0])
            shape["lengths"].append(2 * size[1])
        elif kind == mujoco.mjtGeom.mjGEOM_SPHERE:
            shape["half_sizes"].append((size[0],) * 3)
        else:
            shape["half_sizes"].append(size)
    archetypes = {
        mujoco.mjtGeom.mjGEOM_BOX: ("boxes", rr.Boxes3D),
        mujoco.mjtGeom.mjGEOM_CYLINDER: ("cylinders", rr.Cylinders3D),
        mujoco.mjtGeom.mjGEOM_ELLIPSOID: ("ellipsoids", rr.Ellipsoids3D),
        mujoco.mjtGeom.mjGEOM_SPHERE: ("spheres", rr.Ellipsoids3D),
    }
    for kind, fields in shapes.items():
        if kind not in archetypes:
            continue  # meshes and capsules: not in this robot
        name, archetype = archetypes[kind]
        rec.log(
            f"{paths.ROBOT_BODY}/{name}",
            archetype(**fields, show_labels=False, fill_mode="solid"),
            static=True,
        )
    site_mat = data.site_xmat[lidar_site_id].reshape(3, 3)
    pos, quat = _pose_in(base_pos, base_mat, data.site_xpos[lidar_site_id], site_mat)
    rec.log(
        paths.ROBOT_LIDAR,
        rr.Transform3D(translation=pos, quaternion=rr.Quaternion(xyzw=quat)),
        static=True,
    )
    rec.log(
        paths.SCAN_PLANE,
        rr.Cylinders3D(
            lengths=[0.0],
            radii=[SCAN_PLANE_RADIUS_M],
            colors=[(80, 160, 255, 35)],
            fill_mode="solid",
            labels=["scan plane"],
            show_labels=False,
        ),
        static=True,
    )


def log_sensor_view_frame(rec: rr.RecordingStream, range_max_m: float) -> None:
    """The sensor view's drawing frame, the robot's footprint and range rings (static).

    2D views draw y downwards; the sensor frame (x forward, y left) is turned so that
    forward points up and left points left. Points under ``sensor/lidar`` keep their true
    sensor-frame coordinates (shown on hover).
    """
    # drawing axes (right, down) from sensor axes: right = -y, down = -x
    rec.log(
        paths.SENSOR_FRAME,
        rr.Transform3D(mat3x3=[[0.0, -1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, -1.0]]),
        static=True,
    )
    angles = np.linspace(0.0, 2 * math.pi, 121)
    circle = np.column_stack((np.cos(angles), np.sin(angles)))
    radii = np.arange(RING_STEP_M, range_max_m + 1e-9, RING_STEP_M)
    rec.log(
        paths.SENSOR_RINGS,
        rr.LineStrips2D(
            [r * circle for r in radii],
            colors=[(70, 70, 70)],
            radii=-0.5,  # ui points
            labels=[f"{r:g} m" for r in radii],
            show_labels=False,
            draw_order=0.0,
        ),
        static=True,
    )
    rec.log(
        paths.SENSOR_ROBOT,
        rr.LineStrips2D(
            [[(-0.12, -0.17), (0.12, -0.17), (0.12, 0.17), (-0.12, 0.17), (-0.12, -0.17)],
             [(0.0, 0.0), (0.35, 0.0)]],
            colors=[(230, 230, 230)],
            radii=-1.0,
            labels=["robot", "heading (x)"],
            show_labels=False,
            draw_order=1.0,
        ),
        static=True,
    )  # fmt: skip
