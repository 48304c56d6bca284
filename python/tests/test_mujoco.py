"""The MuJoCo adapter, with MuJoCo's own narrow phase as the oracle."""

from __future__ import annotations

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco")

import constraint_stabilization as cs  # noqa: E402
from constraint_stabilization.mujoco import scene_from_mujoco, stabilize_mujoco  # noqa: E402
from mujoco_scenes import bin_xml, random_overlapping_state  # noqa: E402

# The tolerance the adapter is asked for (and the report states): 0.1 mm
# on objects of 5 cm, far above MuJoCo's own narrow-phase accuracy.
TOLERANCE = 1e-4

KINDS = ["box", "mesh", "sphere", "capsule", "cylinder", "pair"] * 2 + ["ellipsoid"]

HINGED = """
<body name="door" pos="0 0 0.1"><joint name="hinge" type="hinge" axis="0 0 1"/>
  <geom name="door_leaf" type="box" size="0.04 0.01 0.04" pos="0.05 0 0"/></body>
"""


def contacts(model, data):
    for c in data.contact[: data.ncon]:
        yield int(c.geom1), int(c.geom2), float(c.dist)


def deepest(model, data, geoms):
    handled = set(geoms)
    dists = [d for g1, g2, d in contacts(model, data) if g1 in handled and g2 in handled]
    return min(dists, default=np.inf)


@pytest.mark.parametrize("seed", [1, 2])
def test_after_the_adapter_mujoco_finds_no_penetration(seed):
    model = mujoco.MjModel.from_xml_string(bin_xml(KINDS, seed=seed, extras=HINGED))
    data = mujoco.MjData(model)
    random_overlapping_state(model, data, seed=seed)
    assert deepest(model, data, range(model.ngeom)) < -5e-3
    qpos_before, qvel_before = data.qpos.copy(), data.qvel.copy()

    result = stabilize_mujoco(model, data, tolerance_absolute=TOLERANCE)

    assert result.report.converged, result.report.status
    assert result.tolerance == TOLERANCE
    mujoco.mj_forward(model, data)
    assert deepest(model, data, result.handled_geoms) >= -result.tolerance
    # Spheres, capsules, cylinders, meshes and boxes were all handled.
    handled_types = {int(model.geom_type[g]) for g in result.handled_geoms}
    for t in ["mjGEOM_SPHERE", "mjGEOM_CAPSULE", "mjGEOM_CYLINDER", "mjGEOM_MESH", "mjGEOM_BOX", "mjGEOM_PLANE"]:
        assert int(getattr(mujoco.mjtGeom, t)) in handled_types, t

    # Skipped: the ellipsoid (its body held fixed, its qpos untouched) and
    # the visual geom; the hinged door held, its hinge angle untouched.
    skipped = {name: reason for _, name, reason in result.skipped_geoms}
    assert "decor" in skipped and "collides with nothing" in skipped["decor"]
    assert any("ellipsoid" in reason for reason in skipped.values())
    held = {name: reason for _, name, reason in result.held_bodies}
    assert "hinge" in held["door"]
    ellipsoid_body = model.body(f"obj{len(KINDS) - 1}").id
    assert ellipsoid_body in {b for b, _, _ in result.held_bodies}
    for body in [ellipsoid_body, model.body("door").id]:
        j = model.body_jntadr[body]
        a, n = model.jnt_qposadr[j], (7 if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE else 1)
        assert np.array_equal(data.qpos[a : a + n], qpos_before[a : a + n])
    # Moved bodies have zero velocity; the others kept theirs.
    assert result.moved_bodies
    for body in result.dynamic_bodies:
        dof = model.jnt_dofadr[model.body_jntadr[body]]
        expected = 0.0 if body in result.moved_bodies else qvel_before[dof : dof + 6]
        assert np.array_equal(data.qvel[dof : dof + 6], np.broadcast_to(expected, (6,)))


def test_velocities_can_be_kept_and_a_clean_state_is_untouched():
    model = mujoco.MjModel.from_xml_string(bin_xml(["box", "sphere", "capsule"], seed=5))
    data = mujoco.MjData(model)
    random_overlapping_state(model, data, seed=5)
    qvel = data.qvel.copy()
    result = stabilize_mujoco(model, data, zero_velocities=False, tolerance_absolute=TOLERANCE)
    assert result.report.converged and result.moved_bodies
    assert np.array_equal(data.qvel, qvel)
    qpos = data.qpos.copy()
    again = stabilize_mujoco(model, data, tolerance_absolute=TOLERANCE)
    assert again.report.status == "nothing_to_do" and not again.moved_bodies
    assert np.array_equal(data.qpos, qpos)


def test_the_scene_mirrors_the_model():
    model = mujoco.MjModel.from_xml_string(bin_xml(["pair", "mesh", "cylinder"], seed=4))
    data = mujoco.MjData(model)
    random_overlapping_state(model, data, seed=4)
    built = scene_from_mujoco(model, data)
    # 3 free bodies, 4 walls, the plane's box.
    assert len(built.scene) == 8 and sum(built.scene.fixed) == 5
    # MuJoCo's masses, not a uniform density.
    masses = [m for m in built.scene.masses if m is not None]
    expected = [model.body_mass[model.body(f"obj{i}").id] for i in range(3)]
    assert masses == pytest.approx(expected, rel=1e-12)
    # The plane's box is far larger than anything, but the tolerance scale
    # is the smallest dynamic body's.
    assert built.scene.scale < 0.1
    # Poses in and out of MuJoCo's wxyz order are exact.
    poses = built.poses(data)
    for index, adr, _ in built.free_joints:
        q = data.qpos[adr : adr + 7]
        assert np.allclose(poses[index], q / np.r_[1, 1, 1, [np.linalg.norm(q[3:])] * 4], rtol=0, atol=1e-15)


def test_batch_from_a_mujoco_model():
    model = mujoco.MjModel.from_xml_string(bin_xml(["box", "mesh", "sphere", "capsule"], seed=6))
    data = mujoco.MjData(model)
    built = scene_from_mujoco(model, data)
    layouts = []
    for seed in range(3):
        random_overlapping_state(model, data, seed=10 + seed)
        layouts.append(built.poses(data))
    result = cs.stabilize_batch(built.scene, np.stack(layouts), quaternion_order="wxyz", threads=2, tolerance_absolute=TOLERANCE)
    assert result.converged.all()
    for layout in result.poses:
        built.write(data, layout)
        mujoco.mj_forward(model, data)
        assert deepest(model, data, built.handled_geoms) >= -TOLERANCE
