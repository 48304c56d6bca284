//! The deepest-vertex search against brute force and parry's EPA, and the
//! exhaustive fallback (forced by an iteration cap of zero) against parry.

mod vclip_support;

use constraint_stabilization::geometry::ConvexPolyhedron;
use constraint_stabilization::vclip::{
    BodyRole, DeepestVertex, FallbackReason, Outcome, VClip, VClipSettings, vclip,
};
use nalgebra::{Isometry3, Point3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use vclip_support::*;

/// Rounding allowance for quantities computed two ways, relative to scale.
const ROUNDING: f64 = 1e-9;

/// Gap left by the push-out check, relative to scale: well above parry's
/// intersection fuzz (about 5e-8).
const PUSH_OUT_GAP: f64 = 1e-6;

/// Checks a deepest vertex against brute force over all vertices and
/// against parry (EPA depth, separation after the push-out). Returns
/// `depth / EPA depth`.
fn check_deepest(
    dv: &DeepestVertex,
    a: &ConvexPolyhedron,
    pose_a: &Isometry3<f64>,
    b: &ConvexPolyhedron,
    pose_b: &Isometry3<f64>,
) -> f64 {
    let scale = a.scale().max(b.scale());
    let (vertex_poly, vertex_pose, face_poly, face_pose) = match dv.vertex_body {
        BodyRole::A => (a, pose_a, b, pose_b),
        BodyRole::B => (b, pose_b, a, pose_a),
    };
    let face = &face_poly.faces()[dv.face];
    let normal_world = face_pose.rotation * face.plane.normal;
    let on_face_world = face_pose * face_poly.vertices()[face.vertices[0]];
    let height = |p: &Point3<f64>| normal_world.dot(&(vertex_pose * p - on_face_world));
    let brute_min = vertex_poly
        .vertices()
        .iter()
        .map(height)
        .fold(f64::INFINITY, f64::min);
    assert!(dv.depth >= 0.0);
    assert!(
        (dv.depth + brute_min.min(0.0)).abs() <= ROUNDING * scale,
        "depth {} brute-force minimum {brute_min}",
        dv.depth
    );
    assert!((height(&vertex_poly.vertices()[dv.vertex]) - brute_min).abs() <= ROUNDING * scale);
    assert!((dv.normal_world - normal_world).norm() <= 1e-12);
    assert!(
        (dv.vertex_world - vertex_pose * vertex_poly.vertices()[dv.vertex]).norm() <= 1e-12 * scale
    );
    let (pa, pb) = (parry_shape(a), parry_shape(b));
    let epa = parry_depth(&pa, pose_a, &pb, pose_b);
    assert!(
        dv.depth >= epa - ROUNDING * scale,
        "depth {} below EPA {epa}",
        dv.depth
    );
    let (moved_a, moved_b) = pushed_out(dv, pose_a, pose_b, PUSH_OUT_GAP * scale);
    let after = parry_distance(&pa, &moved_a, &pb, &moved_b);
    assert!(
        after >= PUSH_OUT_GAP * scale * (1.0 - 1e-3),
        "after push-out: {after}"
    );
    assert!(!parry_intersects(&pa, &moved_a, &pb, &moved_b));
    if epa > 0.0 { dv.depth / epa } else { 1.0 }
}

/// Both the witness face of DESIGN.md section 4 (`refine_face: false`) and
/// the refined face (default): the deepest vertex is the brute-force
/// minimum, the depth bounds parry's EPA depth, the push-out separates.
#[test]
fn deepest_vertex_is_the_brute_force_minimum_and_bounds_epa() {
    let witness_face = VClip::new(VClipSettings {
        refine_face: false,
        ..VClipSettings::default()
    });
    let refined = VClip::default();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let (mut count, mut by_role) = (0, [0, 0]);
    let mut ratios = [Vec::new(), Vec::new()];
    while count < 2000 {
        let (n, m) = (rng.random_range(4..=120), rng.random_range(4..=120));
        let a = random_hull_varied(&mut rng, n, 1.0);
        let radius_b = rng.random_range(0.3..1.5);
        let b = random_hull_varied(&mut rng, m, radius_b);
        let (pose_a, pose_b) = (random_pose(&mut rng, 0.8), random_pose(&mut rng, 0.8));
        for (k, engine) in [&witness_face, &refined].into_iter().enumerate() {
            let result = engine.query(&a, &pose_a, &b, &pose_b, None).unwrap();
            assert!(!result.fell_back());
            if let Outcome::Penetrating(dv) = result.outcome {
                ratios[k].push(check_deepest(&dv, &a, &pose_a, &b, &pose_b));
                if k == 1 {
                    by_role[(dv.vertex_body == BodyRole::B) as usize] += 1;
                    count += 1;
                }
            }
        }
    }
    for (name, r) in ["witness face", "refined face"].iter().zip(&mut ratios) {
        r.sort_by(f64::total_cmp);
        eprintln!(
            "{name}: depth / EPA depth: median {:.3}, 90% {:.3}, max {:.3}",
            r[r.len() / 2],
            r[r.len() * 9 / 10],
            r[r.len() - 1]
        );
    }
    eprintln!("refined: vertex on A {}, on B {}", by_role[0], by_role[1]);
    assert!(by_role[0] > 100 && by_role[1] > 100, "{by_role:?}");
    // The refinement never makes the answer deeper than the witness face.
    assert!(ratios[1][ratios[1].len() / 2] <= ratios[0][ratios[0].len() / 2]);
}

/// A small body deep inside a large one: the walk must end in the
/// vertex–face local minimum (no edge of the small body crosses a face).
#[test]
fn body_inside_another_is_a_vertex_face_penetration() {
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    for _ in 0..200 {
        let big = random_hull_varied(&mut rng, 60, 3.0);
        let small = random_hull_varied(&mut rng, 20, 0.05);
        let pose_big = random_pose(&mut rng, 1.0);
        let pose_small = pose_big * Isometry3::rotation(nalgebra::Vector3::new(0.3, 0.2, 0.1));
        let result = vclip(&small, &pose_small, &big, &pose_big, None).unwrap();
        let Outcome::Penetrating(dv) = result.outcome else {
            panic!("containment not detected: {:?}", result.outcome);
        };
        check_deepest(&dv, &small, &pose_small, &big, &pose_big);
    }
}

/// An iteration cap of zero forces the exhaustive fallback: it must agree
/// with parry (distance, status) and its deepest vertex pass the same
/// checks; the result must say that it fell back.
#[test]
fn forced_fallback_is_correct_and_reported() {
    let forced = VClip::new(VClipSettings {
        max_iterations: Some(0),
        ..VClipSettings::default()
    });
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut seen = [0, 0];
    for _ in 0..400 {
        let (n, m) = (rng.random_range(4..=40), rng.random_range(4..=40));
        let a = random_hull_varied(&mut rng, n, 1.0);
        let b = random_hull_varied(&mut rng, m, 1.0);
        let (pose_a, pose_b) = (random_pose(&mut rng, 0.9), random_pose(&mut rng, 0.9));
        let result = forced.query(&a, &pose_a, &b, &pose_b, None).unwrap();
        assert_eq!(result.fallback, Some(FallbackReason::IterationCap));
        let (pa, pb) = (parry_shape(&a), parry_shape(&b));
        let scale = a.scale().max(b.scale());
        let parry_d = parry_distance(&pa, &pose_a, &pb, &pose_b);
        match result.outcome {
            Outcome::Separated {
                distance,
                witness_a_world,
                witness_b_world,
            } => {
                assert!(
                    (distance - parry_d).abs() <= ROUNDING * scale,
                    "{distance} vs {parry_d}"
                );
                assert!(
                    ((witness_a_world - witness_b_world).norm() - distance).abs()
                        <= ROUNDING * scale
                );
                seen[0] += 1;
            }
            Outcome::Penetrating(dv) => {
                assert!(
                    parry_intersects(&pa, &pose_a, &pb, &pose_b) || parry_d <= ROUNDING * scale
                );
                check_deepest(&dv, &a, &pose_a, &b, &pose_b);
                seen[1] += 1;
            }
        }
        let walked = vclip(&a, &pose_a, &b, &pose_b, None).unwrap();
        assert_eq!(
            separated_distance(&walked).is_some(),
            separated_distance(&result).is_some()
        );
    }
    assert!(seen[0] > 50 && seen[1] > 50, "{seen:?}");
}
