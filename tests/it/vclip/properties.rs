//! Property tests (proptest) of V-Clip on random hulls and poses: symmetry
//! in the two bodies, invariance under scaling of the scene, agreement with
//! parry's distance, and the push-out property of the deepest vertex.
//! Case counts are bounded so that `cargo test` stays fast.

use crate::support::proptest_config;
use constraint_stabilization::internals::geometry::ConvexPolyhedron;
use constraint_stabilization::internals::vclip::{Outcome, VClipResult, vclip};
use dev_support::random::random_hull_varied;
use dev_support::sat::separating_axis_depth;
use dev_support::vclip::{
    parry_depth, parry_distance, parry_intersects, parry_shape, pushed_out, separated_distance,
};
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use proptest::prelude::*;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

const AGREEMENT: f64 = 1e-9;

/// parry's intersection test is fuzzy within about 5e-8 of touching.
const PARRY_FUZZ: f64 = 1e-7;

/// Gap left by the push-out check, relative to scale: well above
/// [`PARRY_FUZZ`].
const PUSH_OUT_GAP: f64 = 1e-6;

fn hull_from_seed(seed: u64, n: usize, scale: f64) -> ConvexPolyhedron {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let unit = random_hull_varied(&mut rng, n, 1.0);
    let points: Vec<Point3<f64>> = unit.vertices().iter().map(|p| p * scale).collect();
    ConvexPolyhedron::from_points(&points).expect("a scaled hull is a hull")
}

fn pose(translation: [f64; 3], rotation: [f64; 3], scale: f64) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::from(Vector3::from(translation) * scale),
        UnitQuaternion::from_scaled_axis(Vector3::from(rotation)),
    )
}

fn distance_of(result: &VClipResult) -> Option<f64> {
    separated_distance(result)
}

fn coords() -> impl Strategy<Value = [f64; 3]> {
    [-1.5..1.5f64, -1.5..1.5f64, -1.5..1.5f64]
}

fn angles() -> impl Strategy<Value = [f64; 3]> {
    [-3.0..3.0f64, -3.0..3.0f64, -3.0..3.0f64]
}

proptest! {
    #![proptest_config(proptest_config::config(64))]

    #[test]
    fn swapping_the_bodies_gives_the_same_answer(
        seeds in (any::<u64>(), any::<u64>()), sizes in (4usize..40, 4usize..40),
        ta in coords(), ra in angles(), tb in coords(), rb in angles(),
    ) {
        let (a, b) = (hull_from_seed(seeds.0, sizes.0, 1.0), hull_from_seed(seeds.1, sizes.1, 1.0));
        let (pose_a, pose_b) = (pose(ta, ra, 1.0), pose(tb, rb, 1.0));
        let ab = vclip(&a, &pose_a, &b, &pose_b, None).unwrap();
        let ba = vclip(&b, &pose_b, &a, &pose_a, None).unwrap();
        let scale = a.scale().max(b.scale());
        let parry_d = parry_distance(&parry_shape(&a), &pose_a, &parry_shape(&b), &pose_b);
        match (distance_of(&ab), distance_of(&ba)) {
            (Some(x), Some(y)) => {
                prop_assert!((x - y).abs() <= AGREEMENT * scale);
                prop_assert!((x - parry_d).abs() <= AGREEMENT * scale);
                if let (Outcome::Separated { witness_a_world: pa, witness_b_world: pb, .. },
                        Outcome::Separated { witness_a_world: qb, witness_b_world: qa, .. }) = (ab.outcome, ba.outcome) {
                    // Witnesses may differ where the closest points are not unique
                    // (parallel features); their distance may not.
                    prop_assert!(((pa - pb).norm() - (qa - qb).norm()).abs() <= AGREEMENT * scale);
                }
            }
            (None, None) => prop_assert!(parry_d <= AGREEMENT * scale),
            _ => prop_assert!(parry_d <= PARRY_FUZZ * scale),
        }
    }

    #[test]
    fn scaling_the_scene_scales_the_distance(
        seeds in (any::<u64>(), any::<u64>()), sizes in (4usize..40, 4usize..40),
        ta in coords(), ra in angles(), tb in coords(), rb in angles(),
        exponent in prop::sample::select(vec![-3i32, 3]),
    ) {
        let s = 10f64.powi(exponent);
        let unit = (hull_from_seed(seeds.0, sizes.0, 1.0), hull_from_seed(seeds.1, sizes.1, 1.0));
        let scaled = (hull_from_seed(seeds.0, sizes.0, s), hull_from_seed(seeds.1, sizes.1, s));
        let r1 = vclip(&unit.0, &pose(ta, ra, 1.0), &unit.1, &pose(tb, rb, 1.0), None).unwrap();
        let rs = vclip(&scaled.0, &pose(ta, ra, s), &scaled.1, &pose(tb, rb, s), None).unwrap();
        let unit_scale = unit.0.scale().max(unit.1.scale());
        match (r1.outcome, rs.outcome) {
            (Outcome::Separated { distance: d1, .. }, Outcome::Separated { distance: ds, .. }) => {
                prop_assert!((ds / s - d1).abs() <= AGREEMENT * unit_scale);
            }
            (Outcome::Penetrating(p1), Outcome::Penetrating(ps)) => {
                // The same walk on a scaled copy: the same depth, scaled.
                prop_assert!(
                    (ps.depth / s - p1.depth).abs() <= AGREEMENT * unit_scale,
                    "depth {} at scale 1, {} at scale {s}", p1.depth, ps.depth
                );
                prop_assert!((ps.normal_world - p1.normal_world).norm() <= AGREEMENT);
                let (pa, pb) = (parry_shape(&unit.0), parry_shape(&unit.1));
                let parry_d = parry_distance(&pa, &pose(ta, ra, 1.0), &pb, &pose(tb, rb, 1.0));
                prop_assert!(parry_d <= PARRY_FUZZ * unit_scale, "parry distance {parry_d}");
            }
            (o1, os) => {
                let (d1, ds) = (distance_of(&r1), distance_of(&rs));
                prop_assert!(
                    d1.unwrap_or(0.0).max(ds.unwrap_or(0.0) / s) <= AGREEMENT * unit_scale,
                    "scale 1: {o1:?}, scale {s}: {os:?}"
                );
            }
        }
    }

    #[test]
    fn pushing_out_by_the_depth_separates(
        seeds in (any::<u64>(), any::<u64>()), sizes in (4usize..40, 4usize..40),
        ta in [-0.5..0.5f64, -0.5..0.5f64, -0.5..0.5f64], ra in angles(), rb in angles(),
    ) {
        let (a, b) = (hull_from_seed(seeds.0, sizes.0, 1.0), hull_from_seed(seeds.1, sizes.1, 1.0));
        let (pose_a, pose_b) = (pose(ta, ra, 1.0), pose([0.0; 3], rb, 1.0));
        let result = vclip(&a, &pose_a, &b, &pose_b, None).unwrap();
        let scale = a.scale().max(b.scale());
        let (pa, pb) = (parry_shape(&a), parry_shape(&b));
        match result.outcome {
            Outcome::Penetrating(dv) => {
                prop_assert!(dv.depth >= 0.0);
                let exact = separating_axis_depth(&a, &pose_a, &b, &pose_b);
                prop_assert!(dv.depth >= exact.all - AGREEMENT * scale);
                prop_assert!(dv.depth >= parry_depth(&pa, &pose_a, &pb, &pose_b) - AGREEMENT * scale);
                let (moved_a, moved_b) = pushed_out(&dv, &pose_a, &pose_b, PUSH_OUT_GAP * scale);
                prop_assert!(!parry_intersects(&pa, &moved_a, &pb, &moved_b));
            }
            // Rarely reached (centres within 0.5 * sqrt(3)): a separated
            // answer must be parry's distance and no overlap.
            Outcome::Separated { distance, .. } => {
                let parry_d = parry_distance(&pa, &pose_a, &pb, &pose_b);
                prop_assert!((distance - parry_d).abs() <= AGREEMENT * scale, "{distance} vs {parry_d}");
                prop_assert!(
                    separating_axis_depth(&a, &pose_a, &b, &pose_b).all <= AGREEMENT * scale
                );
            }
        }
    }
}
