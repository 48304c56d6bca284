"""The MuJoCo adapter: stabilizes an ``MjModel``/``MjData`` state in place.

``import constraint_stabilization.mujoco`` needs the optional dependency
``mujoco`` (``pip install ./python[mujoco]``); it is imported only here.

What becomes what
-----------------
Geoms are grouped by the body they are welded to (``model.body_weldid``):

* a group whose root body has exactly one joint, a **free** joint, and no
  jointed descendant, becomes one **dynamic** body: its pose is the free
  joint's ``qpos`` (the root body's frame, wxyz quaternion), its geoms the
  parts of one shape placed by their ``geom_pos``/``geom_quat`` (a
  compound when there are several or one is offset), its mass properties
  MuJoCo's own (``body_mass``, ``body_ipos``, ``body_iquat``,
  ``body_inertia``, summed over the welded bodies), not a uniform density;
* geoms of the world and of bodies welded to it are **fixed** bodies at
  their world poses;
* bodies on hinge, slide or ball joints (and free bodies with jointed
  descendants, or not attached to the world) are **held fixed** at their
  current world poses and listed in :attr:`MujocoResult.held_bodies` with
  the reason.

Geom types: ``box`` → cuboid (``size`` = half extents); ``mesh`` → the
convex hull of its vertices (``mesh_vert``; MuJoCo collides meshes as their
hulls, and its mesh vertices are already in the geom's frame); ``sphere``
→ sphere (``size[0]``); ``capsule`` → capsule along z (``size = [radius,
half_length]``, the library's convention); ``cylinder`` → cylinder along z
(``size = [radius, half_height]``; the library's circumscribed prism, never
smaller than the true cylinder); ``plane`` → a fixed box whose top face is
the plane, covering every other geom with a wide margin and as thick as it
is wide (the library has no half-space; the scene's tolerance scale comes
from the smallest dynamic body, so the big box does not loosen it).
Skipped, listed in :attr:`MujocoResult.skipped_geoms` with the reason:
ellipsoids, height fields, SDFs and any other type, and geoms that collide
with nothing (``contype == conaffinity == 0``, visual geoms; such a geom
on a moved body moves with it, as it would in MuJoCo). A dynamic body with
a skipped colliding geom is held fixed (the skipped geom would move with
it unseen), its other geoms staying obstacles.

Not modelled: MuJoCo's collision filters (``contype``/``conaffinity``
bit masks between colliding geoms, ``<exclude>`` pairs, the parent-child
rule: the library separates every pair of handled geoms), ``margin`` and
``gap``, and friction (the library's ``friction`` setting applies to
every contact; default frictionless).

The corrected poses are written into ``data.qpos`` (only for the bodies
that moved; every other number of ``qpos`` is left bit for bit), their
``qvel`` zeroed (``zero_velocities=True``, the default) or kept, and
``mj_forward`` is run so that ``data`` is consistent.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Tuple

import numpy as np

from ._api import Report, Scene, Shape, box, compound, hull, stabilize
from ._api import capsule as _capsule
from ._api import cylinder as _cylinder
from ._api import sphere as _sphere
from .errors import InputError

__all__ = ["MujocoScene", "MujocoResult", "scene_from_mujoco", "stabilize_mujoco"]

# The plane's box: half width = PLANE_COVER_FACTOR times the farthest
# reach of any other geom from the plane's origin (in the plane), plus
# PLANE_COVER_RADII bounding radii of the largest geom; as thick as wide.
PLANE_COVER_FACTOR = 2.0
PLANE_COVER_RADII = 4.0
# A plane box in a scene without other geoms.
PLANE_MIN_HALF_WIDTH = 1.0


def _mujoco() -> Any:
    try:
        import mujoco
    except ImportError as error:  # pragma: no cover - depends on the install
        raise ImportError(
            "constraint_stabilization.mujoco needs the mujoco package: "
            "pip install ./python[mujoco]"
        ) from error
    return mujoco


@dataclass
class MujocoScene:
    """A MuJoCo model as a library scene, with the maps back to MuJoCo."""

    scene: Scene
    # For each scene body: the MuJoCo body id it stands for (the weld
    # root for a dynamic body, the geom's body for a fixed one).
    body_ids: List[int]
    # For each scene body: the geoms it holds.
    geom_ids: List[List[int]]
    # For each dynamic scene body: (scene index, qpos address, dof address).
    free_joints: List[Tuple[int, int, int]]
    handled_geoms: List[int]
    skipped_geoms: List[Tuple[int, str, str]]
    held_bodies: List[Tuple[int, str, str]]
    # World poses (wxyz) of the fixed scene bodies, as built.
    fixed_poses: Dict[int, np.ndarray] = field(repr=False)

    def poses(self, data: Any) -> np.ndarray:
        """The scene's ``(n, 7)`` poses (wxyz) at ``data.qpos``: the
        dynamic bodies' from their free joints (quaternion normalized, as
        MuJoCo uses it), the fixed ones as built."""
        n = len(self.scene)
        poses = np.zeros((n, 7))
        for index, pose in self.fixed_poses.items():
            poses[index] = pose
        for index, qpos_adr, _ in self.free_joints:
            poses[index] = _normalized_pose(np.asarray(data.qpos[qpos_adr : qpos_adr + 7], dtype=float))
        return poses

    def write(self, data: Any, poses: np.ndarray, *, zero_velocities: bool = True) -> List[int]:
        """Writes the dynamic bodies' rows of ``poses`` (wxyz) that differ
        from :meth:`poses` into ``data.qpos`` (and zeroes their ``qvel``
        if asked); returns the MuJoCo ids of the bodies written."""
        before = self.poses(data)
        moved = []
        for index, qpos_adr, dof_adr in self.free_joints:
            if np.array_equal(poses[index], before[index]):
                continue
            data.qpos[qpos_adr : qpos_adr + 7] = poses[index]
            if zero_velocities:
                data.qvel[dof_adr : dof_adr + 6] = 0.0
            moved.append(self.body_ids[index])
        return moved


@dataclass
class MujocoResult:
    """What :func:`stabilize_mujoco` did."""

    report: Report
    # MuJoCo ids of the bodies whose qpos was changed.
    moved_bodies: List[int]
    # MuJoCo ids of the free bodies stabilized as dynamic bodies.
    dynamic_bodies: List[int]
    # Geoms represented in the library's scene.
    handled_geoms: List[int]
    # (geom id, name, reason) of each geom left out.
    skipped_geoms: List[Tuple[int, str, str]]
    # (body id, name, reason) of each body held where it was.
    held_bodies: List[Tuple[int, str, str]]

    @property
    def tolerance(self) -> float:
        """The absolute penetration tolerance of the call (model units)."""
        return self.report.tolerance


def _normalized_pose(row: np.ndarray) -> np.ndarray:
    q = row[3:7]
    norm = float(np.linalg.norm(q))
    if not np.isfinite(norm) or norm == 0.0 or not np.isfinite(row[:3]).all():
        raise InputError(f"free joint qpos {list(row)} is not a pose")
    out = row.copy()
    out[3:7] = q / norm
    return out


def _name(mj: Any, model: Any, kind: Any, index: int) -> str:
    return mj.mj_id2name(model, kind, index) or f"#{index}"


def _quat_of_mat(mj: Any, mat9: np.ndarray) -> np.ndarray:
    quat = np.zeros(4)
    mj.mju_mat2Quat(quat, np.ascontiguousarray(mat9, dtype=float))
    return quat


def _mat_of_quat(mj: Any, quat: np.ndarray) -> np.ndarray:
    mat = np.zeros(9)
    mj.mju_quat2Mat(mat, np.ascontiguousarray(quat, dtype=float))
    return mat.reshape(3, 3)


def _geom_shape(mj: Any, model: Any, g: int) -> Tuple[Optional[Shape], str]:
    """The library shape of geom ``g`` in its own frame, or why not."""
    kind = int(model.geom_type[g])
    size = np.asarray(model.geom_size[g], dtype=float)
    t = mj.mjtGeom
    if kind == t.mjGEOM_BOX:
        return box(size), ""
    if kind == t.mjGEOM_SPHERE:
        return _sphere(size[0]), ""
    if kind == t.mjGEOM_CAPSULE:
        return _capsule(size[0], size[1]), ""
    if kind == t.mjGEOM_CYLINDER:
        return _cylinder(size[0], size[1]), ""
    if kind == t.mjGEOM_MESH:
        mesh = int(model.geom_dataid[g])
        start, count = int(model.mesh_vertadr[mesh]), int(model.mesh_vertnum[mesh])
        return hull(np.asarray(model.mesh_vert[start : start + count], dtype=float)), ""
    names = {
        t.mjGEOM_ELLIPSOID: "ellipsoid",
        t.mjGEOM_HFIELD: "height field",
        t.mjGEOM_SDF: "sdf",
    }
    return None, f"{names.get(kind, f'geom type {kind}')} geoms are not supported"


def _plane_box(mj: Any, model: Any, data: Any, g: int, others: List[int]) -> Tuple[Shape, np.ndarray]:
    """The fixed box standing for plane geom ``g`` and its world pose
    (wxyz): top face on the plane, covering every geom of ``others``."""
    rotation = np.asarray(data.geom_xmat[g], dtype=float).reshape(3, 3)
    origin = np.asarray(data.geom_xpos[g], dtype=float)
    reach, radius = 0.0, 0.0
    for o in others:
        in_plane = rotation.T @ (np.asarray(data.geom_xpos[o], dtype=float) - origin)
        reach = max(reach, abs(in_plane[0]), abs(in_plane[1]), abs(in_plane[2]))
        radius = max(radius, float(model.geom_rbound[o]))
    half = max(PLANE_COVER_FACTOR * (reach + radius) + PLANE_COVER_RADII * radius, PLANE_MIN_HALF_WIDTH)
    centre = origin - half * rotation[:, 2]
    quat = _quat_of_mat(mj, rotation.reshape(9))
    return box([half, half, half]), np.concatenate([centre, quat])


def _group_mass(mj: Any, model: Any, data: Any, root: int, members: List[int]) -> Optional[Tuple[float, np.ndarray, np.ndarray]]:
    """MuJoCo's mass, centre of mass (root frame) and inertia about it
    (root axes) of the welded bodies ``members``; None if massless."""
    r_root = np.asarray(data.xmat[root], dtype=float).reshape(3, 3)
    x_root = np.asarray(data.xpos[root], dtype=float)
    items = []
    for b in members:
        m = float(model.body_mass[b])
        if m <= 0.0:
            continue
        if b == root:
            r_rel, p_rel = np.eye(3), np.zeros(3)
        else:
            r_rel = r_root.T @ np.asarray(data.xmat[b], dtype=float).reshape(3, 3)
            p_rel = r_root.T @ (np.asarray(data.xpos[b], dtype=float) - x_root)
        r_inertial = r_rel @ _mat_of_quat(mj, np.asarray(model.body_iquat[b], dtype=float))
        com = p_rel + r_rel @ np.asarray(model.body_ipos[b], dtype=float)
        inertia = r_inertial @ np.diag(np.asarray(model.body_inertia[b], dtype=float)) @ r_inertial.T
        items.append((m, com, inertia))
    if not items:
        return None
    mass = sum(m for m, _, _ in items)
    com = sum(m * c for m, c, _ in items) / mass
    inertia = np.zeros((3, 3))
    for m, c, i in items:
        d = c - com
        inertia += i + m * (np.dot(d, d) * np.eye(3) - np.outer(d, d))
    return mass, com, inertia


def scene_from_mujoco(model: Any, data: Any) -> MujocoScene:
    """The library scene of a MuJoCo model at ``data``'s state (runs
    ``mj_kinematics`` on ``data`` for the world poses of fixed geoms)."""
    mj = _mujoco()
    mj.mj_kinematics(model, data)
    obj = mj.mjtObj
    free = mj.mjtJoint.mjJNT_FREE
    joint_names = {int(v): n for n, v in [("free", mj.mjtJoint.mjJNT_FREE), ("ball", mj.mjtJoint.mjJNT_BALL), ("slide", mj.mjtJoint.mjJNT_SLIDE), ("hinge", mj.mjtJoint.mjJNT_HINGE)]}

    skipped: List[Tuple[int, str, str]] = []
    held: List[Tuple[int, str, str]] = []
    shapes: Dict[int, Shape] = {}
    planes: List[int] = []
    groups: Dict[int, List[int]] = {}
    for g in range(model.ngeom):
        name = _name(mj, model, obj.mjOBJ_GEOM, g)
        if model.geom_contype[g] == 0 and model.geom_conaffinity[g] == 0:
            skipped.append((g, name, "collides with nothing (contype = conaffinity = 0)"))
            continue
        if int(model.geom_type[g]) == mj.mjtGeom.mjGEOM_PLANE:
            planes.append(g)
            continue
        shape, reason = _geom_shape(mj, model, g)
        if shape is None:
            skipped.append((g, name, reason))
        else:
            shapes[g] = shape
        groups.setdefault(int(model.body_weldid[model.geom_bodyid[g]]), []).append(g)

    # Which weld groups move: free root, attached to the world, no jointed
    # descendant, every colliding geom supported.
    dynamic: Dict[int, int] = {}
    for root in sorted(groups):
        if root == 0:
            continue
        body_name = _name(mj, model, obj.mjOBJ_BODY, root)
        jnt_num, jnt_adr = int(model.body_jntnum[root]), int(model.body_jntadr[root])
        kinds = [int(model.jnt_type[j]) for j in range(jnt_adr, jnt_adr + jnt_num)]
        if kinds != [int(free)]:
            names = ", ".join(joint_names.get(k, str(k)) for k in kinds)
            held.append((root, body_name, f"on {names} joint(s): held fixed"))
            continue
        if model.body_parentid[root] != 0:
            held.append((root, body_name, "free joint below another body: held fixed"))
            continue
        jointed = [b for b in range(model.nbody) if model.body_rootid[b] == root and model.body_weldid[b] != root]
        if jointed:
            held.append((root, body_name, "has jointed descendants: held fixed"))
            continue
        unsupported = [g for g in groups[root] if g not in shapes]
        if unsupported:
            held.append((root, body_name, f"has unsupported geom {_name(mj, model, obj.mjOBJ_GEOM, unsupported[0])}: held fixed"))
            continue
        dynamic[root] = jnt_adr

    scene = Scene()
    body_ids: List[int] = []
    geom_ids: List[List[int]] = []
    free_joints: List[Tuple[int, int, int]] = []
    fixed_poses: Dict[int, np.ndarray] = {}
    handled: List[int] = []

    for root, joint in dynamic.items():
        geoms = groups[root]
        x_root = np.asarray(data.xpos[root], dtype=float)
        r_root = np.asarray(data.xmat[root], dtype=float).reshape(3, 3)
        parts, placements = [], []
        for g in geoms:
            if model.geom_bodyid[g] == root:
                placement = np.concatenate([model.geom_pos[g], model.geom_quat[g]]).astype(float)
            else:
                r_rel = r_root.T @ np.asarray(data.geom_xmat[g], dtype=float).reshape(3, 3)
                p_rel = r_root.T @ (np.asarray(data.geom_xpos[g], dtype=float) - x_root)
                placement = np.concatenate([p_rel, _quat_of_mat(mj, r_rel.reshape(9))])
            parts.append(shapes[g])
            placements.append(placement)
        identity = np.array([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0])
        if len(parts) == 1 and np.array_equal(placements[0], identity):
            shape = parts[0]
        else:
            shape = compound(parts, np.array(placements), quaternion_order="wxyz")
        members = [b for b in range(model.nbody) if model.body_weldid[b] == root]
        index = scene.add_body(shape, name=_name(mj, model, obj.mjOBJ_BODY, root))
        mass = _group_mass(mj, model, data, root, members)
        if mass is not None:
            scene.set_mass_properties(index, mass[0], list(mass[1]), mass[2])
        body_ids.append(root)
        geom_ids.append(list(geoms))
        free_joints.append((index, int(model.jnt_qposadr[joint]), int(model.jnt_dofadr[joint])))
        handled.extend(geoms)

    for root in sorted(groups):
        if root in dynamic:
            continue
        for g in groups[root]:
            if g not in shapes:
                continue
            pose = np.concatenate([np.asarray(data.geom_xpos[g], dtype=float), _quat_of_mat(mj, np.asarray(data.geom_xmat[g], dtype=float))])
            index = scene.add_body(shapes[g], fixed=True, name=_name(mj, model, obj.mjOBJ_GEOM, g))
            fixed_poses[index] = pose
            body_ids.append(int(model.geom_bodyid[g]))
            geom_ids.append([g])
            handled.append(g)

    others = [g for g in handled]
    for g in planes:
        shape, pose = _plane_box(mj, model, data, g, others)
        index = scene.add_body(shape, fixed=True, name=_name(mj, model, obj.mjOBJ_GEOM, g))
        fixed_poses[index] = pose
        body_ids.append(int(model.geom_bodyid[g]))
        geom_ids.append([g])
        handled.append(g)

    return MujocoScene(
        scene=scene,
        body_ids=body_ids,
        geom_ids=geom_ids,
        free_joints=free_joints,
        handled_geoms=sorted(handled),
        skipped_geoms=skipped,
        held_bodies=held,
        fixed_poses=fixed_poses,
    )


def stabilize_mujoco(model: Any, data: Any, *, zero_velocities: bool = True, forward: bool = True, **settings: Any) -> MujocoResult:
    """Removes the interpenetration of ``data``'s state in place (module
    docs): builds the scene, stabilizes it (``settings`` as for
    :func:`constraint_stabilization.stabilize`), writes the moved free
    bodies' poses into ``data.qpos``, zeroes their ``qvel`` unless
    ``zero_velocities=False``, and runs ``mj_forward`` unless
    ``forward=False``. On an error ``data.qpos`` is untouched."""
    mj = _mujoco()
    built = scene_from_mujoco(model, data)
    poses, report = stabilize(built.scene, built.poses(data), quaternion_order="wxyz", **settings)
    moved = built.write(data, poses, zero_velocities=zero_velocities)
    if forward:
        mj.mj_forward(model, data)
    return MujocoResult(
        report=report,
        moved_bodies=moved,
        dynamic_bodies=[built.body_ids[i] for i, _, _ in built.free_joints],
        handled_geoms=built.handled_geoms,
        skipped_geoms=built.skipped_geoms,
        held_bodies=built.held_bodies,
    )
