//! Scenes of round and curved shapes stabilized end to end: after the
//! call, the deepest penetration by the support-function oracle
//! (`dev_support::sat::sat_depth` routes round parts to it) is within the
//! call's tolerance; a stack of cylinders standing on their caps is lifted
//! column-wise; a compound of a capsule and a sphere rests like its parts.

use crate::stabilize::support::{describe, stabilize_with};
use constraint_stabilization::body::{MassSpec, Shape, ShapePart};
use constraint_stabilization::{Settings, Status};
use dev_support::random::{mixed_shape, random_rotation};
use dev_support::scene::{IDENTITY_XYZW, body, ground, scene_of, xyzw};
use nalgebra::Vector3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

#[test]
fn a_mixed_pile_is_resolved_by_the_oracle() {
    // Four seeds: ten took 36 s of CI's test run for nothing the first
    // four do not exercise (every kind appears in each pile).
    for seed in 0..4u64 {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut descs = vec![ground()];
        for i in 0..14 {
            let at = [
                rng.random_range(-0.8..0.8),
                rng.random_range(0.0..1.2),
                rng.random_range(-0.8..0.8),
            ];
            let shape = mixed_shape(&mut rng, i, 0.45);
            let rotation = xyzw(&random_rotation(&mut rng));
            descs.push(body(
                &format!("b{i}"),
                shape,
                at,
                rotation,
                MassSpec::Density(1.0),
            ));
        }
        let mut scene = scene_of(&descs);
        let (report, residual) = stabilize_with(&mut scene, Settings::default());
        println!(
            "{}",
            describe(&format!("mixed pile {seed}"), &report, residual)
        );
        assert_eq!(report.status, Status::Converged, "seed {seed}");
        // The library's depths of cylinders and cones (support functions
        // by default: an overlap reached, never below the true depth; or
        // polyhedra that hold the true solids) bound the true ones, so the
        // oracle (true shapes) sees at most the library's residual: within
        // the tolerance.
        assert!(
            residual <= report.tolerance,
            "seed {seed}: oracle depth {residual:e}"
        );
    }
}

#[test]
fn a_stack_of_cylinders_is_lifted_column_wise() {
    // Three cylinders standing on their caps (axis z turned to y), each
    // sunk by `depth` into the one below: the exact correction lifts them
    // straight up, by depth, 2 depth, 3 depth, without turning.
    let (h, r, depth) = (0.2, 0.3, 0.01);
    let upright = xyzw(&nalgebra::UnitQuaternion::from_scaled_axis(
        Vector3::x() * -std::f64::consts::FRAC_PI_2,
    ));
    let mut descs = vec![ground()];
    for level in 0..3 {
        let y = h + level as f64 * 2.0 * h - (level as f64 + 1.0) * depth;
        descs.push(body(
            &format!("c{level}"),
            Shape::Cylinder {
                half_height: h,
                radius: r,
            },
            [0.0, y, 0.0],
            upright,
            MassSpec::Mass(1.0),
        ));
    }
    let mut scene = scene_of(&descs);
    let start: Vec<Vector3<f64>> = scene
        .bodies()
        .iter()
        .map(|b| *b.translation_user())
        .collect();
    let mut settings = Settings::default();
    settings.tolerance_relative = 1e-9;
    settings.target_margin_relative = 1e-9;
    let (report, residual) = stabilize_with(&mut scene, settings);
    println!("{}", describe("cylinder stack", &report, residual));
    assert_eq!(report.status, Status::Converged);
    for level in 0..3 {
        let body = &scene.bodies()[level + 1];
        let moved = body.translation_user() - start[level + 1];
        let lift = (level as f64 + 1.0) * depth;
        println!("c{level}: moved {moved:?}");
        assert!(
            (moved.y - lift).abs() <= 1e-6 * lift + 4e-9,
            "c{level}: {moved:?}"
        );
        assert!(moved.x.abs() + moved.z.abs() <= 1e-9, "c{level}: {moved:?}");
    }
    assert!(residual <= report.tolerance);
}

#[test]
fn a_compound_of_round_parts_is_lifted_whole() {
    let part = |shape: Shape, x: f64| ShapePart {
        shape,
        translation: Vector3::new(x, 0.0, 0.0),
        rotation_xyzw: xyzw(&nalgebra::UnitQuaternion::from_scaled_axis(
            Vector3::y() * std::f64::consts::FRAC_PI_2,
        )),
    };
    let dumbbell = Shape::Compound {
        parts: vec![
            part(
                Shape::Capsule {
                    half_height: 0.4,
                    radius: 0.1,
                },
                0.0,
            ),
            part(Shape::Sphere { radius: 0.2 }, 0.6),
            part(Shape::Sphere { radius: 0.2 }, -0.6),
        ],
    };
    let depth = 0.03;
    let mut scene = scene_of(&[
        ground(),
        body(
            "dumbbell",
            dumbbell,
            [0.0, 0.2 - depth, 0.0],
            IDENTITY_XYZW,
            MassSpec::Mass(1.0),
        ),
    ]);
    let (report, residual) = stabilize_with(&mut scene, Settings::default());
    println!("{}", describe("dumbbell", &report, residual));
    assert_eq!(report.status, Status::Converged);
    let moved = scene.bodies()[1].translation_user() - Vector3::new(0.0, 0.2 - depth, 0.0);
    assert!((moved.y - depth).abs() <= 1e-3 * depth, "{moved:?}");
    assert!(residual <= report.tolerance);
}

#[cfg(feature = "serde")]
#[test]
fn the_rapier_mixed_pile_state_is_measured_and_resolved_by_the_oracle() {
    // A pile of 60 balls, capsules, cylinders and rounded boxes after 5 s
    // of Rapier (tests/data/engine/rp08_mixed_pile.json). The depth the
    // library reports before the call is the oracle's on the true shapes,
    // above it by at most the cylinders' stated deviation (the bound of
    // their circumscribed polyhedra with the support path off; the default
    // support path agrees with the oracle within its measured bound);
    // after the call the oracle's depth is within the tolerance.
    /// Agreement of the library's depth with the oracle's on exact (round
    /// and polyhedral) pairs, relative to the scene's scale: the oracle's
    /// refinement, not the library, sets it.
    const ORACLE_AGREEMENT_RELATIVE: f64 = 1e-7;
    let mut scene = super::rp08_mixed_pile();
    let (before, _) = dev_support::sat::sat_deepest(&scene);
    let deviation = scene
        .bodies()
        .iter()
        .map(|b| b.shape().surface_deviation())
        .fold(0.0, f64::max);
    assert!(deviation > 0.0, "the pile holds cylinders");
    let (report, residual) = stabilize_with(&mut scene, Settings::default());
    println!("{}", describe("rp08_mixed_pile", &report, residual));
    println!("oracle before {before:.6e}, largest deviation {deviation:.3e}");
    let slack = ORACLE_AGREEMENT_RELATIVE * report.scale;
    assert!(
        report.depth_before >= before - slack && report.depth_before <= before + deviation + slack,
        "reported {:e}, oracle {before:e}",
        report.depth_before
    );
    assert_eq!(report.status, Status::Converged);
    assert!(
        residual <= report.tolerance,
        "oracle depth after {residual:e}"
    );
}
