//! The support path's rows against the oracle's exact signed distance
//! under motion: for random pairs of a cylinder or cone with every kind,
//! the central finite difference of the oracle's signed distance
//! (`dev_support::support_oracle`) under a small translation `s` or
//! rotation `w` of body A (about its user origin `o`) equals the change
//! its deepest row predicts,
//!
//! ```text
//! d sd = n . s + n . (w x (p_a - o))
//! ```
//!
//! with `n` the row's normal and `p_a` its point on A: the row's normal is
//! the direction of steepest change of the true signed distance and its
//! point the true contact point. Pairs whose deepest rows tie (a flat
//! contact) have no such derivative under rotation and are skipped (their
//! translation derivative is still checked).

use super::support::{curved_part_geometry, random_body};
use constraint_stabilization::Settings;
use constraint_stabilization::body::{Body, BodyDesc, MassSpec};
use constraint_stabilization::internals::contact;
use constraint_stabilization::internals::vclip::{VClip, VClipSettings};
use dev_support::random::MIXED_SHAPE_KINDS;
use dev_support::scene::xyzw;
use dev_support::support_oracle::body_signed_distance;
use nalgebra::{UnitQuaternion, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Step of the finite differences (length, and radians), the pairs being
/// of size about 1.
const STEP: f64 = 1e-5;

/// Agreement of a finite difference with the row's prediction: the
/// oracle's error over the step (about 1e-9 / 1e-5) plus the curvature's
/// second-order term over the step.
const DERIVATIVE_AGREEMENT: f64 = 5e-4;

/// Rows whose separations are within this of the least one tie (a flat
/// contact).
const TIE: f64 = 1e-6;

/// Margin within which rows are built (every near pair gets its rows).
const MARGIN: f64 = 0.5;

/// `body` moved by `shift` and turned by `turn` (rotation vector) about
/// its user origin.
fn moved(body: &Body, shift: Vector3<f64>, turn: Vector3<f64>) -> Body {
    let [x, y, z, w] = body.rotation_user_xyzw();
    let rotation = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(w, x, y, z));
    Body::new(BodyDesc {
        name: "moved".into(),
        shape: body.shape().clone(),
        translation: body.translation_user() + shift,
        rotation_xyzw: xyzw(&(UnitQuaternion::from_scaled_axis(turn) * rotation)),
        mass: MassSpec::Mass(1.0),
    })
    .expect("a moved valid body is valid")
}

/// Checks one pair; returns whether its rotation derivatives were checked
/// (`None`: no pair built or no row).
fn check_pair(seed: u64, curved: usize, kind: usize, worst: &mut f64) -> Option<bool> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let offset = Vector3::from_fn(|_, _| rng.random_range(-0.9..0.9));
    let a = random_body(&mut rng, curved, offset)?;
    let b = random_body(&mut rng, kind, Vector3::zeros())?;
    let (ga, gb) = (curved_part_geometry(&a, 0), curved_part_geometry(&b, 0));
    let vclip = VClip::new(VClipSettings {
        curved_support_functions: true,
        ..VClipSettings::default()
    });
    let query = contact::query(&vclip, &ga, &gb, None).expect("a valid query");
    let points = contact::contact_points(&query, &ga, &gb, MARGIN, &Settings::default()).points;
    let least = points
        .iter()
        .map(|p| p.separation)
        .fold(f64::INFINITY, f64::min);
    let tied: Vec<_> = points
        .iter()
        .filter(|p| p.separation <= least + TIE)
        .collect();
    let deepest = tied.first()?;
    let origin = a.translation_user();
    let single = tied.len() == 1;
    let axes = [Vector3::x(), Vector3::y(), Vector3::z()];
    for (k, axis) in axes.iter().enumerate() {
        let shift = axis * STEP;
        let difference = (body_signed_distance(&moved(&a, shift, Vector3::zeros()), &b)
            - body_signed_distance(&moved(&a, -shift, Vector3::zeros()), &b))
            / (2.0 * STEP);
        let predicted = deepest.normal_world[k];
        *worst = worst.max((difference - predicted).abs());
        assert!(
            (difference - predicted).abs() <= DERIVATIVE_AGREEMENT,
            "seed {seed}, kinds {curved} {kind}, shift {k}: oracle {difference:e}, row {predicted:e}\n{:?}\n{:?}",
            a.shape(),
            b.shape()
        );
        if !single {
            continue;
        }
        let turn = axis * STEP;
        let difference = (body_signed_distance(&moved(&a, Vector3::zeros(), turn), &b)
            - body_signed_distance(&moved(&a, Vector3::zeros(), -turn), &b))
            / (2.0 * STEP);
        let lever = deepest.point_a_world.coords - origin;
        let predicted = lever.cross(&deepest.normal_world)[k];
        *worst = worst.max((difference - predicted).abs());
        assert!(
            (difference - predicted).abs() <= DERIVATIVE_AGREEMENT,
            "seed {seed}, kinds {curved} {kind}, turn {k}: oracle {difference:e}, row {predicted:e}\n{:?}\n{:?}",
            a.shape(),
            b.shape()
        );
    }
    Some(single)
}

/// Two seeds of every combination of a cylinder or cone with every kind.
#[test]
fn support_rows_are_the_gradient_of_the_exact_signed_distance() {
    let (mut pairs, mut turned, mut worst) = (0, 0, 0.0);
    for curved in 6..8 {
        for kind in 0..MIXED_SHAPE_KINDS {
            for seed in 0..2 {
                if let Some(single) =
                    check_pair(9000 + 100 * kind as u64 + seed, curved, kind, &mut worst)
                {
                    pairs += 1;
                    turned += usize::from(single);
                }
            }
        }
    }
    println!(
        "support rows against the oracle's finite differences: {pairs} pairs, {turned} with rotations, worst difference {worst:.2e}"
    );
    assert!(
        turned >= pairs / 2,
        "{turned} of {pairs} pairs had a single deepest row"
    );
}
