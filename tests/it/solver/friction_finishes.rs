//! Friction that always finishes (issue 21): the small engine states of
//! `tests/data/engine` with their engine's friction written on every body
//! (Bullet 0.5 x 0.5 = 0.25, MuJoCo 1.0, Rapier 0.5) converge under both
//! friction models, the exact depth after within the call's tolerance
//! (brute-force separating axes); a box pressed into a right-angled corner
//! with `mu = 2`, which no correction can free without sliding against a
//! wall (the two contacts' cones leave no common direction), is solved
//! without friction and the report says so, while with `mu = 0.3` its
//! friction is honoured.

use crate::stabilize::support::stabilize_with;
use crate::support::engine_states::engine_states;
use constraint_stabilization::body::MassSpec;
use constraint_stabilization::scene::Scene;
use constraint_stabilization::{FrictionModel, Report, Settings, Status};
use dev_support::sat::sat_deepest;
use dev_support::scene::{IDENTITY_XYZW, cuboid, ground, scene_of};

/// The coefficient of a pair of default bodies in the state's engine.
pub(super) fn engine_friction(stem: &str) -> f64 {
    match &stem[..2] {
        "bt" => 0.5 * 0.5,
        "mj" => 1.0,
        _ => 0.5,
    }
}

/// `scene` with the friction coefficient `mu` written on every body.
pub(super) fn with_friction_on_every_body(scene: &Scene, mu: f64) -> Scene {
    let mut scene = scene.clone();
    for body in 0..scene.bodies().len() {
        scene
            .body_mut(body)
            .expect("a body of the scene")
            .set_friction(Some(mu))
            .expect("a valid coefficient");
    }
    scene
}

fn islands_without_friction(report: &Report) -> usize {
    report
        .pass_reports
        .iter()
        .flat_map(|pass| &pass.solved)
        .filter(|island| island.friction_dropped)
        .count()
}

/// A call on `scene` under `model`: resolved, and no exact depth beyond
/// the tolerance left.
fn converged(scene: &Scene, model: FrictionModel, label: &str) -> Report {
    let mut scene = scene.clone();
    let mut settings = Settings::default();
    settings.friction_model = model;
    let (report, _) = stabilize_with(&mut scene, settings);
    assert!(
        report.status.is_resolved(),
        "{label} {model:?}: {:?}",
        report.status
    );
    let (deepest, pair) = sat_deepest(&scene);
    assert!(
        deepest <= report.tolerance,
        "{label} {model:?}: {deepest:e} at {pair:?} (tolerance {:e})",
        report.tolerance
    );
    report
}

#[test]
fn small_engine_states_with_their_engines_friction_converge() {
    let small = ["03_heavy", "04_heavy", "06_thrown"];
    let mut states = 0;
    for (stem, scene) in engine_states() {
        if !small.iter().any(|s| stem.contains(s)) {
            continue;
        }
        states += 1;
        let frictional = with_friction_on_every_body(&scene, engine_friction(&stem));
        for model in FrictionModel::ALL {
            converged(&frictional, model, &stem);
        }
    }
    assert_eq!(states, 9, "three engines, three small states each");
}

/// A unit cube of mass 1 sunk 1 cm into the ground (top face `y = 0`) and
/// 1 cm into a fixed wall on its `-x` side, every body with friction `mu`.
fn cube_in_a_corner(mu: f64) -> Scene {
    let sink = 0.01;
    let wall = cuboid(
        "wall",
        [0.5, 2.0, 2.0],
        [-1.0, 2.0, 0.0],
        IDENTITY_XYZW,
        MassSpec::Fixed,
    );
    let cube = cuboid(
        "cube",
        [0.5, 0.5, 0.5],
        [-sink, 0.5 - sink, 0.0],
        IDENTITY_XYZW,
        MassSpec::Mass(1.0),
    );
    with_friction_on_every_body(&scene_of(&[ground(), wall, cube]), mu)
}

#[test]
fn a_cube_wedged_in_a_corner_is_solved_without_friction_and_the_report_says_so() {
    for model in FrictionModel::ALL {
        let wedged = converged(&cube_in_a_corner(2.0), model, "mu 2");
        assert_eq!(wedged.status, Status::Converged);
        assert!(islands_without_friction(&wedged) > 0, "{model:?}");
        let free = converged(&cube_in_a_corner(0.3), model, "mu 0.3");
        assert_eq!(islands_without_friction(&free), 0, "{model:?}");
    }
}
