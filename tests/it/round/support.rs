//! Cylinders and cones on their true solids by support functions
//! (`VClipSettings::curved_support_functions`, `contact::round::support_pair`):
//! random pairs of a cylinder or cone with every kind against the
//! support-function oracle (`dev_support::support_oracle`), the stated
//! bound [`SUPPORT_AGREEMENT`]; parry's contact query as a cross-check.

use super::signed_distance;
use crate::support::proptest_config;
use constraint_stabilization::body::{Body, BodyDesc, MassSpec, Shape};
use constraint_stabilization::internals::contact::{self, BodyGeometry, PairQuery};
use constraint_stabilization::internals::vclip::{VClip, VClipSettings};
use dev_support::random::{MIXED_SHAPE_KINDS, mixed_shape, random_rotation};
use dev_support::scene::xyzw;
use dev_support::support_oracle::body_signed_distance;
use nalgebra::Vector3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The support path's agreement with the oracle, relative to the pair's
/// size (about 1 here): 2e-2 of the default tolerance (`1e-6` of the
/// scene's length scale) when the scene is no larger than the pair, less
/// for a larger scene.
pub const SUPPORT_AGREEMENT: f64 = 2e-8;

/// Part `k` of `body` as the support-function narrow phase sees it.
pub fn curved_part_geometry(body: &Body, k: usize) -> BodyGeometry<'_> {
    super::part_geometry(body, k).curved(body.part_curved(k))
}

/// V-Clip settings with the support-function path on.
pub fn support_vclip() -> VClip {
    VClip::new(VClipSettings {
        curved_support_functions: true,
        ..VClipSettings::default()
    })
}

/// The support path's answers for every part pair.
pub fn support_queries(a: &Body, b: &Body) -> Vec<PairQuery> {
    let vclip = support_vclip();
    let mut answers = Vec::new();
    for ka in 0..a.parts().len() {
        for kb in 0..b.parts().len() {
            let (ga, gb) = (curved_part_geometry(a, ka), curved_part_geometry(b, kb));
            answers.push(contact::query(&vclip, &ga, &gb, None).expect("a valid query"));
        }
    }
    answers
}

/// The support path's signed distance of two bodies.
pub fn support_signed_distance(a: &Body, b: &Body) -> f64 {
    support_queries(a, b)
        .iter()
        .map(PairQuery::signed_value)
        .fold(f64::INFINITY, f64::min)
}

/// A body of shape kind `kind` (of `dev_support::random::mixed_shape`,
/// size 1) at `at`, randomly turned; `None` when the library rejects it.
pub(super) fn random_body(rng: &mut ChaCha8Rng, kind: usize, at: Vector3<f64>) -> Option<Body> {
    Body::new(BodyDesc {
        name: "b".into(),
        shape: mixed_shape(rng, kind, 1.0),
        translation: at,
        rotation_xyzw: xyzw(&random_rotation(rng)),
        mass: MassSpec::Mass(1.0),
    })
    .ok()
}

/// One random pair: a cylinder or cone (`curved` 6 or 7) and kind `kind`;
/// returns the error against the oracle.
fn check_pair(seed: u64, curved: usize, kind: usize) -> Option<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let offset = Vector3::from_fn(|_, _| rng.random_range(-0.9..0.9));
    let a = random_body(&mut rng, curved, offset)?;
    let b = random_body(&mut rng, kind, Vector3::zeros())?;
    let library = support_signed_distance(&a, &b);
    let oracle = body_signed_distance(&a, &b);
    assert!(
        (library - oracle).abs() <= SUPPORT_AGREEMENT,
        "seed {seed}, kinds {curved} {kind}: support {library:e}, oracle {oracle:e}\n{:?}\n{:?}",
        a.shape(),
        b.shape()
    );
    // The support path never reports less depth (or more distance) than
    // an overlap reached allows: it is at most the polyhedra's bound away.
    let polyhedra = signed_distance(&a, &b);
    assert!(library >= polyhedra - 1e-12, "{library:e} {polyhedra:e}");
    Some((library - oracle).abs())
}

proptest::proptest! {
    #![proptest_config(proptest_config::config(64))]

    /// A cylinder or cone against every kind.
    #[test]
    fn support_pairs_agree_with_the_oracle(seed in 0u64..u64::MAX, curved in 6usize..8, kind in 0..MIXED_SHAPE_KINDS) {
        check_pair(seed, curved, kind);
    }
}

/// Every combination, several seeds each; the worst error printed
/// (`--nocapture`).
#[test]
fn support_every_combination_of_kinds() {
    let mut worst: f64 = 0.0;
    let mut count = 0;
    for curved in 6..8 {
        for kind in 0..MIXED_SHAPE_KINDS {
            for seed in 0..10 {
                if let Some(error) = check_pair(7000 + 100 * kind as u64 + seed, curved, kind) {
                    worst = worst.max(error);
                    count += 1;
                }
            }
        }
    }
    println!("support path: worst |error| against the oracle {worst:.3e} over {count} pairs");
}

/// A cylinder in a compound (with a box) against a cone.
#[test]
fn support_compound_part() {
    use constraint_stabilization::body::ShapePart;
    let compound = Shape::Compound {
        parts: vec![
            ShapePart {
                shape: Shape::Cylinder {
                    half_height: 0.3,
                    radius: 0.2,
                },
                translation: Vector3::new(0.2, 0.0, 0.0),
                rotation_xyzw: [0.0, 0.0, 0.0, 1.0],
            },
            ShapePart {
                shape: Shape::Cuboid {
                    half_extents: Vector3::new(0.1, 0.1, 0.4),
                },
                translation: Vector3::new(-0.2, 0.0, 0.0),
                rotation_xyzw: [0.0, 0.0, 0.0, 1.0],
            },
        ],
    };
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for _ in 0..10 {
        let a = Body::new(BodyDesc {
            name: "c".into(),
            shape: compound.clone(),
            translation: Vector3::from_fn(|_, _| rng.random_range(-0.3..0.3)),
            rotation_xyzw: xyzw(&random_rotation(&mut rng)),
            mass: MassSpec::Mass(1.0),
        })
        .expect("valid");
        let b = random_body(&mut rng, 7, Vector3::new(0.0, 0.0, 0.5)).expect("valid");
        let library = support_signed_distance(&a, &b);
        let oracle = body_signed_distance(&a, &b);
        assert!(
            (library - oracle).abs() <= SUPPORT_AGREEMENT,
            "{library:e} {oracle:e}"
        );
    }
}
