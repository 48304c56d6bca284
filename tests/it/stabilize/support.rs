//! Helpers of the stabilizer tests only: the parry-and-SAT penetration
//! residual of a scene, stabilizing with a check of the result, one line
//! describing a run, bit-exact pose hashes, and the heavy-box-on-light-box
//! scenes of the friction and velocity tests.
//!
//! The residual's oracle is parry3d-f64's `query::contact` (GJK/EPA), which
//! this project did not write, backed by the brute-force separating-axis
//! depth of `dev_support::sat` (parry's EPA under-reports on coincident
//! faces): the residual of a scene is the largest depth over every pair of
//! bodies with at least one dynamic body (pairs of fixed bodies cannot be
//! corrected and are skipped). Pairs whose AABBs (from the exact world
//! vertices) are disjoint cannot penetrate and are skipped too.
#![allow(dead_code)]

use constraint_stabilization::body::MassSpec;
use constraint_stabilization::internals::geometry::isometry_to_parry;
use constraint_stabilization::scene::Scene;
use constraint_stabilization::{Report, Settings, Stabilizer};
use dev_support::sat::{deepest_over_pairs, sat_depth};
use dev_support::scene::{IDENTITY_XYZW, assert_finite, cuboid, ground, pose_bits, scene_of, xyzw};
use nalgebra::{UnitQuaternion, Vector3};
use parry3d_f64::query;
use parry3d_f64::shape::ConvexPolyhedron as ParryPolyhedron;

/// The bodies of every island solved in some pass of `report`.
pub fn solved_bodies(report: &Report) -> std::collections::BTreeSet<usize> {
    report
        .pass_reports
        .iter()
        .flat_map(|p| &p.solved)
        .flat_map(|island| island.bodies.iter().copied())
        .collect()
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

/// Penetration of one pair by parry (`-dist`, 0 when separated; the
/// deepest over the part pairs of compound bodies).
pub fn parry_pair_depth(scene: &Scene, shapes: &[Vec<ParryPolyhedron>], a: usize, b: usize) -> f64 {
    let poses = |body: usize| -> Vec<_> {
        scene.bodies()[body]
            .part_poses()
            .map(|p| isometry_to_parry(&p))
            .collect()
    };
    let round = |body: usize| {
        let body = &scene.bodies()[body];
        (0..body.parts().len())
            .any(|k| body.parts()[k].rounding().is_some() || body.part_curved(k).is_some())
    };
    if round(a) || round(b) {
        // A round part's polyhedron is its core or a bounding box, a
        // cylinder's or cone's a circumscribed approximation: the
        // support-function oracle of `sat_depth` measures the pair on the
        // true solids.
        return 0.0;
    }
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
