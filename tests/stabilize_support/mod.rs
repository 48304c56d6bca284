//! Shared helpers of the `stabilize_*` integration tests: scene builders,
//! bit-exact pose snapshots, and the penetration oracle.
//!
//! The oracle is parry3d-f64's `query::contact` (GJK/EPA), which this project
//! did not write, backed by a brute-force separating-axis depth written here
//! (parry's EPA under-reports on coincident faces): the residual of a scene
//! is the largest depth over every pair of bodies with at least one dynamic
//! body (pairs of fixed bodies cannot be corrected and are skipped). Pairs
//! whose AABBs (from the exact world vertices) are disjoint cannot
//! penetrate and are skipped too.

#![allow(dead_code)]

#[path = "../sat_support/mod.rs"]
mod sat;

use constraint_stabilization::body::{BodyDesc, MassSpec, Shape};
use constraint_stabilization::geometry::ConvexPolyhedron;
use constraint_stabilization::geometry::isometry_to_parry;
use constraint_stabilization::scene::Scene;
use constraint_stabilization::{Report, Settings, Stabilizer};
use nalgebra::{Isometry3, Matrix3, Point3, UnitQuaternion, Vector3};
use parry3d_f64::query;
use parry3d_f64::shape::ConvexPolyhedron as ParryPolyhedron;

/// The identity rotation `[x, y, z, w]`.
pub const IDENTITY_XYZW: [f64; 4] = [0.0, 0.0, 0.0, 1.0];

/// A body description of `shape` placed by its shape frame.
pub fn body(
    name: &str,
    shape: Shape,
    translation: [f64; 3],
    rotation_xyzw: [f64; 4],
    mass: MassSpec,
) -> BodyDesc {
    BodyDesc {
        name: name.into(),
        shape,
        translation: Vector3::from(translation),
        rotation_xyzw,
        mass,
    }
}

/// A body description of a box.
pub fn cuboid(
    name: &str,
    half_extents: [f64; 3],
    translation: [f64; 3],
    rotation_xyzw: [f64; 4],
    mass: MassSpec,
) -> BodyDesc {
    let half_extents = Vector3::from(half_extents);
    body(
        name,
        Shape::Cuboid { half_extents },
        translation,
        rotation_xyzw,
        mass,
    )
}

/// The fixed ground of the scenes: a slab whose top face is the plane
/// `y = 0`.
pub fn ground() -> BodyDesc {
    cuboid(
        "ground",
        [20.0, 0.5, 20.0],
        [0.0, -0.5, 0.0],
        IDENTITY_XYZW,
        MassSpec::Fixed,
    )
}

/// A unit cube of mass 1, face down on [`ground`], sunk by `depth`.
pub fn unit_cube_sunk(name: &str, depth: f64) -> BodyDesc {
    cuboid(
        name,
        [0.5, 0.5, 0.5],
        [0.0, 0.5 - depth, 0.0],
        IDENTITY_XYZW,
        MassSpec::Mass(1.0),
    )
}

/// A body description of a convex hull.
pub fn hull(
    name: &str,
    points: Vec<Point3<f64>>,
    translation: [f64; 3],
    rotation_xyzw: [f64; 4],
    mass: MassSpec,
) -> BodyDesc {
    body(
        name,
        Shape::ConvexHull { points },
        translation,
        rotation_xyzw,
        mass,
    )
}

/// `[x, y, z, w]` of a unit quaternion.
pub fn xyzw(rotation: &UnitQuaternion<f64>) -> [f64; 4] {
    let q = rotation.quaternion();
    [q.i, q.j, q.k, q.w]
}

/// A description scaled by `s` about the world origin: translation, box
/// half extents and hull points times `s`; masses times `s^3` (density
/// unchanged), so that the mass-weighted problem is the same up to scale.
pub fn scaled(desc: &BodyDesc, s: f64) -> BodyDesc {
    let shape = match &desc.shape {
        Shape::Cuboid { half_extents } => Shape::Cuboid {
            half_extents: half_extents * s,
        },
        Shape::ConvexHull { points } => Shape::ConvexHull {
            points: points.iter().map(|p| p * s).collect(),
        },
        Shape::Compound { .. } => panic!("scaled: convex shapes only"),
    };
    let mass = match desc.mass {
        MassSpec::Mass(m) => MassSpec::Mass(m * s * s * s),
        other => other,
    };
    BodyDesc {
        name: desc.name.clone(),
        shape,
        translation: desc.translation * s,
        rotation_xyzw: desc.rotation_xyzw,
        mass,
    }
}

/// Builds a scene from descriptions (panics on an invalid one: the tests
/// build valid scenes).
pub fn scene_of(descs: &[BodyDesc]) -> Scene {
    let mut scene = Scene::new();
    for desc in descs {
        scene.add_body(desc.clone()).expect("test bodies are valid");
    }
    scene
}

/// Every user pose as raw f64 bits: translation then rotation `[x, y, z, w]`.
pub type PoseBits = [u64; 7];

/// The user poses of all bodies, bit for bit.
pub fn pose_bits(scene: &Scene) -> Vec<PoseBits> {
    scene
        .bodies()
        .iter()
        .map(|b| {
            let t = b.translation_user();
            let q = b.rotation_user_xyzw();
            [
                t.x.to_bits(),
                t.y.to_bits(),
                t.z.to_bits(),
                q[0].to_bits(),
                q[1].to_bits(),
                q[2].to_bits(),
                q[3].to_bits(),
            ]
        })
        .collect()
}

/// Asserts that the bodies `indices` have exactly the poses of `before`.
pub fn assert_untouched(scene: &Scene, before: &[PoseBits], indices: &[usize]) {
    let now = pose_bits(scene);
    for &i in indices {
        assert_eq!(
            now[i],
            before[i],
            "body {i} ({}) moved but must be bit-identical",
            scene.bodies()[i].name()
        );
    }
}

/// The bodies of every island solved in some pass of `report`.
pub fn solved_bodies(report: &Report) -> std::collections::BTreeSet<usize> {
    report
        .pass_reports
        .iter()
        .flat_map(|p| &p.solved)
        .flat_map(|island| island.bodies.iter().copied())
        .collect()
}

/// Asserts that no pose component is NaN or infinite.
pub fn assert_finite(scene: &Scene) {
    for body in scene.bodies() {
        let finite = body.translation_user().iter().all(|c| c.is_finite())
            && body.rotation_user_xyzw().iter().all(|c| c.is_finite());
        assert!(finite, "body {} has a non-finite pose", body.name());
    }
}

/// Penetration of one pair by parry (`-dist`, 0 when separated; the
/// deepest over the part pairs of compound bodies).
pub fn parry_pair_depth(scene: &Scene, shapes: &[Vec<ParryPolyhedron>], a: usize, b: usize) -> f64 {
    let poses = |body: usize| -> Vec<_> {
        scene.bodies()[body]
            .part_poses()
            .map(|p| isometry_to_parry(&p))
            .collect()
    };
    let (poses_a, poses_b) = (poses(a), poses(b));
    let mut deepest: f64 = 0.0;
    for (shape_a, pose_a) in shapes[a].iter().zip(&poses_a) {
        for (shape_b, pose_b) in shapes[b].iter().zip(&poses_b) {
            let depth = query::contact(pose_a, shape_a, pose_b, shape_b, 0.0)
                .expect("parry supports convex polyhedra")
                .map_or(0.0, |c| (-c.dist).max(0.0));
            deepest = deepest.max(depth);
        }
    }
    deepest
}

/// The parry shapes of every part of every body (part frame, origin at
/// the part's COM).
pub fn parry_shapes(scene: &Scene) -> Vec<Vec<ParryPolyhedron>> {
    scene
        .bodies()
        .iter()
        .map(|b| {
            b.parts()
                .iter()
                .map(|part| {
                    part.polyhedron()
                        .to_parry()
                        .expect("parry accepts our hulls")
                })
                .collect()
        })
        .collect()
}

/// The deepest penetration of the scene and the pair it is in: for every
/// pair, the larger of parry's EPA depth and the brute-force separating-axis
/// depth [`sat_depth`]. parry alone is not enough: on coincident faces its
/// EPA can return less than the true depth (two unit boxes offset by 0.01
/// along a face: parry 0.57, true 0.99), which would hide a residual.
pub fn penetration_residual(scene: &Scene) -> (f64, Option<(usize, usize)>) {
    let shapes = parry_shapes(scene);
    deepest_over_pairs(scene, |a, b| {
        parry_pair_depth(scene, &shapes, a, b).max(sat_depth(scene, a, b))
    })
}

/// The deepest brute-force separating-axis depth [`sat_depth`] of the
/// scene and the pair it is in (no parry): the exact deepest penetration.
pub fn sat_deepest(scene: &Scene) -> (f64, Option<(usize, usize)>) {
    deepest_over_pairs(scene, |a, b| sat_depth(scene, a, b))
}

/// The largest `depth(a, b)` over the pairs `a < b` with a dynamic body
/// whose world AABBs (from the exact world vertices) overlap, and the pair.
fn deepest_over_pairs(
    scene: &Scene,
    depth: impl Fn(usize, usize) -> f64,
) -> (f64, Option<(usize, usize)>) {
    let aabbs: Vec<_> = scene.bodies().iter().map(|b| b.world_aabb()).collect();
    let overlap = |a: usize, b: usize| {
        let ((min_a, max_a), (min_b, max_b)) = (aabbs[a], aabbs[b]);
        (0..3).all(|k| min_a[k] <= max_b[k] && min_b[k] <= max_a[k])
    };
    let mut worst = (0.0, None);
    for a in 0..scene.len() {
        for b in a + 1..scene.len() {
            let both_fixed = scene.bodies()[a].is_fixed() && scene.bodies()[b].is_fixed();
            if both_fixed || !overlap(a, b) {
                continue;
            }
            let d = depth(a, b);
            if d > worst.0 {
                worst = (d, Some((a, b)));
            }
        }
    }
    worst
}

/// Penetration depth of bodies `a` and `b` by the separating axis theorem,
/// by brute force: the smallest overlap of the projections of the world
/// vertices over every face normal of both bodies and every cross product
/// of an edge of `a` with an edge of `b` (0 when some axis separates). For
/// convex polyhedra this minimum is the exact penetration depth.
/// Over the part pairs of compound bodies, the deepest.
pub fn sat_depth(scene: &Scene, a: usize, b: usize) -> f64 {
    let (body_a, body_b) = (&scene.bodies()[a], &scene.bodies()[b]);
    let mut deepest: f64 = 0.0;
    for (part_a, pose_a) in body_a.parts().iter().zip(body_a.part_poses()) {
        for (part_b, pose_b) in body_b.parts().iter().zip(body_b.part_poses()) {
            let overlap = sat_overlap(part_a.polyhedron(), &pose_a, part_b.polyhedron(), &pose_b);
            deepest = deepest.max(overlap);
        }
    }
    deepest
}

/// The smallest overlap of the projections of two posed polyhedra over
/// every face normal of both and every cross product of an edge of each
/// (brute force, [`sat::sat_axes`]): the exact penetration depth when
/// positive; when negative, some axis separates the bodies (by at least
/// that gap).
pub fn sat_overlap(
    poly_a: &ConvexPolyhedron,
    pose_a: &Isometry3<f64>,
    poly_b: &ConvexPolyhedron,
    pose_b: &Isometry3<f64>,
) -> f64 {
    sat::sat_axes(poly_a, pose_a, poly_b, pose_b).all
}

/// [`sat_overlap`] and the axis that realizes it, oriented from B towards A
/// (translating A by the overlap along it makes the bodies touch).
pub fn sat_axis(
    poly_a: &ConvexPolyhedron,
    pose_a: &Isometry3<f64>,
    poly_b: &ConvexPolyhedron,
    pose_b: &Isometry3<f64>,
) -> (f64, Vector3<f64>) {
    let axes = sat::sat_axes(poly_a, pose_a, poly_b, pose_b);
    (axes.all, axes.axis)
}

/// FNV-1a over the bits of every user pose.
pub fn pose_hash(scene: &Scene) -> u64 {
    pose_bits(scene)
        .iter()
        .flatten()
        .fold(0xcbf2_9ce4_8422_2325, |h, &bits| {
            (h ^ bits).wrapping_mul(0x0000_0100_0000_01b3)
        })
}

/// Stabilizes with `settings`, checks that no pose became non-finite and
/// returns the report and the residual ([`penetration_residual`]).
pub fn stabilize_with(scene: &mut Scene, settings: Settings) -> (Report, f64) {
    let mut stabilizer = Stabilizer::new(settings).expect("valid settings");
    let report = stabilizer.stabilize(scene).expect("stabilization succeeds");
    assert_finite(scene);
    let (residual, _) = penetration_residual(scene);
    (report, residual)
}

/// [`stabilize_with`] the default settings.
pub fn stabilize_default(scene: &mut Scene) -> (Report, f64) {
    stabilize_with(scene, Settings::default())
}

/// One line describing a run, printed by the tests (`--nocapture`) so that
/// the figures of the report can be reproduced.
pub fn describe(label: &str, report: &Report, residual: f64) -> String {
    format!(
        "{label}: {} passes {} islands {} depth {:.3e} -> {:.3e} residual {:.3e} tol {:.3e} displacement {:.6e} moved {}",
        report.status.name(),
        report.passes,
        report.islands_solved(),
        report.depth_before,
        report.depth_after,
        residual,
        report.tolerance,
        report.displacement,
        report.bodies_moved
    )
}

/// A far-away pair that must not be touched: two unit boxes side by side
/// along x with a gap of `gap` (within the contact margin when small, so
/// they form an island of their own that does not penetrate), centred at
/// `at`. Returns the two descriptions.
pub fn bystander_pair(at: [f64; 3], gap: f64) -> [BodyDesc; 2] {
    let h = 0.5;
    [
        cuboid(
            "bystander_a",
            [h, h, h],
            [at[0] - h - gap / 2.0, at[1], at[2]],
            IDENTITY_XYZW,
            MassSpec::Mass(1.0),
        ),
        cuboid(
            "bystander_b",
            [h, h, h],
            [at[0] + h + gap / 2.0, at[1], at[2]],
            IDENTITY_XYZW,
            MassSpec::Mass(1.0),
        ),
    ]
}

/// World-frame inverse inertia of a solid box of `mass` and `half_extents`
/// turned by `rotation`, in closed form (`I = m/3 diag(b^2 + c^2, a^2 + c^2,
/// a^2 + b^2)` for half extents `a, b, c`), not from the library.
pub fn cuboid_inverse_inertia_world(
    mass: f64,
    half_extents: &Vector3<f64>,
    rotation: &UnitQuaternion<f64>,
) -> Matrix3<f64> {
    let [a2, b2, c2] = [0, 1, 2].map(|k| half_extents[k] * half_extents[k]);
    let inverse_body = Matrix3::from_diagonal(&Vector3::new(
        3.0 / (mass * (b2 + c2)),
        3.0 / (mass * (a2 + c2)),
        3.0 / (mass * (a2 + b2)),
    ));
    let r = rotation.to_rotation_matrix();
    r.matrix() * inverse_body * r.matrix().transpose()
}

/// A dynamic body's part in one contact row: its inverse mass, world
/// inverse inertia and centre of mass, and the side of the row it is on
/// (`+1` for the body the normal points towards, `-1` for the other).
pub struct RowMember {
    /// `1 / m`.
    pub inverse_mass: f64,
    /// World-frame `I^-1`.
    pub inverse_inertia: Matrix3<f64>,
    /// Centre of mass, world frame.
    pub centre: Vector3<f64>,
    /// `+1` or `-1`.
    pub side: f64,
}

impl RowMember {
    /// A dynamic box: mass, half extents, and its pose (centre, rotation).
    pub fn cuboid(
        mass: f64,
        half_extents: [f64; 3],
        centre: Vector3<f64>,
        rotation: &UnitQuaternion<f64>,
        side: f64,
    ) -> Self {
        let half_extents = Vector3::from(half_extents);
        RowMember {
            inverse_mass: 1.0 / mass,
            inverse_inertia: cuboid_inverse_inertia_world(mass, &half_extents, rotation),
            centre,
            side,
        }
    }
}

/// A body's correction: translation and world rotation vector.
#[derive(Debug, Clone, Copy)]
pub struct Correction {
    /// `dx`.
    pub dx: Vector3<f64>,
    /// `dtheta` (the body turns by `exp(dtheta)`).
    pub dtheta: Vector3<f64>,
}

/// The minimal correction for one contact row, derived here (DESIGN.md
/// section 3): the row at world point `point` with unit normal `normal` has
/// `J_i = side_i [n^T, (r_i x n)^T]` with `r_i = point - centre_i`, and
/// `dq = M^-1 J^T lambda`, `lambda = (target - phi) / (J M^-1 J^T)`.
/// Fixed bodies have no columns: leave them out of `members`.
pub fn one_row_correction(
    members: &[RowMember],
    point: &Vector3<f64>,
    normal: &Vector3<f64>,
    phi: f64,
    target: f64,
) -> Vec<Correction> {
    let columns: Vec<(Vector3<f64>, Vector3<f64>)> = members
        .iter()
        .map(|m| {
            let r_cross_n = (point - m.centre).cross(normal);
            (
                normal * (m.side * m.inverse_mass),
                m.inverse_inertia * r_cross_n * m.side,
            )
        })
        .collect();
    let effective: f64 = members
        .iter()
        .zip(&columns)
        .map(|(m, (dx, dtheta))| {
            m.side * (normal.dot(dx) + (point - m.centre).cross(normal).dot(dtheta))
        })
        .sum();
    let lambda = (target - phi) / effective;
    columns
        .into_iter()
        .map(|(dx, dtheta)| Correction {
            dx: dx * lambda,
            dtheta: dtheta * lambda,
        })
        .collect()
}

/// A bound on the second-order remainder of a one-row linearization over
/// the correction: every second-order term of `phi(q + dq)` is a rotation
/// times the displacement of a point (the contact point of a body, or the
/// face normal turning while the points move apart), so it is at most
/// `(sum |dtheta_i|) * (sum |dx_i| + |r_i| |dtheta_i|)` with `|r_i|` the
/// lever of body `i`. Later passes remove at most this much penetration.
pub fn second_order_remainder(corrections: &[Correction], levers: &[f64]) -> f64 {
    let turn: f64 = corrections.iter().map(|c| c.dtheta.norm()).sum();
    let reach: f64 = corrections
        .iter()
        .zip(levers)
        .map(|(c, lever)| c.dx.norm() + lever * c.dtheta.norm())
        .sum();
    turn * reach
}

/// A body's motion between two poses: translation of the centre of mass
/// and the world rotation vector of `R_after R_before^-1`.
pub fn motion(before: &Isometry3<f64>, after: &Isometry3<f64>) -> Correction {
    Correction {
        dx: after.translation.vector - before.translation.vector,
        dtheta: (after.rotation * before.rotation.inverse()).scaled_axis(),
    }
}

/// World positions of a body's vertices.
pub fn world_vertices(scene: &Scene, index: usize) -> Vec<Vector3<f64>> {
    let body = &scene.bodies()[index];
    body.parts()
        .iter()
        .zip(body.part_poses())
        .flat_map(|(part, pose)| {
            part.polyhedron()
                .vertices()
                .iter()
                .map(move |v| (pose * v).coords)
                .collect::<Vec<_>>()
        })
        .collect()
}

/// The body's vertices sorted by their height along `direction`, lowest
/// first.
pub fn vertices_by_height(
    scene: &Scene,
    index: usize,
    direction: &Vector3<f64>,
) -> Vec<Vector3<f64>> {
    let mut vertices = world_vertices(scene, index);
    vertices.sort_by(|p, q| direction.dot(p).total_cmp(&direction.dot(q)));
    vertices
}

/// How many times [`second_order_remainder`] (relative to the first-order
/// push `target - phi`) a body's motion may differ from the one-row closed
/// form, relative to that motion: later passes (or the rest of a shortened
/// line-search step) remove a leftover penetration of at most the
/// remainder, along nearly the same row, so they scale the closed form by
/// at most that fraction; twice that covers the change of the row between
/// passes (itself first order in the rotation).
pub const SECOND_ORDER_FACTOR: f64 = 2.0;

/// The relative tolerance of a comparison with the one-row closed form must
/// stay below this, or the comparison could not tell a right split from a
/// wrong one (the scene's depth is then too large for a first-order check).
pub const DISCRIMINATING_TOLERANCE: f64 = 0.02;

/// Asserts that each body moved as its one-row closed form `expected`, to
/// `relative` of each part (translation, rotation) of that motion, and
/// that `relative` is below [`DISCRIMINATING_TOLERANCE`].
pub fn assert_motions_match(
    label: &str,
    measured: &[Correction],
    expected: &[Correction],
    relative: f64,
) {
    assert!(
        relative <= DISCRIMINATING_TOLERANCE,
        "{label}: relative tolerance {relative:e} cannot discriminate"
    );
    for (k, (m, e)) in measured.iter().zip(expected).enumerate() {
        println!(
            "{label}: body {k}: dx {:?} vs {:?}, dtheta {:?} vs {:?} (relative tolerance {relative:.2e})",
            m.dx, e.dx, m.dtheta, e.dtheta
        );
        assert!(
            (m.dx - e.dx).norm() <= relative * e.dx.norm(),
            "{label}: body {k} translated by {:?}, closed form {:?}",
            m.dx,
            e.dx
        );
        assert!(
            (m.dtheta - e.dtheta).norm() <= relative * e.dtheta.norm(),
            "{label}: body {k} turned by {:?}, closed form {:?}",
            m.dtheta,
            e.dtheta
        );
    }
}

/// The relative tolerance of a one-row comparison: the second-order
/// remainder and the stabilizer's depth tolerance (the final gap may lie
/// anywhere between `-tolerance` and the target), both relative to the
/// first-order push `target - phi`.
pub fn one_row_tolerance(
    corrections: &[Correction],
    levers: &[f64],
    push: f64,
    depth_tolerance: f64,
) -> f64 {
    (SECOND_ORDER_FACTOR * second_order_remainder(corrections, levers) + depth_tolerance) / push
}

/// Half width (x and z) of the light box: narrower than the heavy one, so
/// that its top corners are the ones inside the heavy box and the contact
/// normal is the heavy box's (tilted) face normal.
pub const LIGHT_HALF_WIDTH: f64 = 0.3;

/// A light box (half extents 0.3, 0.5, 0.3) resting flat on the ground and
/// a unit box `ratio` times heavier on it, turned by `tilt` about z (so the
/// contact normals are tilted, as after an engine step), placed so that
/// the light box's deepest top corner is `depth` inside it.
pub fn heavy_on_light(ratio: f64, tilt: f64, depth: f64) -> Scene {
    heavy_on_floating_light(ratio, tilt, depth, 0.0)
}

/// [`heavy_on_light`] with the light box (and the heavy one with it)
/// raised by `gap` above the ground: its contact with the ground is open.
pub fn heavy_on_floating_light(ratio: f64, tilt: f64, depth: f64, gap: f64) -> Scene {
    let rotation = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), tilt);
    let w = LIGHT_HALF_WIDTH;
    let light = cuboid(
        "light",
        [w, 0.5, w],
        [0.0, 0.5 + gap, 0.0],
        IDENTITY_XYZW,
        MassSpec::Mass(1.0),
    );
    // Depth of a top corner (x, 1) below the heavy box's bottom face, for
    // its centre at height y: -x sin(tilt) + (1 - y) cos(tilt) + 0.5,
    // largest at x = -w.
    let y = 1.0 + gap + (0.5 + w * tilt.sin() - depth) / tilt.cos();
    let heavy = cuboid(
        "heavy",
        [0.5, 0.5, 0.5],
        [0.0, y, 0.0],
        xyzw(&rotation),
        MassSpec::Mass(ratio),
    );
    scene_of(&[ground(), light, heavy])
}
