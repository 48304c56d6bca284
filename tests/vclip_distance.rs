//! Separated distance and penetration status of V-Clip against parry3d-f64
//! (GJK distance and intersection test) on random pairs.

mod vclip_support;

use constraint_stabilization::geometry::ConvexPolyhedron;
use constraint_stabilization::vclip::{Outcome, vclip};
use nalgebra::Vector3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use vclip_support::*;

/// Agreement required between V-Clip's and parry's distances, relative to
/// the scene scale (the larger body's scale plus the distance).
const DISTANCE_AGREEMENT: f64 = 1e-9;

/// Within this distance of touching (relative to scale) the penetration
/// status may differ from parry's.
const TOUCHING_BAND: f64 = 1e-9;

#[test]
fn random_cuboids_agree_with_parry() {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let mut checked = 0;
    for _ in 0..3000 {
        let half_a = Vector3::new(
            rng.random_range(0.1..2.0),
            rng.random_range(0.1..2.0),
            rng.random_range(0.1..2.0),
        );
        let half_b = Vector3::new(
            rng.random_range(0.1..2.0),
            rng.random_range(0.1..2.0),
            rng.random_range(0.1..2.0),
        );
        let a = ConvexPolyhedron::cuboid(half_a).unwrap();
        let b = ConvexPolyhedron::cuboid(half_b).unwrap();
        let (pose_a, pose_b) = (random_pose(&mut rng, 3.0), random_pose(&mut rng, 3.0));
        let (pa, pb) = (parry_shape(&a), parry_shape(&b));
        let result = vclip(&a, &pose_a, &b, &pose_b, None).unwrap();
        assert!(!result.fell_back());
        let scale = a.scale().max(b.scale());
        let parry_d = parry_distance(&pa, &pose_a, &pb, &pose_b);
        let intersects = parry_intersects(&pa, &pose_a, &pb, &pose_b);
        match result.outcome {
            Outcome::Separated {
                distance,
                witness_a_world,
                witness_b_world,
            } => {
                assert!(
                    (distance - parry_d).abs() <= DISTANCE_AGREEMENT * (scale + distance),
                    "v-clip {distance} parry {parry_d}"
                );
                assert!(
                    ((witness_a_world - witness_b_world).norm() - distance).abs() <= 1e-12 * scale
                );
                assert!(!intersects || distance <= TOUCHING_BAND * scale);
            }
            Outcome::Penetrating(_) => {
                assert!(
                    intersects || parry_d <= TOUCHING_BAND * scale,
                    "parry distance {parry_d}"
                );
            }
        }
        checked += 1;
    }
    assert_eq!(checked, 3000);
}
