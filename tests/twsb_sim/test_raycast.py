"""The compiled caster answers as ``mujoco.mj_multiRay`` does: the same geom, distance and
normal for every ray, the same geoms left out, and MuJoCo itself for what it does not
cover (meshes)."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from twsb_sim.house import add_house_to_spec, random_house
from twsb_sim.raycast import RayCaster

TOLERANCE = 1e-9  # m, and for the normals' components
GT = mujoco.mjtGeom
NO_ROBOT = np.array([1, 1, 1, 0, 1, 1], dtype=np.uint8)  # the LiDAR's geom groups


def _mujoco(model, data, origin, dirs, geomgroup, cutoff, flg_static=True, bodyexclude=-1):
    n = len(dirs)
    ids, dist, normals = np.empty(n, np.int32), np.empty(n), np.empty(3 * n)
    mujoco.mj_multiRay(
        model, data, origin, dirs.reshape(-1), geomgroup, flg_static, bodyexclude, ids, dist,
        normals, n, cutoff,
    )  # fmt: skip
    return ids, dist, normals


def _ours(caster, data, origin, dirs, cutoff):
    n = len(dirs)
    ids, dist, normals = np.full(n, 7, np.int32), np.full(n, 7.0), np.full(3 * n, 7.0)
    caster.cast(data, origin, dirs, ids, dist, normals, cutoff)
    return ids, dist, normals


def _assert_same(model, data, origin, dirs, geomgroup=None, cutoff=12.0, **flags):
    caster = RayCaster(model, geomgroup, **flags)
    assert caster.compiled
    expected = _mujoco(model, data, origin, dirs, geomgroup, cutoff, **flags)
    got = _ours(caster, data, origin, dirs, cutoff)
    np.testing.assert_array_equal(got[0], expected[0])
    np.testing.assert_allclose(got[1], expected[1], rtol=0, atol=TOLERANCE)
    np.testing.assert_allclose(got[2], expected[2], rtol=0, atol=TOLERANCE)
    return got


def _directions(rng, n, flat=False):
    dirs = rng.normal(size=(n, 3))
    if flat:  # a tilted scan fan, as a pitching LiDAR casts
        dirs[:, 2] = rng.normal(scale=0.2) * dirs[:, 0]
    return dirs / np.linalg.norm(dirs, axis=1, keepdims=True)


@pytest.mark.parametrize("kind", ["sphere", "capsule", "ellipsoid", "cylinder", "box", "plane"])
def test_one_geom_of_each_type(kind):
    spec = mujoco.MjSpec()
    body = spec.worldbody.add_body(name="mover", pos=[0.3, -0.2, 0.5], quat=[0.9, 0.3, 0.2, 0.1])
    if kind != "plane":  # planes only sit on static bodies
        body.add_joint(type=mujoco.mjtJoint.mjJNT_FREE)
    size = [0.0, 0.0, 0.1] if kind == "plane" else [0.4, 0.25, 0.6]
    body.add_geom(name=kind, type=getattr(GT, f"mjGEOM_{kind.upper()}"), size=size)
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    rng = np.random.default_rng(len(kind))
    centre = data.geom_xpos[0]
    hits = 0
    offsets = np.array([[0.05, 0.05, 0.05], [1.5, 0, 0], [0, -2, -1], [0, 0, 3]])  # m
    for origin in centre + offsets:  # inside, then outside
        aims = centre + rng.normal(scale=0.4, size=(400, 3)) - origin  # hit, graze and miss
        dirs = np.concatenate((aims, _directions(rng, 100)))
        ids = _assert_same(model, data, origin, dirs)[0]
        hits += np.count_nonzero(ids == 0)
    assert 300 < hits < 1900


@pytest.fixture(scope="module")
def house_scene():
    """A generated house with a tilted plane, a mover of each round type and the robot's
    geom group in the way."""
    spec = mujoco.MjSpec()
    add_house_to_spec(spec, random_house(3))
    spec.worldbody.add_geom(
        name="ramp", type=GT.mjGEOM_PLANE, size=[1.0, 0.6, 0.1], pos=[2.0, 2.0, 0.2],
        euler=[0.3, -0.2, 0.4],
    )  # fmt: skip
    spec.worldbody.add_geom(
        name="slope", type=GT.mjGEOM_PLANE, size=[0, 0, 0.1], pos=[0, 0, 2.3], euler=[0.1, 3.0, 0]
    )
    person = spec.worldbody.add_body(name="person", mocap=True, pos=[3.0, 3.0, 0.9])
    for k, kind in enumerate(("CAPSULE", "ELLIPSOID", "CYLINDER", "SPHERE")):
        person.add_geom(
            name=f"part_{k}", type=getattr(GT, f"mjGEOM_{kind}"), size=[0.15, 0.3, 0.2],
            pos=[0.0, 0.4 * k - 0.6, 0.0], euler=[0.5 * k, 0.2, 0.0],
        )  # fmt: skip
    spec.worldbody.add_geom(name="robot_shell", type=GT.mjGEOM_SPHERE, size=[0.3], group=3)
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return model, data


@pytest.mark.parametrize("cutoff", [12.0, 2.0])
def test_a_house_from_many_origins(house_scene, cutoff):
    model, data = house_scene
    rng = np.random.default_rng(int(cutoff))
    floor = model.geom("floor").id
    low = data.geom_xpos[floor] - model.geom_size[floor]
    high = data.geom_xpos[floor] + model.geom_size[floor]
    found = set()
    for k in range(40):
        origin = rng.uniform(low, high)
        origin[2] = rng.uniform(0.05, 2.3)
        dirs = _directions(rng, 480, flat=k % 2 == 0)
        ids = _assert_same(model, data, origin, dirs, NO_ROBOT, cutoff)[0]
        found.update(ids.tolist())
    named = {mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, g) for g in found if g >= 0}
    assert {"floor", "ramp", "slope", "part_0", "part_1", "part_2", "part_3"} <= named
    assert "robot_shell" not in named


def _eligibility_scene():
    """Boxes one behind the other along +x, each left out of rays by one rule but the last."""
    spec = mujoco.MjSpec()
    hidden = spec.add_material(name="hidden", rgba=[1, 1, 1, 0])
    shown = spec.add_material(name="shown", rgba=[1, 1, 1, 1])
    wall = {"type": GT.mjGEOM_BOX, "size": [0.05, 1.0, 1.0]}
    spec.worldbody.add_geom(name="robot", pos=[1, 0, 0], group=3, **wall)
    spec.worldbody.add_geom(name="clear", pos=[2, 0, 0], rgba=[1, 1, 1, 0], **wall)
    spec.worldbody.add_geom(name="clear_material", pos=[3, 0, 0], material=hidden.name, **wall)
    body = spec.worldbody.add_body(name="door", pos=[4, 0, 0])
    body.add_joint(type=mujoco.mjtJoint.mjJNT_SLIDE)
    body.add_geom(name="moving", **wall)
    spec.worldbody.add_geom(name="painted", pos=[5, 0, 0], rgba=[1, 1, 1, 0],
                            material=shown.name, **wall)  # fmt: skip
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return model, data


@pytest.mark.parametrize(
    ("flags", "first"),
    [
        ({"geomgroup": NO_ROBOT}, "moving"),  # robot group, rgba and material alpha 0 out
        ({"geomgroup": None}, "robot"),  # no group mask: the robot's geom too
        ({"geomgroup": NO_ROBOT, "flg_static": False}, "moving"),
        ({"geomgroup": NO_ROBOT, "flg_static": False, "bodyexclude": 1}, None),
        ({"geomgroup": NO_ROBOT, "bodyexclude": 1}, "painted"),  # a material's alpha counts
        ({"geomgroup": np.array([0, 1, 1, 0, 1, 1], np.uint8)}, None),  # group 0: nothing
    ],
)
def test_which_geoms_rays_see(flags, first):
    model, data = _eligibility_scene()
    dirs = np.array([[1.0, 0.0, 0.0], [1.0, 0.01, 0.02], [1.0, -0.15, 0.1]])
    ids = _assert_same(model, data, np.zeros(3), dirs, **flags)[0]
    names = {mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, g) if g >= 0 else None
             for g in ids}  # fmt: skip
    assert names == {first}


def test_cutoff_leaves_out_far_geoms_but_never_planes():
    spec = mujoco.MjSpec()
    spec.worldbody.add_geom(name="floor", type=GT.mjGEOM_PLANE, size=[50, 50, 0.1], pos=[40, 0, 0])
    spec.worldbody.add_geom(name="far", type=GT.mjGEOM_BOX, size=[0.5, 2, 2], pos=[10, 0, 1])
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    dirs = np.array([[1.0, 0.0, 0.0], [1.0, 0.0, -0.1]])
    origin = np.array([0.0, 0.0, 1.0])
    ids, dist, normals = _assert_same(model, data, origin, dirs, cutoff=3.0)
    assert ids.tolist() == [-1, 0]  # the box is beyond 3 m + its bound; the floor is not
    assert dist.tolist() == [-1.0, pytest.approx(10.0)]  # in units of the direction's length
    assert normals.tolist()[:3] == [0, 0, 0]
    ids = _assert_same(model, data, origin, dirs, cutoff=12.0)[0]
    assert ids.tolist() == [1, 1]


def test_a_mesh_geom_is_cast_by_mujoco():
    spec = mujoco.MjSpec()
    vertices = [0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1]
    spec.add_mesh(name="tetra", uservert=vertices)
    spec.worldbody.add_geom(name="rock", type=GT.mjGEOM_MESH, meshname="tetra", pos=[2, 0, 0])
    spec.worldbody.add_geom(
        name="wall", type=GT.mjGEOM_BOX, size=[0.1, 2, 2], pos=[4, 0, 0], group=1
    )
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    caster = RayCaster(model)
    assert not caster.compiled
    dirs = _directions(np.random.default_rng(0), 200, flat=True)
    dirs[:, 0] = np.abs(dirs[:, 0])
    got = _ours(caster, data, np.array([0.0, 0.1, 0.1]), dirs, 12.0)
    expected = _mujoco(model, data, np.array([0.0, 0.1, 0.1]), dirs, None, 12.0)
    for a, b in zip(got, expected, strict=True):
        np.testing.assert_array_equal(a, b)
    assert {0, 1} <= set(got[0].tolist())
    # in a geom group rays do not see, the mesh needs no MuJoCo
    assert RayCaster(model, np.array([0, 1, 1, 1, 1, 1], np.uint8)).compiled


def test_a_ray_of_no_length_hits_nothing():
    spec = mujoco.MjSpec()
    spec.worldbody.add_geom(name="ball", type=GT.mjGEOM_SPHERE, size=[1.0])
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    short = np.array([[0.0, 0.0, 0.0], [1e-8, 0.0, 0.0], [1e-7, 0.0, 0.0]])  # 1e-15 squared
    ids, dist, normals = _assert_same(model, data, np.zeros(3), short)
    assert ids.tolist() == [-1, -1, 0] and dist.tolist()[:2] == [-1, -1]
    assert not normals[:6].any()
