//! Broad phase against brute force: all O(n^2) pairs of enlarged AABBs, and
//! parry3d-f64's distance query (every pair within the margin must be a
//! candidate).

use crate::support::proptest_config;
use constraint_stabilization::body::{BodyDesc, MassSpec, Shape};
use constraint_stabilization::internals::broad_phase::{
    BodyPair, BroadPhaseError, BroadPhaseUpdate, IncrementalBroadPhase, REBUILD_MOVED_FRACTION,
    candidate_pairs, candidate_pairs_of_aabbs, grown_boxes, has_candidate_pair,
};
use constraint_stabilization::scene::Scene;
use nalgebra::Vector3;
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::{Pose, Vector};
use parry3d_f64::shape::Cuboid;
use proptest::prelude::*;

fn brute_force(aabbs: &[Aabb], fixed: &[bool], margin: f64) -> Vec<BodyPair> {
    let overlap = |a: &Aabb, b: &Aabb| {
        (0..3).all(|k| {
            a.mins[k] - margin / 2.0 <= b.maxs[k] + margin / 2.0
                && b.mins[k] - margin / 2.0 <= a.maxs[k] + margin / 2.0
        })
    };
    let mut pairs = vec![];
    for i in 0..aabbs.len() {
        for j in i + 1..aabbs.len() {
            if !(fixed[i] && fixed[j]) && overlap(&aabbs[i], &aabbs[j]) {
                pairs.push(BodyPair::new(i, j).unwrap());
            }
        }
    }
    pairs
}

fn aabbs() -> impl Strategy<Value = (Vec<Aabb>, Vec<bool>)> {
    let aabb = (
        0.0..10.0f64,
        0.0..10.0f64,
        0.0..10.0f64,
        0.0..1.5f64,
        0.0..1.5f64,
        0.0..1.5f64,
    )
        .prop_map(|(x, y, z, a, b, c)| {
            Aabb::new(Vector::new(x, y, z), Vector::new(x + a, y + b, z + c))
        });
    (0usize..80).prop_flat_map(move |n| {
        (
            prop::collection::vec(aabb.clone(), n),
            prop::collection::vec(prop::bool::weighted(0.15), n),
        )
    })
}

#[derive(Debug, Clone)]
struct BoxSpec {
    half: [f64; 3],
    translation: [f64; 3],
    rotation: [f64; 4],
    fixed: bool,
}

fn boxes() -> impl Strategy<Value = Vec<BoxSpec>> {
    let spec = (
        (0.05..1.0f64, 0.05..1.0f64, 0.05..1.0f64),
        (0.0..6.0f64, 0.0..6.0f64, 0.0..6.0f64),
        (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64, 0.1..1.0f64),
        prop::bool::weighted(0.2),
    )
        .prop_map(|(h, t, (x, y, z, w), fixed)| {
            let n = (x * x + y * y + z * z + w * w).sqrt();
            BoxSpec {
                half: [h.0, h.1, h.2],
                translation: [t.0, t.1, t.2],
                rotation: [x / n, y / n, z / n, w / n],
                fixed,
            }
        });
    prop::collection::vec(spec, 0..40)
}

fn scene_of(specs: &[BoxSpec]) -> Scene {
    let mut scene = Scene::new();
    for (k, s) in specs.iter().enumerate() {
        scene
            .add_body(BodyDesc {
                name: format!("box{k}"),
                shape: Shape::Cuboid {
                    half_extents: Vector3::from(s.half),
                },
                translation: Vector3::from(s.translation),
                rotation_xyzw: s.rotation,
                mass: if s.fixed {
                    MassSpec::Fixed
                } else {
                    MassSpec::Density(1.0)
                },
            })
            .unwrap();
    }
    scene
}

proptest! {
    #![proptest_config(proptest_config::config(200))]

    #[test]
    fn pairs_of_aabbs_match_brute_force((aabbs, fixed) in aabbs(), margin in 0.0..0.5f64) {
        let found = candidate_pairs_of_aabbs(&aabbs, &fixed, margin).unwrap();
        prop_assert_eq!(found, brute_force(&aabbs, &fixed, margin));
    }

    #[test]
    fn scene_pairs_match_brute_force_and_contain_all_near_pairs(specs in boxes(), margin in 0.0..0.3f64) {
        let scene = scene_of(&specs);
        let found = candidate_pairs(&scene, margin).unwrap();
        // One body's scan (the round-off bound's test) agrees with the
        // pairs: a body has a candidate pair exactly when it is in one.
        let boxes = grown_boxes(&scene, margin).unwrap();
        for i in 0..specs.len() {
            let in_a_pair = found.iter().any(|p| p.body_a == i || p.body_b == i);
            prop_assert_eq!(has_candidate_pair(&boxes, &scene.fixed_flags(), i), in_a_pair);
        }
        let aabbs: Vec<Aabb> = scene.bodies().iter().map(|b| {
            let (min, max) = b.world_aabb();
            Aabb::new(Vector::new(min.x, min.y, min.z), Vector::new(max.x, max.y, max.z))
        }).collect();
        prop_assert_eq!(&found, &brute_force(&aabbs, &scene.fixed_flags(), margin));
        // Oracle from parry: every pair (not both fixed) at distance <= margin is a candidate.
        let pose = |s: &BoxSpec| {
            let [x, y, z, w] = s.rotation;
            Pose::from_parts(Vector::from(s.translation), parry3d_f64::math::Rotation::from_xyzw(x, y, z, w))
        };
        for i in 0..specs.len() {
            for j in i + 1..specs.len() {
                if specs[i].fixed && specs[j].fixed {
                    continue;
                }
                let d = parry3d_f64::query::distance(
                    &pose(&specs[i]), &Cuboid::new(Vector::from(specs[i].half)),
                    &pose(&specs[j]), &Cuboid::new(Vector::from(specs[j].half)),
                ).unwrap().distance;
                if d <= margin {
                    prop_assert!(found.contains(&BodyPair::new(i, j).unwrap()), "pair {} {} at distance {}", i, j, d);
                }
            }
        }
    }
}

/// One pass's moves: (body index, translation added) pairs.
fn moves() -> impl Strategy<Value = Vec<Vec<(usize, [f64; 3])>>> {
    let step = (0..40usize, (-1.5..1.5f64, -1.5..1.5f64, -1.5..1.5f64))
        .prop_map(|(i, t)| (i, [t.0, t.1, t.2]));
    prop::collection::vec(prop::collection::vec(step, 0..30), 1..6)
}

proptest! {
    #![proptest_config(proptest_config::config(200))]

    /// The broad phase kept across passes finds exactly the pairs of a full
    /// build at every pass: a few bodies moved (refit), many (rebuild),
    /// none (reused), moves that make and break overlaps, fixed bodies.
    #[test]
    fn incremental_pairs_equal_a_full_build_after_every_move(
        specs in boxes(), passes in moves(), margin in 0.0..0.3f64,
    ) {
        let mut scene = scene_of(&specs);
        let mut incremental = IncrementalBroadPhase::new();
        let (first, update) = incremental.candidate_pairs(&scene, margin).unwrap();
        prop_assert_eq!(first.to_vec(), candidate_pairs(&scene, margin).unwrap());
        prop_assert_eq!(update, BroadPhaseUpdate::Rebuilt);
        for pass in passes {
            let mut moved = std::collections::BTreeSet::new();
            for (i, shift) in pass {
                let Some(body) = scene.bodies_mut().get_mut(i) else { continue };
                if body.is_fixed() {
                    continue;
                }
                let translation = body.translation_user() + Vector3::from(shift);
                let rotation = body.rotation_user_xyzw();
                body.set_user_pose(translation, rotation).unwrap();
                moved.insert(i);
            }
            let (found, update) = incremental.candidate_pairs(&scene, margin).unwrap();
            prop_assert_eq!(found.to_vec(), candidate_pairs(&scene, margin).unwrap());
            let refit = moved.len() as f64 <= REBUILD_MOVED_FRACTION * specs.len() as f64;
            let expected = if refit { BroadPhaseUpdate::Refitted(moved.len()) } else { BroadPhaseUpdate::Rebuilt };
            prop_assert_eq!(update, expected);
        }
    }
}

/// A changed margin or a body made fixed cannot reuse the stored pairs.
#[test]
fn incremental_rebuilds_when_the_margin_or_the_fixed_flags_change() {
    let specs: Vec<BoxSpec> = (0..4)
        .map(|k| BoxSpec {
            half: [0.5; 3],
            translation: [k as f64 * 1.1, 0.0, 0.0],
            rotation: [0.0, 0.0, 0.0, 1.0],
            fixed: false,
        })
        .collect();
    let mut scene = scene_of(&specs);
    let mut incremental = IncrementalBroadPhase::new();
    let (pairs, _) = incremental.candidate_pairs(&scene, 0.05).unwrap();
    assert!(pairs.is_empty(), "gaps of 0.1 are beyond the margin 0.05");
    let (pairs, update) = incremental.candidate_pairs(&scene, 0.05).unwrap();
    assert_eq!((pairs.len(), update), (0, BroadPhaseUpdate::Refitted(0)));
    let (pairs, update) = incremental.candidate_pairs(&scene, 0.2).unwrap();
    assert_eq!((pairs.len(), update), (3, BroadPhaseUpdate::Rebuilt));
    let mut fixed_specs = specs.clone();
    fixed_specs[0].fixed = true;
    fixed_specs[1].fixed = true;
    scene = scene_of(&fixed_specs);
    let (pairs, update) = incremental.candidate_pairs(&scene, 0.2).unwrap();
    assert_eq!((pairs.len(), update), (2, BroadPhaseUpdate::Rebuilt));
}

#[test]
fn invalid_input_is_an_error() {
    let unit = Aabb::new(Vector::ZERO, Vector::ONE);
    assert_eq!(
        candidate_pairs_of_aabbs(&[unit], &[false], -1.0),
        Err(BroadPhaseError::InvalidMargin(-1.0))
    );
    assert!(matches!(
        candidate_pairs_of_aabbs(&[unit], &[false], f64::NAN),
        Err(BroadPhaseError::InvalidMargin(_))
    ));
    assert_eq!(
        candidate_pairs_of_aabbs(&[unit], &[], 0.0),
        Err(BroadPhaseError::LengthMismatch { aabbs: 1, flags: 0 })
    );
    let inverted = Aabb::new(Vector::ONE, Vector::ZERO);
    assert_eq!(
        candidate_pairs_of_aabbs(&[unit, inverted], &[false, false], 0.0),
        Err(BroadPhaseError::InvalidAabb(1))
    );
}

#[test]
fn touching_boxes_are_candidates_and_fixed_pairs_are_not() {
    let a = Aabb::new(Vector::ZERO, Vector::ONE);
    let b = Aabb::new(Vector::new(1.0, 0.0, 0.0), Vector::new(2.0, 1.0, 1.0));
    let c = Aabb::new(Vector::new(2.0, 0.0, 0.0), Vector::new(3.0, 1.0, 1.0));
    let found = candidate_pairs_of_aabbs(&[a, b, c], &[true, false, true], 0.0).unwrap();
    assert_eq!(
        found,
        vec![BodyPair::new(0, 1).unwrap(), BodyPair::new(1, 2).unwrap()]
    );
    let both_fixed = candidate_pairs_of_aabbs(&[a, b], &[true, true], 0.0).unwrap();
    assert!(both_fixed.is_empty());
}
