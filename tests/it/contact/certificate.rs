//! Separation certificates (`contact::certificate`): the motion bound
//! covers every point of a moved solid; a pair the certificate skips is
//! separated beyond the margin by the independent oracles (parry3d-f64 for
//! polyhedra, the support-function oracle for round and curved solids);
//! the margin used is the current one.

use constraint_stabilization::Settings;
use constraint_stabilization::body::{Body, BodyDesc, MassSpec};
use constraint_stabilization::internals::broad_phase::IncrementalBroadPhase;
use constraint_stabilization::internals::contact::certificate::{motion_bound, reach};
use constraint_stabilization::internals::contact::{
    Detection, DetectionState, QueryMemo, SceneGeometry, SceneParts, SeparationCertificates,
    WarmStartCache, detect,
};
use constraint_stabilization::internals::vclip::VClip;
use constraint_stabilization::scene::Scene;
use dev_support::random::{
    MIXED_SHAPE_KINDS, mixed_shape, random_hull, random_pose, random_rotation,
};
use dev_support::scene::xyzw;
use dev_support::support_oracle::body_signed_distance;
use dev_support::vclip::{parry_distance, parry_shape};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::support::proptest_config::config;

/// Rounding allowed in the bound's check: the displacement and the bound
/// are computed in floating point from coordinates of order 10.
const BOUND_ROUNDING: f64 = 1e-12;

/// Every vertex of a random hull moves by at most the bound between two
/// random poses (small and large rotations alike).
fn check_bound(seed: u64) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let radius = rng.random_range(0.1..3.0);
    let hull = random_hull(&mut rng, 12, radius);
    let from = random_pose(&mut rng, 5.0);
    let angle = if rng.random_bool(0.5) {
        rng.random_range(0.0..1e-3)
    } else {
        rng.random_range(0.0..std::f64::consts::PI)
    };
    let axis = nalgebra::Unit::new_normalize(Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0)));
    let turn = UnitQuaternion::from_axis_angle(&axis, angle);
    let shift = Translation3::from(Vector3::from_fn(|_, _| rng.random_range(-0.5..0.5)));
    let to = shift * Isometry3::from_parts(from.translation, turn * from.rotation);
    let bound = motion_bound(&from, &to, reach(&hull, None));
    for vertex in hull.vertices() {
        let moved = (to * vertex - from * vertex).norm();
        assert!(
            moved <= bound + BOUND_ROUNDING,
            "seed {seed}: a vertex moved {moved:e}, bound {bound:e}"
        );
    }
}

/// One body of kind `kind` (`dev_support::random::mixed_shape`, size 1) at
/// `at`, randomly turned.
fn random_body(rng: &mut ChaCha8Rng, kind: usize, at: Vector3<f64>) -> Option<Body> {
    Body::new(BodyDesc {
        name: format!("kind{kind}"),
        shape: mixed_shape(rng, kind, 1.0),
        translation: at,
        rotation_xyzw: xyzw(&random_rotation(rng)),
        mass: MassSpec::Mass(1.0),
    })
    .ok()
}

/// Detection of `scene` with `certificates` (`None`: without) and a fresh
/// memo and warm-start cache, at contact margin `margin`.
fn detection(
    scene: &Scene,
    certificates: Option<&mut SeparationCertificates>,
    margin: f64,
) -> Detection {
    let mut settings = Settings::default();
    settings.contact_margin_absolute = Some(margin);
    let lengths = settings.resolve(1.0);
    let parts = SceneParts::of(scene);
    let poses: Vec<Isometry3<f64>> = scene.bodies().iter().map(|b| *b.com_pose()).collect();
    let part_poses = parts.poses(&poses);
    let geometry = SceneGeometry {
        parts: &parts,
        poses: &part_poses,
    };
    let state = DetectionState {
        broad_phase: &mut IncrementalBroadPhase::new(),
        cache: &mut WarmStartCache::default(),
        memo: &mut QueryMemo::default(),
        certificates,
        kept_pairs: &[],
    };
    detect(
        scene,
        geometry,
        state,
        &VClip::new(settings.vclip),
        &lengths,
    )
    .expect("valid poses")
}

/// The signed distance of bodies 0 and 1 by an independent oracle:
/// parry3d-f64 for two polyhedra (kinds 4 and 5), else the
/// support-function oracle (a lower bound on the distance of separated
/// solids, within 2e-8 of it).
fn oracle_distance(scene: &Scene) -> f64 {
    let [a, b] = [&scene.bodies()[0], &scene.bodies()[1]];
    let polyhedral = |body: &Body| {
        body.parts()[0].rounding().is_none() && body.shape().surface_deviation() == 0.0
    };
    if polyhedral(a) && polyhedral(b) {
        let pose = |body: &Body| body.part_poses().next().expect("one part");
        let shape = |body: &Body| parry_shape(body.parts()[0].polyhedron());
        return parry_distance(&shape(a), &pose(a), &shape(b), &pose(b));
    }
    body_signed_distance(a, b)
}

/// A random motion of a body: a translation up to `shift` and a turn up
/// to `angle` about its centre of mass.
fn moved(rng: &mut ChaCha8Rng, pose: &Isometry3<f64>, shift: f64, angle: f64) -> Isometry3<f64> {
    let axis = nalgebra::Unit::new_normalize(Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0)));
    let turn = UnitQuaternion::from_axis_angle(&axis, rng.random_range(0.0..angle));
    let direction = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0));
    let step = direction.normalize() * rng.random_range(0.0..shift);
    Isometry3::from_parts(
        Translation3::from(pose.translation.vector + step),
        turn * pose.rotation,
    )
}

/// One random pair, detected, moved and detected again with the
/// certificates of the first detection: whether the certificate skipped
/// the pair (`None`: the pair was not even a broad-phase candidate). A
/// skipped pair is separated beyond the margin by the oracle, and a
/// detection without certificates finds it neither active nor penetrating.
fn check_pair(seed: u64) -> Option<bool> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let kinds = [0, 1].map(|_| rng.random_range(0..MIXED_SHAPE_KINDS));
    let offset = Vector3::from_fn(|_, _| rng.random_range(-2.0..2.0));
    let a = random_body(&mut rng, kinds[0], Vector3::zeros())?;
    let b = random_body(&mut rng, kinds[1], offset)?;
    let mut scene = Scene::new();
    scene.push_body(a);
    scene.push_body(b);
    let margin = rng.random_range(0.0..0.3);
    let mut store = SeparationCertificates::default();
    detection(&scene, Some(&mut store), margin);
    let (shift, angle) = (rng.random_range(0.0..0.5), rng.random_range(0.0..0.5));
    for index in 0..2 {
        let pose = moved(&mut rng, scene.bodies()[index].com_pose(), shift, angle);
        scene.set_com_pose(index, pose).expect("a finite pose");
    }
    let with = detection(&scene, Some(&mut store), margin);
    if with.candidates == 0 {
        return None;
    }
    let certified = with.certified == 1;
    if certified {
        let distance = oracle_distance(&scene);
        assert!(
            distance > margin,
            "seed {seed}: certified, but the oracle's distance is {distance:e} (margin {margin:e})"
        );
        let without = detection(&scene, None, margin);
        assert!(
            without.active_pairs.is_empty() && without.penetrations.is_empty(),
            "seed {seed}: certified, but a query finds the pair active"
        );
    }
    Some(certified)
}

proptest! {
    #![proptest_config(config(64))]

    #[test]
    fn the_motion_bound_covers_every_vertex(seed in any::<u64>()) {
        check_bound(seed);
    }

    #[test]
    fn a_certified_pair_is_separated_beyond_the_margin(seed in any::<u64>()) {
        check_pair(seed);
    }
}

/// The soundness check above is not vacuous: over fixed seeds, the
/// certificate skips some of the candidate pairs (measured 19 of 116),
/// and every skip is confirmed by the oracle.
#[test]
fn certificates_skip_many_candidate_pairs_all_confirmed() {
    let answers: Vec<bool> = (0..300).filter_map(check_pair).collect();
    let skipped = answers.iter().filter(|&&c| c).count();
    assert!(
        answers.len() >= 100 && skipped >= 10,
        "{skipped} of {} candidate pairs certified",
        answers.len()
    );
}

/// The margin of a certificate is the current one: a pair recorded
/// beyond a small margin is queried again under a larger one that reaches
/// it, and becomes active. (Two unit cubes whose boxes overlap, the second
/// turned by 45 degrees about z: 0.35 apart.)
#[test]
fn a_larger_margin_is_not_certified_by_a_smaller_one() {
    let turned = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), std::f64::consts::FRAC_PI_4);
    let mut scene = Scene::new();
    for (at, rotation) in [
        ([0.0, 0.0, 0.0], UnitQuaternion::identity()),
        ([1.1, 1.1, 0.0], turned),
    ] {
        let desc = dev_support::scene::cuboid(
            "box",
            [0.5, 0.5, 0.5],
            at,
            xyzw(&rotation),
            MassSpec::Mass(1.0),
        );
        scene.push_body(Body::new(desc).expect("a valid box"));
    }
    let mut store = SeparationCertificates::default();
    let small = detection(&scene, Some(&mut store), 0.05);
    assert_eq!((small.queried, small.active_pairs.len()), (1, 0));
    // Unmoved: the answer itself is reused. Moved 1 cm apart: certified.
    let unmoved = detection(&scene, Some(&mut store), 0.05);
    assert_eq!((unmoved.queried, unmoved.reused), (0, 1));
    let apart = nalgebra::Translation3::new(0.01, 0.0, 0.0) * scene.bodies()[1].com_pose();
    scene.set_com_pose(1, apart).expect("a finite pose");
    let again = detection(&scene, Some(&mut store), 0.05);
    assert_eq!((again.queried, again.certified), (0, 1));
    let large = detection(&scene, Some(&mut store), 0.5);
    assert_eq!((large.queried, large.certified), (1, 0));
    assert_eq!(large.active_pairs.len(), 1);
}
