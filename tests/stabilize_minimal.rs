//! The correction is the minimal mass-weighted one: for single penetrating
//! pairs whose minimal correction is known in closed form, the reported
//! displacement `sqrt(sum m |dx|^2 + dtheta^T I dtheta)` is within 1% of it,
//! with clarabel at a tight tolerance and with the default (auto) solver.
//!
//! Oracles (derived here, not by the library):
//! - a box of mass `m` sunk by `d` face-down into a fixed ground: the only
//!   feasible corrections lift the whole bottom face by at least `d`; the
//!   cheapest is the pure lift, displacement `sqrt(m) (d + g)` with `g` the
//!   target margin;
//! - two free boxes of masses `m1`, `m2` overlapping by `d` face to face
//!   along a face normal `n`: minimize `m1 a^2 + m2 b^2` with `a + b = d`:
//!   `a = d m2 / (m1 + m2)`, `b = d m1 / (m1 + m2)`, displacement
//!   `d sqrt(m1 m2 / (m1 + m2))`, each body moving along `-n` / `+n`.

mod stabilize_support;

use constraint_stabilization::body::MassSpec;
use constraint_stabilization::solver::SolverChoice;
use constraint_stabilization::{Settings, Status};
use nalgebra::{UnitQuaternion, Vector3};
use stabilize_support::*;

/// The bound: within 1% of the minimal displacement.
const RELATIVE_AGREEMENT: f64 = 0.01;

/// Tight tolerance and target margin (relative to the scene scale).
const TIGHT: f64 = 1e-9;

fn tight(choice: SolverChoice) -> Settings {
    let mut settings = Settings {
        tolerance_relative: TIGHT,
        target_margin_relative: TIGHT,
        ..Settings::default()
    };
    settings.solver.choice = choice;
    settings
}

fn assert_close(label: &str, measured: f64, expected: f64) {
    println!("{label}: displacement {measured:.9e}, minimal {expected:.9e}");
    assert!(
        (measured - expected).abs() <= RELATIVE_AGREEMENT * expected,
        "{label}: displacement {measured:e}, minimal {expected:e}"
    );
}

#[test]
fn box_sunk_into_fixed_ground_is_lifted_by_the_depth() {
    let (mass, depth) = (2.5, 0.02);
    for choice in [SolverChoice::Clarabel, SolverChoice::Auto] {
        let mut scene = scene_of(&[
            cuboid(
                "ground",
                [10.0, 0.5, 10.0],
                [0.0, -0.5, 0.0],
                IDENTITY_XYZW,
                MassSpec::Fixed,
            ),
            cuboid(
                "box",
                [0.4, 0.3, 0.6],
                [0.1, 0.3 - depth, -0.2],
                IDENTITY_XYZW,
                MassSpec::Mass(mass),
            ),
        ]);
        let (report, residual) = stabilize_with(&mut scene, tight(choice));
        println!("{}", describe(&format!("{choice:?}"), &report, residual));
        assert_eq!(report.status, Status::Converged);
        assert!(residual <= report.tolerance);
        let margin = TIGHT * report.scale;
        assert_close(
            &format!("box on ground, {choice:?}"),
            report.displacement,
            mass.sqrt() * (depth + margin),
        );
        let lift = scene.bodies()[1].translation_user().y - (0.3 - depth);
        assert!((lift - depth).abs() <= RELATIVE_AGREEMENT * depth);
    }
}

#[test]
fn two_free_boxes_separate_in_inverse_mass_ratio() {
    for (m1, m2) in [(1.0, 3.0), (1.0, 1e4)] {
        two_free_boxes(m1, m2);
    }
}

fn two_free_boxes(m1: f64, m2: f64) {
    let depth = 0.03;
    // The pair along x, b's smaller face centred on a's (off-centre, a small
    // rotation of a would lower the cost below the pure-translation formula),
    // then the whole configuration turned by `frame`: the minimal correction
    // does not depend on the world frame.
    let frames = [
        UnitQuaternion::identity(),
        UnitQuaternion::from_scaled_axis(Vector3::new(0.4, -0.7, 0.2)),
    ];
    for frame in frames {
        for choice in [SolverChoice::Clarabel, SolverChoice::Auto] {
            let centre_a = frame * Vector3::new(-0.5 + depth / 2.0, 0.0, 0.0);
            let centre_b = frame * Vector3::new(0.5 - depth / 2.0, 0.0, 0.0);
            let rotation = xyzw(&frame);
            let mut scene = scene_of(&[
                cuboid(
                    "a",
                    [0.5, 0.5, 0.5],
                    centre_a.into(),
                    rotation,
                    MassSpec::Mass(m1),
                ),
                cuboid(
                    "b",
                    [0.5, 0.3, 0.4],
                    centre_b.into(),
                    rotation,
                    MassSpec::Mass(m2),
                ),
            ]);
            let (report, residual) = stabilize_with(&mut scene, tight(choice));
            println!("{}", describe(&format!("{choice:?}"), &report, residual));
            assert_eq!(report.status, Status::Converged);
            assert!(residual <= report.tolerance);
            let gap = depth + TIGHT * report.scale;
            assert_close(
                &format!("two boxes, {choice:?}, frame {frame:?}"),
                report.displacement,
                gap * (m1 * m2 / (m1 + m2)).sqrt(),
            );
            let normal = frame * Vector3::x();
            let moved_a = scene.bodies()[0].translation_user() - centre_a;
            let moved_b = scene.bodies()[1].translation_user() - centre_b;
            let expected_a = -normal * gap * m2 / (m1 + m2);
            let expected_b = normal * gap * m1 / (m1 + m2);
            assert!((moved_a - expected_a).norm() <= RELATIVE_AGREEMENT * gap);
            assert!((moved_b - expected_b).norm() <= RELATIVE_AGREEMENT * gap);
        }
    }
}
