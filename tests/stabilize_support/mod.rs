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

use constraint_stabilization::body::{BodyDesc, MassSpec, Shape};
use constraint_stabilization::geometry::ConvexPolyhedron;
use constraint_stabilization::geometry::isometry_to_parry;
use constraint_stabilization::scene::Scene;
use constraint_stabilization::{Report, Settings, Stabilizer};
use nalgebra::{Isometry3, Point3, UnitQuaternion, Vector3};
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

/// Asserts that no pose component is NaN or infinite.
pub fn assert_finite(scene: &Scene) {
    for body in scene.bodies() {
        let finite = body.translation_user().iter().all(|c| c.is_finite())
            && body.rotation_user_xyzw().iter().all(|c| c.is_finite());
        assert!(finite, "body {} has a non-finite pose", body.name());
    }
}

/// Penetration of one pair by parry (`-dist`, 0 when separated).
pub fn parry_pair_depth(scene: &Scene, shapes: &[ParryPolyhedron], a: usize, b: usize) -> f64 {
    let pose_a = isometry_to_parry(scene.bodies()[a].com_pose());
    let pose_b = isometry_to_parry(scene.bodies()[b].com_pose());
    query::contact(&pose_a, &shapes[a], &pose_b, &shapes[b], 0.0)
        .expect("parry supports convex polyhedra")
        .map_or(0.0, |c| (-c.dist).max(0.0))
}

/// The parry shapes of all bodies (body frame, origin at the COM).
pub fn parry_shapes(scene: &Scene) -> Vec<ParryPolyhedron> {
    scene
        .bodies()
        .iter()
        .map(|b| b.polyhedron().to_parry().expect("parry accepts our hulls"))
        .collect()
}

/// The deepest penetration of the scene and the pair it is in: for every
/// pair, the larger of parry's EPA depth and the brute-force separating-axis
/// depth [`sat_depth`]. parry alone is not enough: on coincident faces its
/// EPA can return less than the true depth (two unit boxes offset by 0.01
/// along a face: parry 0.57, true 0.99), which would hide a residual.
pub fn penetration_residual(scene: &Scene) -> (f64, Option<(usize, usize)>) {
    let shapes = parry_shapes(scene);
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
            let depth = parry_pair_depth(scene, &shapes, a, b).max(sat_depth(scene, a, b));
            if depth > worst.0 {
                worst = (depth, Some((a, b)));
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
pub fn sat_depth(scene: &Scene, a: usize, b: usize) -> f64 {
    let (body_a, body_b) = (&scene.bodies()[a], &scene.bodies()[b]);
    sat_overlap(
        body_a.polyhedron(),
        body_a.com_pose(),
        body_b.polyhedron(),
        body_b.com_pose(),
    )
    .max(0.0)
}

/// The smallest overlap of the projections of two posed polyhedra over
/// every face normal of both and every cross product of an edge of each
/// (brute force): the exact penetration depth when positive; when negative,
/// some axis separates the bodies (by at least that gap).
pub fn sat_overlap(
    poly_a: &ConvexPolyhedron,
    pose_a: &Isometry3<f64>,
    poly_b: &ConvexPolyhedron,
    pose_b: &Isometry3<f64>,
) -> f64 {
    sat_axis(poly_a, pose_a, poly_b, pose_b).0
}

/// [`sat_overlap`] and the axis that realizes it, oriented from B towards A
/// (translating A by the overlap along it makes the bodies touch).
pub fn sat_axis(
    poly_a: &ConvexPolyhedron,
    pose_a: &Isometry3<f64>,
    poly_b: &ConvexPolyhedron,
    pose_b: &Isometry3<f64>,
) -> (f64, Vector3<f64>) {
    let world = |poly: &ConvexPolyhedron, pose: &Isometry3<f64>| -> Vec<Vector3<f64>> {
        poly.vertices().iter().map(|v| (pose * v).coords).collect()
    };
    let (points_a, points_b) = (world(poly_a, pose_a), world(poly_b, pose_b));
    let faces = |poly: &ConvexPolyhedron, pose: &Isometry3<f64>| -> Vec<Vector3<f64>> {
        poly.faces()
            .iter()
            .map(|f| pose.rotation * f.plane.normal)
            .collect()
    };
    let edges = |poly: &ConvexPolyhedron, pose: &Isometry3<f64>| -> Vec<Vector3<f64>> {
        poly.edges()
            .iter()
            .map(|e| pose.rotation * e.direction)
            .collect()
    };
    let (edges_a, edges_b) = (edges(poly_a, pose_a), edges(poly_b, pose_b));
    let span = |points: &[Vector3<f64>], axis: &Vector3<f64>| {
        points
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                let h = axis.dot(p);
                (lo.min(h), hi.max(h))
            })
    };
    // Moving A along +axis separates after max_b - min_a, along -axis
    // after max_a - min_b.
    let overlap = |axis: &Vector3<f64>| {
        let (min_a, max_a) = span(&points_a, axis);
        let (min_b, max_b) = span(&points_b, axis);
        let (along, against) = (max_b - min_a, max_a - min_b);
        if along <= against {
            (along, *axis)
        } else {
            (against, -axis)
        }
    };
    let edge_axes: Vec<Vector3<f64>> = edges_a
        .iter()
        .flat_map(|da| {
            edges_b
                .iter()
                .filter_map(move |db| da.cross(db).try_normalize(PARALLEL_SINE))
        })
        .collect();
    faces(poly_a, pose_a)
        .into_iter()
        .chain(faces(poly_b, pose_b))
        .chain(edge_axes)
        .map(|axis| overlap(&axis))
        .fold((f64::INFINITY, Vector3::zeros()), |best, next| {
            if next.0 < best.0 { next } else { best }
        })
}

/// Edge pairs closer to parallel than this sine give no axis of their own.
const PARALLEL_SINE: f64 = 1e-9;

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
