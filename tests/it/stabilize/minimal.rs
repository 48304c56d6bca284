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
//!   `d sqrt(m1 m2 / (m1 + m2))`, each body moving along `-n` / `+n`
//!   without turning. Each body's motion is checked against its own closed
//!   form (to 1% of that motion: at mass ratio 1e4 the heavy body moves
//!   1e-4 of the light one, so a bound relative to the gap would let a
//!   heavy body that does not move at all pass), and its rotation against
//!   [`rotation_allowance`];
//! - a body sunk on one vertex into a fixed ground (a box on one corner, a
//!   rod at one end): one row, `dq = M^-1 J^T lambda` with `lambda =
//!   (target - phi) / (J M^-1 J^T)`, the inertia in closed form; the
//!   stabilizer's answer agrees to first order, within a tolerance derived
//!   from the second-order remainder (`one_row`), and the exact
//!   depth after the call (separating axes) is within the tolerance.

use crate::stabilize::one_row::{
    RowMember, assert_motions_match, motion, one_row_correction, one_row_tolerance,
    vertices_by_height,
};
use crate::stabilize::support::{describe, stabilize_with};
use constraint_stabilization::body::MassSpec;
use constraint_stabilization::solver::SolverChoice;
use constraint_stabilization::{Settings, Status};
use dev_support::sat::sat_depth;
use dev_support::scene::{IDENTITY_XYZW, cuboid, ground, scene_of, xyzw};
use nalgebra::{UnitQuaternion, Vector3};

/// The bound: within 1% of the minimal displacement.
const RELATIVE_AGREEMENT: f64 = 0.01;

/// Tight tolerance and target margin (relative to the scene scale).
const TIGHT: f64 = 1e-9;

fn tight(choice: SolverChoice) -> Settings {
    let mut settings = {
        let mut settings = Settings::default();
        settings.tolerance_relative = TIGHT;
        settings.target_margin_relative = TIGHT;
        settings
    };
    settings.solver.choice = choice;
    settings
}

/// The largest rotation accepted where the minimal correction is a pure
/// translation of length `motion`: the angle that moves the body's farthest
/// point (at `radius`, its circumradius) by `RELATIVE_AGREEMENT` of that
/// motion, so that a rotation is held to the same bound as the translation.
fn rotation_allowance(motion: f64, radius: f64) -> f64 {
    RELATIVE_AGREEMENT * motion / radius
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
            ground(),
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
        let body = &scene.bodies()[1];
        let moved = body.translation_user() - Vector3::new(0.1, 0.3 - depth, -0.2);
        let expected = Vector3::y() * (depth + margin);
        assert!(
            (moved - expected).norm() <= RELATIVE_AGREEMENT * expected.norm(),
            "{choice:?}: moved {moved:?}, expected {expected:?}"
        );
        let turned = body.user_pose().rotation.angle();
        let allowed = rotation_allowance(
            expected.norm(),
            body.polyhedron().expect("a convex body").scale(),
        );
        assert!(turned <= allowed, "{choice:?}: turned by {turned:e} rad");
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
            let label = format!("{choice:?}, m1 {m1:e}, m2 {m2:e}, frame {frame:?}");
            let expected_a = -normal * gap * m2 / (m1 + m2);
            let expected_b = normal * gap * m1 / (m1 + m2);
            for (index, centre, expected) in [(0, centre_a, expected_a), (1, centre_b, expected_b)]
            {
                let body = &scene.bodies()[index];
                let moved = body.translation_user() - centre;
                println!("{label}: body {index} moved {moved:?}, expected {expected:?}");
                assert!(
                    (moved - expected).norm() <= RELATIVE_AGREEMENT * expected.norm(),
                    "{label}: body {index} moved {moved:?}, expected {expected:?}"
                );
                let turned = body.user_pose().rotation.angle_to(&frame);
                let allowed = rotation_allowance(
                    expected.norm(),
                    body.polyhedron().expect("a convex body").scale(),
                );
                assert!(
                    turned <= allowed,
                    "{label}: body {index} turned by {turned:e} rad (allowed {allowed:e})"
                );
            }
        }
    }
}

/// How far the lowest vertex of a box sunk on one vertex is pushed into
/// the ground: small against the body, so that the rotation of the
/// correction is small and the first-order closed form is accurate to well
/// below 1% (checked by [`assert_motions_match`]).
const CORNER_DEPTH: f64 = 1e-3;

/// The same for the rod: rolling about its own axis is 400 times cheaper
/// than turning the box, so its correction turns it much more per unit of
/// depth, and the depth is smaller to keep the first-order check sharp.
const ROD_END_DEPTH: f64 = 1e-4;

/// Rounding of a vertex placed at a given height (unit-sized bodies).
const PLACEMENT_ROUNDING: f64 = 1e-12;

/// A dynamic box of `half_extents` and `mass`, turned by `rotation`, with
/// its lowest vertex `depth` below the top of a fixed ground (and
/// every other vertex clear of the contact margin): one row, through a
/// point off the centre of mass, so the minimal correction lifts and turns
/// the box. The motion must match the one-row closed form.
fn box_sunk_on_one_vertex(
    label: &str,
    half_extents: [f64; 3],
    mass: f64,
    rotation: UnitQuaternion<f64>,
    depth: f64,
) {
    let up = Vector3::y();
    let lowest_offset = rotation_lowest(&half_extents, &rotation);
    let centre = Vector3::new(0.2, -depth - lowest_offset, -0.1);
    let mut scene = scene_of(&[
        ground(),
        cuboid(
            "box",
            half_extents,
            centre.into(),
            xyzw(&rotation),
            MassSpec::Mass(mass),
        ),
    ]);
    let before = *scene.bodies()[1].com_pose();
    let settings = tight(SolverChoice::Auto);
    let margin = settings.contact_margin_relative
        * scene.bodies()[1]
            .polyhedron()
            .expect("a convex body")
            .scale();
    let heights = vertices_by_height(&scene, 1, &up);
    let point = heights[0];
    assert!(
        (up.dot(&point) + depth).abs() <= PLACEMENT_ROUNDING && up.dot(&heights[1]) > 2.0 * margin,
        "{label}: one vertex must be sunk, the others clear of the margin: {heights:?}"
    );
    let (report, residual) = stabilize_with(&mut scene, settings);
    println!("{}", describe(label, &report, residual));
    assert_eq!(report.status, Status::Converged, "{label}");
    assert!(
        residual <= report.tolerance,
        "{label}: residual {residual:e}"
    );
    assert!(
        sat_depth(&scene, 0, 1) <= report.tolerance,
        "{label}: SAT depth"
    );
    let target = TIGHT * report.scale;
    let member = RowMember::cuboid(mass, half_extents, centre, &rotation, 1.0);
    let expected = one_row_correction(&[member], &point, &up, -depth, target);
    let lever = (point - centre).norm();
    let relative = one_row_tolerance(
        &expected,
        &[lever],
        depth + target,
        report.tolerance + target,
    );
    let measured = motion(&before, scene.bodies()[1].com_pose());
    assert_motions_match(label, &[measured], &expected, relative);
}

/// The height of the lowest vertex of a box of `half_extents` turned by
/// `rotation`, relative to its centre.
fn rotation_lowest(half_extents: &[f64; 3], rotation: &UnitQuaternion<f64>) -> f64 {
    let row = rotation.to_rotation_matrix().matrix().row(1).into_owned();
    -(0..3).map(|k| row[k].abs() * half_extents[k]).sum::<f64>()
}

#[test]
fn box_sunk_on_one_corner_lifts_and_turns_as_the_closed_form() {
    box_sunk_on_one_vertex(
        "box on one corner",
        [0.4, 0.3, 0.2],
        2.0,
        UnitQuaternion::from_scaled_axis(Vector3::new(0.5, 0.3, 0.7)),
        CORNER_DEPTH,
    );
}

#[test]
fn rod_sunk_at_one_end_lifts_and_turns_as_the_closed_form() {
    // Tilted end down about z, then turned about its own axis so that one
    // corner of the low end is lower than the other three.
    let rotation = UnitQuaternion::from_scaled_axis(Vector3::new(0.0, 0.0, 0.25))
        * UnitQuaternion::from_scaled_axis(Vector3::new(0.4, 0.0, 0.0));
    box_sunk_on_one_vertex(
        "rod on one end",
        [1.0, 0.05, 0.05],
        1.0,
        rotation,
        ROD_END_DEPTH,
    );
}
