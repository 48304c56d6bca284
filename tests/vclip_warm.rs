//! Warm starts: a query started from any valid feature pair gives the same
//! answer as a cold one (Mirtich 1998, Theorem 2: any start converges), and
//! bad input is rejected with a typed error.

mod vclip_support;

use constraint_stabilization::geometry::{ConvexPolyhedron, Feature};
use constraint_stabilization::vclip::{BodyRole, FeaturePair, Outcome, VClipError, vclip};
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use vclip_support::experiments::{CoherenceRun, mirtich_shapes};
use vclip_support::*;

const AGREEMENT: f64 = 1e-9;

/// Warm and cold answers agree: same status; same distance when separated;
/// when penetrating, both deepest vertices minimize the height over their
/// face's plane (brute force) — the witness face itself may differ, as the
/// walk may reach a different penetration witness.
fn assert_same_answer(
    warm: &constraint_stabilization::vclip::VClipResult,
    cold: &constraint_stabilization::vclip::VClipResult,
    a: &ConvexPolyhedron,
    pose_a: &Isometry3<f64>,
    b: &ConvexPolyhedron,
    pose_b: &Isometry3<f64>,
) {
    let scale = a.scale().max(b.scale());
    match (&warm.outcome, &cold.outcome) {
        (Outcome::Separated { distance: dw, .. }, Outcome::Separated { distance: dc, .. }) => {
            assert!((dw - dc).abs() <= AGREEMENT * scale, "warm {dw} cold {dc}");
        }
        (Outcome::Penetrating(w), Outcome::Penetrating(c)) => {
            for dv in [w, c] {
                let (poly, pose, face_poly, face_pose) = match dv.vertex_body {
                    BodyRole::A => (a, pose_a, b, pose_b),
                    BodyRole::B => (b, pose_b, a, pose_a),
                };
                let face = &face_poly.faces()[dv.face];
                let corner = face_pose * face_poly.vertices()[face.vertices[0]];
                let lowest = poly
                    .vertices()
                    .iter()
                    .map(|p| dv.normal_world.dot(&(pose * p - corner)))
                    .fold(f64::INFINITY, f64::min);
                assert!((dv.depth + lowest).abs() <= AGREEMENT * scale);
            }
        }
        (w, c) => {
            // Only within rounding of touching may the two walks disagree.
            let d = parry_distance(&parry_shape(a), pose_a, &parry_shape(b), pose_b);
            assert!(
                d <= AGREEMENT * scale,
                "warm {w:?} cold {c:?}, parry distance {d}"
            );
        }
    }
}

/// Coherence paths that pass through contact (amplitude shrunk so that the
/// bodies interpenetrate part of the time): warm starts from the previous
/// query agree with cold queries.
#[test]
fn warm_starts_along_paths_through_contact_agree_with_cold() {
    let mut rng = ChaCha8Rng::seed_from_u64(20);
    for (name, shape) in mirtich_shapes() {
        let (mut penetrating, mut queries) = (0, 0);
        for omega in [0.5, 5.0, 25.0] {
            let run = CoherenceRun::new(&mut rng, shape.scale() * 0.6, omega);
            let fixed = Isometry3::identity();
            let mut warm = None;
            for i in 1..=(360.0 / omega).max(100.0) as usize {
                let pose = run.pose(i);
                let hot = vclip(&shape, &fixed, &shape, &pose, warm).unwrap();
                let cold = vclip(&shape, &fixed, &shape, &pose, None).unwrap();
                assert!(!hot.fell_back() && !cold.fell_back(), "{name}");
                assert_same_answer(&hot, &cold, &shape, &fixed, &shape, &pose);
                penetrating += matches!(hot.outcome, Outcome::Penetrating(_)) as usize;
                warm = Some(hot.final_pair);
                queries += 1;
            }
        }
        assert!(
            penetrating > queries / 20 && penetrating < queries * 19 / 20,
            "{name}: {penetrating}/{queries}"
        );
    }
}

fn random_feature(rng: &mut impl Rng, poly: &ConvexPolyhedron) -> Feature {
    match rng.random_range(0..3) {
        0 => Feature::Vertex(rng.random_range(0..poly.vertices().len())),
        1 => Feature::Edge(rng.random_range(0..poly.edges().len())),
        _ => Feature::Face(rng.random_range(0..poly.faces().len())),
    }
}

/// Any valid feature pair, face–face included, is a valid start.
#[test]
fn arbitrary_starting_pairs_give_the_cold_answer() {
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    for _ in 0..1000 {
        let (n, m) = (rng.random_range(4..=80), rng.random_range(4..=80));
        let a = random_hull_varied(&mut rng, n, 1.0);
        let b = random_hull_varied(&mut rng, m, 1.0);
        let (pose_a, pose_b) = (random_pose(&mut rng, 1.2), random_pose(&mut rng, 1.2));
        let cold = vclip(&a, &pose_a, &b, &pose_b, None).unwrap();
        for _ in 0..5 {
            let start = FeaturePair {
                a: random_feature(&mut rng, &a),
                b: random_feature(&mut rng, &b),
            };
            let warm = vclip(&a, &pose_a, &b, &pose_b, Some(start)).unwrap();
            assert!(!warm.fell_back());
            assert_same_answer(&warm, &cold, &a, &pose_a, &b, &pose_b);
        }
    }
}

#[test]
fn bad_input_is_a_typed_error() {
    let cube = ConvexPolyhedron::cuboid(Vector3::new(1.0, 1.0, 1.0)).unwrap();
    let ok = Isometry3::identity();
    let nan = Isometry3::from_parts(
        Translation3::new(f64::NAN, 0.0, 0.0),
        UnitQuaternion::identity(),
    );
    assert_eq!(
        vclip(&cube, &nan, &cube, &ok, None).unwrap_err(),
        VClipError::NonFinitePose { body: BodyRole::A }
    );
    let stretched = Isometry3::from_parts(
        Translation3::new(3.0, 0.0, 0.0),
        UnitQuaternion::new_unchecked(Quaternion::new(2.0, 0.0, 0.0, 0.0)),
    );
    assert!(matches!(
        vclip(&cube, &ok, &cube, &stretched, None),
        Err(VClipError::NonUnitRotation {
            body: BodyRole::B,
            ..
        })
    ));
    let stale = FeaturePair {
        a: Feature::Vertex(0),
        b: Feature::Face(6),
    };
    assert_eq!(
        vclip(&cube, &ok, &cube, &ok, Some(stale)).unwrap_err(),
        VClipError::InvalidWarmStart {
            body: BodyRole::B,
            feature: Feature::Face(6)
        }
    );
}

/// Coincident bodies (the same cube at the same pose) are penetrating, with
/// depth the full width along a face normal.
#[test]
fn coincident_cubes_penetrate_by_their_width() {
    let cube = ConvexPolyhedron::cuboid(Vector3::new(1.0, 2.0, 3.0)).unwrap();
    let pose = Isometry3::identity();
    let result = vclip(&cube, &pose, &cube, &pose, None).unwrap();
    let Outcome::Penetrating(dv) = result.outcome else {
        panic!("{:?}", result.outcome)
    };
    assert!(
        [2.0, 4.0, 6.0].iter().any(|w| (dv.depth - w).abs() < 1e-12),
        "{}",
        dv.depth
    );
}
