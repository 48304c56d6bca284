//! Properties of one call on random scenes (proptest, fixed seed; see
//! `support::proptest_config`): 2 to 9 boxes and hulls of sizes over a decade and
//! masses over four decades, overlapping by up to half their size, some on
//! a fixed ground, with a resting bystander pair away from them. After the
//! call, judged by the brute-force separating-axis oracle:
//! - the exact deepest penetration is never larger than before;
//! - the merit `sum (depth - tolerance)^2` over every pair, measured by the
//!   oracle, never rises;
//! - bodies outside the islands the report says it solved keep their poses
//!   bit for bit (the bystanders are always among them);
//! - no pose is NaN.
//!
//! Some cases add two overlapping boxes at 1.7e308 with a contact margin of
//! 1e308 (their margin-enlarged boxes would overflow). Any error must leave
//! every pose as it was; but no case errs: those calls converge
//! (`overflowing_pair_with_an_overflowing_margin_still_converges`), and no
//! valid scene and settings were found that make a call fail, so the
//! error branch is checked but not exercised (docs/reliability.md).

use crate::stabilize::support::solved_bodies;
use crate::support::proptest_config;
use constraint_stabilization::body::{BodyDesc, MassSpec};
use constraint_stabilization::scene::Scene;
use constraint_stabilization::{Settings, Stabilizer};
use dev_support::sat::sat_depth;
use dev_support::scene::{
    assert_finite, assert_untouched, bystander_pair, cuboid, ground, hull, pose_bits, scene_of,
    xyzw,
};
use nalgebra::{Point3, UnitQuaternion, Vector3};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Cases per run (each a fresh scene and one call).
const CASES: u32 = 512;

/// Depths and merits may differ by this fraction of the scene's scale
/// (rounding of world vertices in the oracle).
const ROUNDING: f64 = 1e-9;

/// Where the far pair sits, next to `f64::MAX`.
const OVERFLOWING: f64 = 1.7e308;

/// A contact margin (valid: finite) beyond which the far pair's enlarged
/// AABBs would overflow.
const OVERFLOWING_MARGIN: f64 = 1e308;

fn overflowing_settings() -> Settings {
    {
        let mut settings = Settings::default();
        settings.contact_margin_absolute = Some(OVERFLOWING_MARGIN);
        settings
    }
}

fn random_body(rng: &mut ChaCha8Rng, k: usize) -> BodyDesc {
    let size = rng.random_range(0.2..2.0);
    let at = [(); 3].map(|_| rng.random_range(-1.0..1.0));
    let axis = Vector3::from_fn(|_, _| rng.random_range(-1.5..1.5));
    let rotation = xyzw(&UnitQuaternion::from_scaled_axis(axis));
    let mass = MassSpec::Mass(10f64.powf(rng.random_range(-2.0..2.0)));
    let name = format!("body{k}");
    if rng.random_bool(0.5) {
        cuboid(&name, [size, size * 0.6, size * 0.4], at, rotation, mass)
    } else {
        let points = (0..rng.random_range(5..24))
            .map(|_| Point3::from(Vector3::from_fn(|_, _| rng.random_range(-size..size))))
            .collect();
        hull(&name, points, at, rotation, mass)
    }
}

fn random_scene(seed: u64, overflowing: bool) -> Vec<BodyDesc> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut descs = Vec::new();
    if rng.random_bool(0.5) {
        descs.push(ground());
    }
    let count = rng.random_range(2..10);
    descs.extend((0..count).map(|k| random_body(&mut rng, k)));
    descs.extend(bystander_pair([0.0, 0.0, 500.0], 1e-4));
    if overflowing {
        descs.extend(overflowing_pair());
    }
    descs
}

/// Two overlapping boxes at [`OVERFLOWING`] (valid bodies: their world
/// vertices round to finite numbers).
fn overflowing_pair() -> [BodyDesc; 2] {
    let at = |x: f64| [OVERFLOWING, x, 0.0];
    let identity = [0.0, 0.0, 0.0, 1.0];
    [
        cuboid("far0", [1.0; 3], at(0.0), identity, MassSpec::Mass(1.0)),
        cuboid("far1", [1.0; 3], at(0.5), identity, MassSpec::Mass(1.0)),
    ]
}

#[test]
fn overflowing_pair_with_an_overflowing_margin_still_converges() {
    let mut scene = scene_of(&overflowing_pair());
    let mut stabilizer = Stabilizer::new(overflowing_settings()).expect("valid settings");
    let report = stabilizer.stabilize(&mut scene).expect("no error");
    assert_finite(&scene);
    assert_eq!(report.status, constraint_stabilization::Status::Converged);
}

/// The oracle's merit and deepest penetration over every pair with a
/// dynamic body.
fn oracle(scene: &Scene, tolerance: f64) -> (f64, f64) {
    let (mut merit, mut deepest) = (0.0, 0.0f64);
    let aabbs: Vec<_> = scene.bodies().iter().map(|b| b.world_aabb()).collect();
    for a in 0..scene.len() {
        for b in a + 1..scene.len() {
            let fixed = scene.bodies()[a].is_fixed() && scene.bodies()[b].is_fixed();
            let ((min_a, max_a), (min_b, max_b)) = (aabbs[a], aabbs[b]);
            let apart = (0..3).any(|k| min_a[k] > max_b[k] || min_b[k] > max_a[k]);
            if fixed || apart {
                continue;
            }
            let depth = sat_depth(scene, a, b);
            deepest = deepest.max(depth);
            merit += (depth - tolerance).max(0.0).powi(2);
        }
    }
    (merit, deepest)
}

fn check_call(seed: u64, overflowing: bool) -> Result<(), TestCaseError> {
    let mut scene = scene_of(&random_scene(seed, overflowing));
    let before = pose_bits(&scene);
    let settings = if overflowing {
        overflowing_settings()
    } else {
        Settings::default()
    };
    let mut stabilizer = Stabilizer::new(settings).expect("valid settings");
    let report = match stabilizer.stabilize(&mut scene) {
        Ok(report) => report,
        Err(error) => {
            println!("seed {seed}: error {error}");
            prop_assert_eq!(pose_bits(&scene), before, "an error moved a body");
            return Ok(());
        }
    };
    assert_finite(&scene);
    let input = scene_of(&random_scene(seed, overflowing));
    let (merit_before, deepest_before) = oracle(&input, report.tolerance);
    let (merit_after, deepest_after) = oracle(&scene, report.tolerance);
    let slack = ROUNDING * report.scale;
    prop_assert!(
        deepest_after <= deepest_before + slack,
        "seed {}: deeper after: {:e} > {:e}",
        seed,
        deepest_after,
        deepest_before
    );
    prop_assert!(
        merit_after <= merit_before + slack * slack,
        "seed {}: merit rose: {:e} > {:e}",
        seed,
        merit_after,
        merit_before
    );
    let solved = solved_bodies(&report);
    let outside: Vec<usize> = (0..scene.len()).filter(|i| !solved.contains(i)).collect();
    assert_untouched(&scene, &before, &outside);
    Ok(())
}

proptest! {
    #![proptest_config(proptest_config::config(CASES))]

    #[test]
    fn a_call_never_makes_a_scene_worse(seed in any::<u64>(), overflowing in prop::bool::weighted(0.2)) {
        check_call(seed, overflowing)?;
    }
}
