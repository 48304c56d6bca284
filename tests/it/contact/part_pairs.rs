//! The part pairs of a scene with compound and offset bodies
//! (`SceneParts::part_pairs` of the broad phase's candidates) against
//! enumeration: every pair of parts of two bodies, not both fixed, whose
//! boxes grown by half the margin overlap.

use constraint_stabilization::Scene;
use constraint_stabilization::body::{BodyDesc, MassSpec, Shape, ShapePart, rounded_aabb};
use constraint_stabilization::internals::broad_phase::{BodyPair, candidate_pairs};
use constraint_stabilization::internals::contact::SceneParts;
use dev_support::random::{MIXED_SHAPE_KINDS, mixed_shape, random_rotation};
use dev_support::scene::xyzw;
use nalgebra::{Isometry3, Point3, Vector3};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A random body's description at `at`: a single shape (kinds of `mixed_shape`, cones
/// and cylinders among them, whose centre of mass is off their shape
/// frame's origin for cones), or a compound of two to four pieces; fixed
/// with probability 1/5.
fn random_body(rng: &mut ChaCha8Rng, at: Vector3<f64>) -> BodyDesc {
    let shape = if rng.random_bool(0.4) {
        let pieces = rng.random_range(2..=4);
        Shape::Compound {
            parts: (0..pieces)
                .map(|_| {
                    let kind = rng.random_range(0..MIXED_SHAPE_KINDS);
                    ShapePart {
                        shape: mixed_shape(rng, kind, 0.6),
                        translation: Vector3::from_fn(|_, _| rng.random_range(-0.5..0.5)),
                        rotation_xyzw: xyzw(&random_rotation(rng)),
                    }
                })
                .collect(),
        }
    } else {
        let kind = rng.random_range(0..MIXED_SHAPE_KINDS);
        mixed_shape(rng, kind, 1.0)
    };
    let mass = match rng.random_bool(0.2) {
        true => MassSpec::Fixed,
        false => MassSpec::Mass(1.0),
    };
    BodyDesc {
        name: "body".into(),
        shape,
        translation: at,
        rotation_xyzw: xyzw(&random_rotation(rng)),
        mass,
    }
}

/// A scene of `count` random bodies in a box of side `spread`.
fn random_scene(seed: u64, count: usize, spread: f64) -> Scene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut scene = Scene::new();
    while scene.bodies().len() < count {
        let at = Vector3::from_fn(|_, _| rng.random_range(0.0..spread));
        // A random shape can be degenerate (a flat hull): drawn again.
        let _ = scene.add_body(random_body(&mut rng, at));
    }
    scene
}

/// Every part pair by enumeration (module docs), ascending.
fn enumerated(
    scene: &Scene,
    parts: &SceneParts,
    poses: &[Isometry3<f64>],
    margin: f64,
) -> Vec<BodyPair> {
    let boxes: Vec<(Point3<f64>, Point3<f64>)> = (0..parts.len())
        .map(|p| {
            let body = &scene.bodies()[parts.owner(p)];
            let k = p - parts.parts_of(parts.owner(p)).start;
            let part = &body.parts()[k];
            rounded_aabb(part.polyhedron(), part.rounding().as_ref(), &poses[p])
        })
        .collect();
    let grow = margin / 2.0;
    let mut pairs = Vec::new();
    for p in 0..parts.len() {
        for q in p + 1..parts.len() {
            let (a, b) = (parts.owner(p), parts.owner(q));
            let both_fixed = scene.bodies()[a].is_fixed() && scene.bodies()[b].is_fixed();
            if a == b || both_fixed {
                continue;
            }
            let ((min_p, max_p), (min_q, max_q)) = (boxes[p], boxes[q]);
            if (0..3)
                .all(|k| min_p[k] - grow <= max_q[k] + grow && min_q[k] - grow <= max_p[k] + grow)
            {
                pairs.push(BodyPair {
                    body_a: p,
                    body_b: q,
                });
            }
        }
    }
    pairs
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    /// The part pairs of the broad phase's candidates are exactly the
    /// enumerated ones, in scenes dense and sparse, at margins from zero.
    #[test]
    fn part_pairs_of_the_candidates_are_the_enumerated_ones(
        seed in 0u64..1_000_000,
        count in 2usize..16,
        spread in 0.5f64..6.0,
        margin in prop_oneof![Just(0.0), 0.0f64..0.4],
    ) {
        let scene = random_scene(seed, count, spread);
        let parts = SceneParts::of(&scene);
        prop_assume!(!parts.all_convex());
        let body_poses: Vec<Isometry3<f64>> = scene.bodies().iter().map(|b| *b.com_pose()).collect();
        let poses = parts.poses(&body_poses);
        let candidates = candidate_pairs(&scene, margin).expect("valid boxes");
        let found = parts.part_pairs(&candidates, &poses, margin);
        prop_assert_eq!(found, enumerated(&scene, &parts, &poses, margin));
    }
}
