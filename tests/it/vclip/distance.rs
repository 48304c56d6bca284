//! Separated distance and penetration status of V-Clip against parry3d-f64
//! (GJK distance and intersection test) on random pairs.

use constraint_stabilization::internals::geometry::ConvexPolyhedron;
use constraint_stabilization::internals::vclip::{Outcome, vclip};
use dev_support::random::{random_hull_varied, random_pose};
use dev_support::vclip::{parry_distance, parry_intersects, parry_shape};
use nalgebra::Vector3;
use parry3d_f64::shape::ConvexPolyhedron as ParryPolyhedron;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Agreement required between V-Clip's and parry's distances, relative to
/// the scene scale (the larger body's scale plus the distance).
const DISTANCE_AGREEMENT: f64 = 1e-9;

/// Within this distance of touching (relative to scale) the penetration
/// status may differ from parry's.
const TOUCHING_BAND: f64 = 1e-9;

/// parry's `intersection_test` stops GJK when the origin is within about
/// `sqrt(10 ε) ≈ 5e-8` of the CSO boundary (relative to the CSO's size; see
/// `parry3d_f64::query::gjk::closest_points`), so it is not an oracle closer
/// to touching than this (relative to scale). Nearer, the pairs built with a
/// known gap are checked against that gap instead.
const PARRY_INTERSECTION_FUZZ: f64 = 1e-7;

/// A witness point lies on its body's surface when its largest signed
/// distance to the body's face planes is within this of 0 (relative to
/// scale).
const ON_SURFACE: f64 = 1e-9;

/// The largest signed distance of `p_world` to the face planes of `poly` at
/// `pose`: 0 on the surface, negative inside.
fn surface_height(
    poly: &ConvexPolyhedron,
    pose: &nalgebra::Isometry3<f64>,
    p_world: &nalgebra::Point3<f64>,
) -> f64 {
    let p_body = pose.inverse_transform_point(p_world);
    poly.faces()
        .iter()
        .map(|f| f.plane.signed_distance(&p_body))
        .fold(f64::NEG_INFINITY, f64::max)
}

/// Both outcomes occur in at least this many of the 3000 cuboid pairs
/// (measured with seed 1: 2312 separated, 688 penetrating).
const MIN_PER_OUTCOME: usize = 500;

#[test]
fn random_cuboids_agree_with_parry() {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let (mut separated, mut penetrating) = (0, 0);
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
                for (poly, pose, p) in [
                    (&a, &pose_a, witness_a_world),
                    (&b, &pose_b, witness_b_world),
                ] {
                    let h = surface_height(poly, pose, &p);
                    assert!(h.abs() <= ON_SURFACE * scale, "witness {p} at height {h}");
                }
                separated += 1;
            }
            Outcome::Penetrating(_) => {
                assert!(
                    intersects || parry_d <= TOUCHING_BAND * scale,
                    "parry distance {parry_d}"
                );
                penetrating += 1;
            }
        }
    }
    assert!(
        separated >= MIN_PER_OUTCOME && penetrating >= MIN_PER_OUTCOME,
        "separated {separated}, penetrating {penetrating}"
    );
}

/// A polyhedron with its parry shape (built once, queried at several
/// poses).
type WithParry<'a> = (&'a ConvexPolyhedron, &'a ParryPolyhedron);

/// Checks one query against parry; returns V-Clip's outcome.
fn check_against_parry(
    (a, pa): WithParry,
    pose_a: &nalgebra::Isometry3<f64>,
    (b, pb): WithParry,
    pose_b: &nalgebra::Isometry3<f64>,
) -> Outcome {
    let result = vclip(a, pose_a, b, pose_b, None).unwrap();
    assert!(
        !result.fell_back(),
        "fell back after {} iterations",
        result.iterations
    );
    let scale =
        a.scale().max(b.scale()) + (pose_a.translation.vector - pose_b.translation.vector).norm();
    let parry_d = parry_distance(pa, pose_a, pb, pose_b);
    let intersects = parry_intersects(pa, pose_a, pb, pose_b);
    match result.outcome {
        Outcome::Separated { distance, .. } => {
            assert!(
                (distance - parry_d).abs() <= DISTANCE_AGREEMENT * scale,
                "v-clip {distance} parry {parry_d}, scale {scale}"
            );
            assert!(
                !intersects || distance <= PARRY_INTERSECTION_FUZZ * scale,
                "parry intersects, v-clip {distance}"
            );
        }
        Outcome::Penetrating(_) => {
            assert!(
                intersects || parry_d <= TOUCHING_BAND * scale,
                "parry distance {parry_d}"
            );
        }
    }
    result.outcome
}

/// 10,000 random pairs of random hulls (4 to 200 points), random poses, and
/// for every separated pair three nearly touching variants (B moved along
/// the closest direction to leave a gap of 1e-4, 1e-8, 1e-11 of the scale)
/// and one pushed 1e-6 of the scale past touching (which overlaps unless the
/// closest points are at sharp corners), all checked against parry.
#[test]
fn random_hulls_agree_with_parry() {
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let (mut separated, mut penetrating, mut near) = (0, 0, 0);
    for _ in 0..10_000 {
        let (n, r) = (rng.random_range(4..=200), rng.random_range(0.5..2.0));
        let a = random_hull_varied(&mut rng, n, r);
        let (n, r) = (rng.random_range(4..=200), rng.random_range(0.5..2.0));
        let b = random_hull_varied(&mut rng, n, r);
        let (pose_a, pose_b) = (random_pose(&mut rng, 1.2), random_pose(&mut rng, 1.2));
        let (pa, pb) = (parry_shape(&a), parry_shape(&b));
        let Outcome::Separated {
            distance,
            witness_a_world,
            witness_b_world,
        } = check_against_parry((&a, &pa), &pose_a, (&b, &pb), &pose_b)
        else {
            penetrating += 1;
            continue;
        };
        separated += 1;
        if distance <= 0.0 {
            continue;
        }
        let direction = (witness_b_world - witness_a_world) / distance;
        let scale = a.scale().max(b.scale());
        for gap in [1e-4, 1e-8, 1e-11, -1e-6] {
            let shift = nalgebra::Translation3::from(-direction * (distance - gap * scale));
            let moved_b = shift * pose_b;
            let outcome = check_against_parry((&a, &pa), &pose_a, (&b, &pb), &moved_b);
            if gap > TOUCHING_BAND {
                let Outcome::Separated { distance: d, .. } = outcome else {
                    panic!("gap {gap}: a positive gap stays separated, V-Clip says {outcome:?}");
                };
                assert!(
                    (d - gap * scale).abs() <= DISTANCE_AGREEMENT * scale,
                    "gap {gap}: {d}"
                );
            }
            near += 1;
        }
    }
    eprintln!("separated {separated}, penetrating {penetrating}, near-touching {near}");
    assert!(separated > 2000 && penetrating > 2000);
}
