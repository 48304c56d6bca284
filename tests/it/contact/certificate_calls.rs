//! Separation certificates kept by the stabilizer across the passes of a
//! call and across calls (`contact::certificate`): a call with them gives
//! the poses of a call without them, bit for bit (a certified pair gives no
//! row either way), over warm sequences of engine states and a Rapier
//! loop; stale certificates (bodies removed, added, reordered, replaced,
//! shapes changed, margin changed) certify nothing wrong: the call's poses
//! are a fresh stabilizer's; an unchanged scene called twice queries no
//! pair (the answers at unchanged poses are reused).

use std::sync::Arc;

use constraint_stabilization::body::{Body, BodyDesc, MassSpec, Shape};
use constraint_stabilization::internals::geometry::ConvexPolyhedron;
use constraint_stabilization::scene::Scene;
use constraint_stabilization::{Report, Settings, Stabilizer};
use dev_support::random::random_rotation;
use dev_support::scene::{cuboid, ground, pose_bits, xyzw};
use nalgebra::{Point3, Vector3};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::support::proptest_config::config;

/// The default settings with the certificates on or off, and without the
/// solver's warm starts: a kept stabilizer's solvers would start from its
/// earlier answers and a fresh one's would not, which moves the poses at
/// rounding level (`solver/warm_starts.rs` and
/// `solver/dual_active_set_warm.rs` test those answers against cold ones
/// within their tolerance); bit for bit, only the certificates may differ.
fn settings(certificates: bool) -> Settings {
    let mut settings = Settings::default();
    settings.vclip.motion_certificates = certificates;
    settings.solver.warm_starts = false;
    settings
}

fn stabilizer(settings: Settings) -> Stabilizer {
    Stabilizer::new(settings).expect("valid settings")
}

/// One call of `stabilizer` on a copy of `input`.
fn call(stabilizer: &mut Stabilizer, input: &Scene) -> (Report, Scene) {
    let mut scene = input.clone();
    let report = stabilizer.stabilize(&mut scene).expect("a valid scene");
    (report, scene)
}

fn assert_same_poses(a: &Scene, b: &Scene, label: &str) {
    assert!(pose_bits(a) == pose_bits(b), "{label}: the poses differ");
}

/// How the scene changes between the call that records certificates and
/// the call that could use them.
#[derive(Debug, Clone, Copy)]
enum Change {
    /// A body removed from the scene directly (later indices shift onto
    /// bodies of the same shape object).
    RemovedDirectly,
    /// A body removed through the stabilizer.
    RemovedThroughStabilizer,
    /// A new box of the shared shape inserted at index 1 (later indices
    /// shift), pressed into its neighbour.
    Added,
    /// The bodies in reverse order (the same shape objects under other
    /// indices).
    Reordered,
    /// A box replaced by a larger hull at its pose (another shape object).
    Replaced,
    /// A box's shape changed to a larger box (another shape object).
    ShapeChanged,
    /// The contact margin raised from the default (8.7 mm) to 0.3 m.
    MarginChanged,
}

/// The unit cube shared by the row's boxes ([`Body::with_polyhedron`]).
fn cube_desc(at: Vector3<f64>, rng: &mut ChaCha8Rng) -> BodyDesc {
    cuboid(
        "box",
        [0.5, 0.5, 0.5],
        at.into(),
        xyzw(&random_rotation(rng)),
        MassSpec::Mass(1.0),
    )
}

/// The ground and `count` randomly turned unit cubes along x, 1.3 to 2 m
/// apart, their centres 0.3 to 1.2 m above the ground's top: some sunk
/// into the ground, some afloat, neighbours' boxes overlapping at various
/// distances. The cubes share one shape object.
fn row(seed: u64, count: usize) -> (Scene, Arc<ConvexPolyhedron>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut scene = Scene::new();
    scene.add_body(ground()).expect("a valid ground");
    let shared = Body::new(cube_desc(Vector3::zeros(), &mut rng))
        .expect("a valid cube")
        .parts()[0]
        .polyhedron()
        .clone();
    let mut x = 0.0;
    for _ in 0..count {
        let at = Vector3::new(x, rng.random_range(0.3..1.2), 0.0);
        let body = Body::with_polyhedron(cube_desc(at, &mut rng), shared.clone());
        scene.push_body(body.expect("a valid cube"));
        x += rng.random_range(1.3..2.0);
    }
    (scene, shared)
}

/// `scene` changed by `change` (for `RemovedThroughStabilizer`, through
/// each of `stabilizers`); the settings of the next calls.
fn changed(
    scene: &Scene,
    change: Change,
    shared: &Arc<ConvexPolyhedron>,
    stabilizers: &mut [&mut Stabilizer],
) -> (Scene, Option<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut scene = scene.clone();
    let pose_of = |scene: &Scene, index: usize| *scene.bodies()[index].com_pose();
    match change {
        Change::RemovedDirectly => {
            scene.remove_bodies(&[1]).expect("an index in range");
        }
        Change::RemovedThroughStabilizer => {
            let input = scene.clone();
            for stabilizer in stabilizers.iter_mut() {
                let mut copy = input.clone();
                stabilizer
                    .remove_bodies(&mut copy, &[1])
                    .expect("an index in range");
                scene = copy;
            }
        }
        Change::Added => {
            let next = pose_of(&scene, 1).translation.vector;
            let at = next - Vector3::new(0.9, 0.0, 0.0);
            let body = Body::with_polyhedron(cube_desc(at, &mut rng), shared.clone());
            let mut rebuilt = Scene::new();
            rebuilt.push_body(scene.bodies()[0].clone());
            rebuilt.push_body(body.expect("a valid cube"));
            scene.bodies()[1..]
                .iter()
                .for_each(|b| _ = rebuilt.push_body(b.clone()));
            scene = rebuilt;
        }
        Change::Reordered => {
            let mut reordered = Scene::new();
            scene
                .bodies()
                .iter()
                .rev()
                .for_each(|b| _ = reordered.push_body(b.clone()));
            scene = reordered;
        }
        Change::Replaced | Change::ShapeChanged => {
            let body = &scene.bodies()[2];
            let shape = match change {
                Change::Replaced => Shape::ConvexHull {
                    points: (0..16)
                        .map(|_| Point3::from(Vector3::from_fn(|_, _| rng.random_range(-1.1..1.1))))
                        .collect(),
                },
                _ => Shape::Cuboid {
                    half_extents: Vector3::new(0.9, 0.9, 0.9),
                },
            };
            let replacement = Body::new(BodyDesc {
                name: "replacement".into(),
                shape,
                translation: body.com_pose().translation.vector,
                rotation_xyzw: body.rotation_user_xyzw(),
                mass: MassSpec::Mass(1.0),
            })
            .expect("a valid body");
            scene.bodies_mut()[2] = replacement;
        }
        Change::MarginChanged => return (scene, Some(0.3)),
    }
    (scene, None)
}

/// Stale certificates in one form: the kept stabilizers' second call (with
/// and without certificates) gives a fresh stabilizer's poses, bit for
/// bit; so does their first call. Returns the pairs certified or answered
/// by an earlier answer at the same poses, in both calls.
fn check_stale(seed: u64, change: Change) -> usize {
    let (input, shared) = row(seed, 6);
    let mut with = stabilizer(settings(true));
    let mut without = stabilizer(settings(false));
    let (first, after_with) = call(&mut with, &input);
    let (_, after_without) = call(&mut without, &input);
    assert_same_poses(&after_with, &after_without, "first call");
    let (next, margin) = changed(&after_with, change, &shared, &mut [&mut with, &mut without]);
    let next_settings = |certificates: bool| {
        let mut next = settings(certificates);
        next.contact_margin_absolute = margin;
        next
    };
    for kept in [&mut with, &mut without] {
        let certificates = kept.settings().vclip.motion_certificates;
        kept.set_settings(next_settings(certificates))
            .expect("valid settings");
    }
    let (report, warm) = call(&mut with, &next);
    let (_, warm_without) = call(&mut without, &next);
    let (_, cold) = call(&mut stabilizer(next_settings(false)), &next);
    let label = format!("{change:?}, seed {seed}");
    assert_same_poses(&warm, &cold, &label);
    assert_same_poses(&warm_without, &cold, &label);
    let skipped = |r: &Report| r.certified_pairs + r.reused_pairs;
    skipped(&first) + skipped(&report)
}

proptest! {
    #![proptest_config(config(14))]

    #[test]
    fn stale_certificates_certify_nothing_wrong(
        seed in any::<u64>(),
        change in prop_oneof![
            Just(Change::RemovedDirectly),
            Just(Change::RemovedThroughStabilizer),
            Just(Change::Added),
            Just(Change::Reordered),
            Just(Change::Replaced),
            Just(Change::ShapeChanged),
            Just(Change::MarginChanged),
        ],
    ) {
        check_stale(seed, change);
    }
}

/// The stale check is not vacuous: over fixed seeds, every change but the
/// removal through the stabilizer (which drops the certificates) and the
/// raised margin (which reaches the pairs) leaves certificates in use.
#[test]
fn stale_scenes_use_certificates() {
    for change in [
        Change::RemovedDirectly,
        Change::Added,
        Change::Reordered,
        Change::Replaced,
        Change::ShapeChanged,
    ] {
        let skipped: usize = (0..6).map(|seed| check_stale(seed, change)).sum();
        assert!(skipped > 0, "{change:?}: nothing certified or reused");
    }
}

#[cfg(feature = "serde")]
mod engine_sequences {
    use constraint_stabilization::scene::Scene;
    use nalgebra::{Translation3, Vector3};

    use super::{assert_same_poses, call, settings, stabilizer};
    use crate::support::engine_states::engine_state;

    /// Every dynamic body lowered along the up axis `z` by `step` times
    /// 1, 2 or 3 (by index): the next state of a warm sequence.
    fn pressed(scene: &Scene, step: f64) -> Scene {
        let mut scene = scene.clone();
        for index in 0..scene.len() {
            if scene.bodies()[index].is_fixed() {
                continue;
            }
            let drop = step * (1 + index % 3) as f64;
            let pose = Translation3::from(Vector3::new(0.0, 0.0, -drop))
                * scene.bodies()[index].com_pose();
            scene.set_com_pose(index, pose).expect("a finite pose");
        }
        scene
    }

    /// Warm sequences of engine states (each called, its answer pressed
    /// down a little, called again, with one kept stabilizer each): with
    /// and without certificates, the same poses bit for bit, and the
    /// certificates skipped pairs (not in the pyramid, whose candidate
    /// pairs are all within the margin).
    #[test]
    fn with_and_without_certificates_give_the_same_poses() {
        let mut certified = 0;
        for stem in [
            "rp05_pyramid",
            "rp08_mixed_pile",
            "mj01_box_bin",
            "bt07_jumble_midfall",
        ] {
            let mut input = engine_state(stem);
            let mut with = stabilizer(settings(true));
            let mut without = stabilizer(settings(false));
            for k in 0..3 {
                let (report, after_with) = call(&mut with, &input);
                let (plain, after_without) = call(&mut without, &input);
                assert_same_poses(&after_with, &after_without, &format!("{stem}, call {k}"));
                assert_eq!(plain.certified_pairs, 0);
                assert!(
                    report.pair_queries <= plain.pair_queries,
                    "{stem}, call {k}"
                );
                certified += report.certified_pairs;
                input = pressed(&after_with, 1e-3);
            }
        }
        assert!(certified > 0, "nothing certified");
    }

    /// An unchanged scene called twice: the second call queries no pair at
    /// all; every candidate pair reuses the first call's last answer at the
    /// same poses, or is certified by an earlier one (a pair certified in
    /// the first call's last pass was last answered at earlier poses).
    #[test]
    fn an_unchanged_scene_queries_no_pair() {
        for stem in ["rp05_pyramid", "rp01_pile_200", "rp08_mixed_pile"] {
            let mut kept = stabilizer(settings(true));
            let (_, settled) = call(&mut kept, &engine_state(stem));
            let (report, again) = call(&mut kept, &settled);
            assert_same_poses(&again, &settled, stem);
            let pass = &report.pass_reports[0];
            assert_eq!(report.pair_queries, 0, "{stem}: {pass:?}");
            let skipped = pass.reused_pairs + pass.certified_pairs;
            assert_eq!(skipped, pass.candidate_pairs, "{stem}: {pass:?}");
        }
    }

    /// The same unchanged scene called twice without certificates queries
    /// every candidate pair again, and ends where the call with them does.
    #[test]
    fn without_certificates_an_unchanged_scene_is_queried_again() {
        let input = engine_state("rp05_pyramid");
        let mut with = stabilizer(settings(true));
        let mut without = stabilizer(settings(false));
        let (_, settled) = call(&mut with, &input);
        call(&mut without, &input);
        let (report, again) = call(&mut without, &settled);
        let (_, again_with) = call(&mut with, &settled);
        assert_same_poses(&again, &again_with, "second call");
        let pass = &report.pass_reports[0];
        assert_eq!(pass.queried_pairs, pass.candidate_pairs, "{pass:?}");
        assert_eq!(pass.reused_pairs + pass.certified_pairs, 0, "{pass:?}");
    }
}

#[cfg(feature = "rapier")]
mod rapier_loop {
    use constraint_stabilization::rapier_bridge::{BridgeSettings, RapierBridge, pose_to_f64};
    use rapier3d::prelude::*;

    use super::settings;

    /// A small pile: a ground slab and 18 boxes and balls dropped in three
    /// layers, turned, onto it.
    fn pile() -> PhysicsWorld {
        let mut world = PhysicsWorld {
            gravity: Vector::new(0.0, 0.0, -9.81),
            ..PhysicsWorld::default()
        };
        let ground = world.insert_body(RigidBodyBuilder::fixed());
        let floor = ColliderBuilder::cuboid(3.0, 3.0, 0.5).translation(Vector::new(0.0, 0.0, -0.5));
        world.insert_collider(floor, Some(ground));
        for k in 0..18 {
            let (i, j, layer) = (k % 3, (k / 3) % 2, k / 6);
            let at = Vector::new(
                i as f32 * 0.45 - 0.45 + 0.05 * layer as f32,
                j as f32 * 0.45 - 0.2,
                0.25 + 0.42 * layer as f32,
            );
            let body = RigidBodyBuilder::dynamic()
                .translation(at)
                .rotation(Vector::new(0.3 * k as f32, 0.2, 0.1 * layer as f32));
            let collider = if k % 4 == 3 {
                ColliderBuilder::ball(0.2)
            } else {
                ColliderBuilder::cuboid(0.2, 0.2, 0.2)
            };
            world.insert(body, collider);
        }
        world
    }

    /// The bodies' poses (f32, converted exactly).
    fn positions(world: &PhysicsWorld) -> Vec<nalgebra::Isometry3<f64>> {
        world
            .bodies
            .iter()
            .map(|(_, body)| pose_to_f64(body.position()))
            .collect()
    }

    /// The same world stepped 80 times, each step followed by a call of a
    /// bridge (the default coupling) with and without certificates: the
    /// same Rapier poses bit for bit after every step, and the certificates
    /// skipped pairs.
    #[test]
    fn a_rapier_loop_with_and_without_certificates_gives_the_same_poses() {
        let mut worlds = [pile(), pile()];
        let mut bridges = [true, false].map(|certificates| {
            RapierBridge::with_settings(BridgeSettings::with_stabilizer(settings(certificates)))
                .expect("valid settings")
        });
        let mut certified = 0;
        for step in 0..80 {
            for (world, bridge) in worlds.iter_mut().zip(&mut bridges) {
                world.step();
                let report = bridge.stabilize_world(world).expect("a valid world");
                if let Some(stabilizer) = report.stabilizer.as_ref() {
                    certified += stabilizer.certified_pairs;
                }
            }
            assert!(
                positions(&worlds[0]) == positions(&worlds[1]),
                "step {step}: the poses differ"
            );
        }
        assert!(certified > 0, "nothing certified");
    }
}

/// The kept certificates are freed with their bodies: all of them when
/// bodies are removed through the stabilizer, and those of another scene
/// once a call has not used them.
#[test]
fn the_kept_certificates_are_freed() {
    let (first, _) = row(3, 6);
    let (second, _) = row(4, 5);
    let mut kept = stabilizer(settings(true));
    let (_, after) = call(&mut kept, &first);
    assert!(kept.separation_certificates() > 0);
    let mut removed = after.clone();
    kept.remove_bodies(&mut removed, &[1])
        .expect("an index in range");
    assert_eq!(kept.separation_certificates(), 0);
    call(&mut kept, &first);
    let mut fresh = stabilizer(settings(true));
    for _ in 0..2 {
        call(&mut kept, &second);
        call(&mut fresh, &second);
    }
    assert_eq!(
        kept.separation_certificates(),
        fresh.separation_certificates()
    );
}
