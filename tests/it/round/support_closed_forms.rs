//! Closed forms of the support-function path for cylinders and cones
//! (`VClipSettings::curved_support_functions`): a stack of cylinders on
//! their caps lifted column-wise by the sums of the depths, straight up; a
//! cylinder lying on a box lifted by its depth on two rows (the ends of its
//! side line); a cone on its base lifted by its depth on four; a tilted
//! cylinder's rim sunk into the ground moved by the closed form of its one
//! row. The row counts are asserted (`support_manifold`,
//! docs/round-shapes.md).

use super::support::{curved_part_geometry, support_queries, support_signed_distance};
use crate::stabilize::support::{describe, stabilize_with};
use constraint_stabilization::body::{Body, MassSpec, Shape};
use constraint_stabilization::internals::contact::contact_points;
use constraint_stabilization::{Settings, Status};
use dev_support::sat::sat_depth;
use dev_support::scene::{body, floor_slab, ground, scene_of, xyzw};
use dev_support::support_oracle::body_depth;
use nalgebra::{UnitQuaternion, Vector3};

/// Tight tolerance and target margin, relative to the scene's scale.
const TIGHT: f64 = 1e-9;

/// Agreement of a motion with its closed form, relative to the motion.
const MOTION_AGREEMENT: f64 = 1e-6;

/// Agreement of a depth with its closed form, relative to the body's size
/// (rounding only: caps and side lines are exact in the support path).
const DEPTH_AGREEMENT: f64 = 1e-12;

/// Largest rotation of a body lifted straight up (rad).
const TURN_AGREEMENT: f64 = 1e-9;

fn tight_support() -> Settings {
    let mut settings = Settings::default();
    settings.tolerance_relative = TIGHT;
    settings.target_margin_relative = TIGHT;
    settings.vclip.curved_support_functions = true;
    settings
}

/// The shape's `z` turned to the world's `y` (up).
fn z_up() -> [f64; 4] {
    xyzw(&UnitQuaternion::from_scaled_axis(
        -Vector3::x() * std::f64::consts::FRAC_PI_2,
    ))
}

/// The shape's `z` turned to the world's `x` (lying).
fn z_along_x() -> [f64; 4] {
    xyzw(&UnitQuaternion::from_scaled_axis(
        Vector3::y() * std::f64::consts::FRAC_PI_2,
    ))
}

/// Contact points of bodies `a` and `b` (single parts) by the support path.
fn support_points(a: &Body, b: &Body, margin: f64) -> usize {
    let queries = support_queries(a, b);
    let mut settings = Settings::default();
    settings.vclip.curved_support_functions = true;
    contact_points(
        &queries[0],
        &curved_part_geometry(a, 0),
        &curved_part_geometry(b, 0),
        margin,
        &settings,
    )
    .points
    .len()
}

#[test]
fn support_cylinder_stack_is_lifted_column_wise() {
    let (half, radius) = (0.2, 0.3);
    let depths = [0.01, 0.02, 0.015];
    let mut descs = vec![ground()];
    let mut bottom = 0.0;
    for (k, depth) in depths.iter().enumerate() {
        bottom -= depth;
        descs.push(body(
            &format!("cylinder{k}"),
            Shape::Cylinder {
                half_height: half,
                radius,
            },
            [0.0, bottom + half, 0.0],
            z_up(),
            MassSpec::Mass(1.0 + k as f64),
        ));
        bottom += 2.0 * half;
    }
    let mut scene = scene_of(&descs);
    for k in 1..=depths.len() {
        let (upper, lower) = (&scene.bodies()[k], &scene.bodies()[k - 1]);
        let measured = -support_signed_distance(upper, lower);
        assert!(
            (measured - depths[k - 1]).abs() <= DEPTH_AGREEMENT,
            "{k}: {measured}"
        );
        assert_eq!(
            support_points(upper, lower, 0.001),
            4,
            "cap on a face or a cap"
        );
    }
    let start: Vec<Vector3<f64>> = scene
        .bodies()
        .iter()
        .map(|b| *b.translation_user())
        .collect();
    let (report, residual) = stabilize_with(&mut scene, tight_support());
    println!(
        "{}",
        describe("cylinder stack (support)", &report, residual)
    );
    assert_eq!(report.status, Status::Converged);
    assert!(
        residual <= report.tolerance,
        "oracle depth after {residual:e}"
    );
    let margin = TIGHT * report.scale;
    let mut lift = 0.0;
    for (k, depth) in depths.iter().enumerate() {
        lift += depth + margin;
        let moved = scene.bodies()[k + 1].translation_user() - start[k + 1];
        let expected = Vector3::y() * lift;
        assert!(
            (moved - expected).norm() <= MOTION_AGREEMENT * lift,
            "cylinder {k}: moved {moved:?}, expected {expected:?}"
        );
        let [x, y, z, w] = scene.bodies()[k + 1].rotation_user_xyzw();
        let turn = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(w, x, y, z)).angle_to(
            &UnitQuaternion::from_scaled_axis(-Vector3::x() * std::f64::consts::FRAC_PI_2),
        );
        assert!(turn <= TURN_AGREEMENT, "cylinder {k} turned {turn:e}");
    }
}

fn lifted_by_its_depth(
    label: &str,
    shape: Shape,
    centre_height: f64,
    rotation: [f64; 4],
    rows: usize,
) {
    let depth = 0.01;
    let start = [0.1, centre_height - depth, -0.2];
    let mut scene = scene_of(&[
        floor_slab("box", [1.0, 0.5, 1.0]),
        body("solid", shape, start, rotation, MassSpec::Mass(1.0)),
    ]);
    let (solid, boxed) = (&scene.bodies()[1], &scene.bodies()[0]);
    let measured = -support_signed_distance(solid, boxed);
    assert!(
        (measured - depth).abs() <= DEPTH_AGREEMENT,
        "{label}: depth {measured}"
    );
    let oracle = body_depth(solid, boxed);
    assert!((oracle - depth).abs() <= 1e-9, "{label}: oracle {oracle}");
    let count = support_points(solid, boxed, 0.001);
    println!("{label}: {count} rows");
    assert_eq!(count, rows, "{label}: rows");
    let (report, _) = stabilize_with(&mut scene, tight_support());
    // The oracle on the true solids (the harness's residual adds parry's
    // depth of the library's polyhedra, which stand out of a lying
    // cylinder by up to their deviation).
    let residual = sat_depth(&scene, 0, 1);
    println!("{}", describe(label, &report, residual));
    assert_eq!(report.status, Status::Converged);
    assert!(
        residual <= report.tolerance,
        "{label}: oracle depth after {residual:e}"
    );
    let moved = scene.bodies()[1].translation_user() - Vector3::from(start);
    let lift = depth + TIGHT * report.scale;
    assert!(
        (moved - Vector3::y() * lift).norm() <= MOTION_AGREEMENT * lift,
        "{label}: moved {moved:?}"
    );
}

#[test]
fn support_cylinder_lying_on_a_box_is_lifted_on_two_rows() {
    let radius = 0.15;
    let shape = Shape::Cylinder {
        half_height: 0.4,
        radius,
    };
    lifted_by_its_depth("cylinder lying (support)", shape, radius, z_along_x(), 2);
}

#[test]
fn support_cone_on_its_base_is_lifted_by_its_depth() {
    let half = 0.3;
    let shape = Shape::Cone {
        half_height: half,
        radius: 0.25,
    };
    // The shape frame is at the middle of the axis: the base is `half` below.
    lifted_by_its_depth("cone on its base (support)", shape, half, z_up(), 4);
}

#[test]
fn support_rim_on_a_face_is_resolved() {
    // A cylinder tilted 0.5 rad about z, its lowest rim point sunk into
    // the ground.
    let (half, radius, depth) = (0.2, 0.3, 0.01);
    let tilt = UnitQuaternion::from_scaled_axis(Vector3::z() * 0.5)
        * UnitQuaternion::from_scaled_axis(-Vector3::x() * std::f64::consts::FRAC_PI_2);
    let shape = Shape::Cylinder {
        half_height: half,
        radius,
    };
    // Height of the lowest point below the centre: h cos + r sin of the tilt.
    let below = half * 0.5_f64.cos() + radius * 0.5_f64.sin();
    let scene = scene_of(&[
        ground(),
        body(
            "c",
            shape,
            [0.0, below - depth, 0.0],
            xyzw(&tilt),
            MassSpec::Mass(1.0),
        ),
    ]);
    let (c, floor) = (&scene.bodies()[1], &scene.bodies()[0]);
    let measured = -support_signed_distance(c, floor);
    assert!(
        (measured - depth).abs() <= DEPTH_AGREEMENT,
        "depth {measured}"
    );
    let rows = support_points(c, floor, 0.001);
    println!("rim on a face: {rows} rows");
    assert_eq!(rows, 1, "a tilted rim touches at one point");
    // The closed form of one row at the lowest rim point `p`, normal `y`,
    // lever `l = p - com`: the mass-weighted projection moves the centre
    // of mass by `y lambda / m` and turns the body by
    // `I^-1 (l x y) lambda`, `lambda = (depth + margin) / (1/m + (l x y) . I^-1 (l x y))`.
    let axis = tilt * Vector3::z();
    let com = c.com_world();
    let down = (-Vector3::y() + axis * axis.y)
        .try_normalize(0.0)
        .expect("the axis is tilted");
    let lowest = com - axis * half + down * radius;
    let arm = (lowest - com).cross(&Vector3::y());
    let inverse_inertia = c.inverse_inertia_world().expect("a dynamic body");
    let mut scene = scene;
    let (report, residual) = stabilize_with(&mut scene, tight_support());
    println!("{}", describe("rim on a face (support)", &report, residual));
    assert_eq!(report.status, Status::Converged);
    assert!(
        residual <= report.tolerance,
        "oracle depth after {residual:e}"
    );
    let lambda = (depth + TIGHT * report.scale) / (1.0 + arm.dot(&(inverse_inertia * arm)));
    let expected_shift = Vector3::y() * lambda;
    let expected_turn = inverse_inertia * arm * lambda;
    let moved = &scene.bodies()[1];
    let shift = moved.com_world() - com;
    let [x, y, z, w] = moved.rotation_user_xyzw();
    let turn = (UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(w, x, y, z))
        * tilt.inverse())
    .scaled_axis();
    println!(
        "rim on a face: shift {shift:?} (closed form {expected_shift:?}), turn {turn:?} (closed form {expected_turn:?})"
    );
    assert!(
        (shift - expected_shift).norm() <= MOTION_AGREEMENT * expected_shift.norm(),
        "shift {shift:?}, closed form {expected_shift:?}"
    );
    assert!(
        (turn - expected_turn).norm() <= MOTION_AGREEMENT * expected_turn.norm(),
        "turn {turn:?}, closed form {expected_turn:?}"
    );
}

/// The Rapier pile of 60 round and curved bodies after 5 s
/// (`tests/data/engine/rp08_mixed_pile.json`) with the support path: the
/// depth reported before the call is the oracle's on the true shapes (no
/// deviation), the call converges, and the oracle's depth after is within
/// the tolerance. The call's time is printed beside the polyhedra's (never
/// asserted).
#[cfg(feature = "serde")]
#[test]
fn support_rapier_mixed_pile_state_is_resolved_by_the_oracle() {
    /// Agreement of the library's depth with the oracle's, relative to the
    /// scene's scale.
    const ORACLE_AGREEMENT_RELATIVE: f64 = 1e-7;
    let scene = super::rp08_mixed_pile();
    let (before, _) = dev_support::sat::sat_deepest(&scene);
    let mut polyhedra = scene.clone();
    let start = std::time::Instant::now();
    let (report_polyhedra, _) = stabilize_with(&mut polyhedra, Settings::default());
    let polyhedra_seconds = start.elapsed().as_secs_f64();
    let mut settings = Settings::default();
    settings.vclip.curved_support_functions = true;
    let mut support = scene.clone();
    let start = std::time::Instant::now();
    let (report, _) = stabilize_with(&mut support, settings);
    let support_seconds = start.elapsed().as_secs_f64();
    let (residual, _) = dev_support::sat::sat_deepest(&support);
    println!(
        "{}",
        describe("rp08_mixed_pile (support)", &report, residual)
    );
    println!(
        "rp08_mixed_pile: call {:.1} ms with support functions ({} passes), {:.1} ms with polyhedra ({} passes); oracle before {before:.6e}",
        1e3 * support_seconds,
        report.passes,
        1e3 * polyhedra_seconds,
        report_polyhedra.passes
    );
    let slack = ORACLE_AGREEMENT_RELATIVE * report.scale;
    assert!(
        (report.depth_before - before).abs() <= slack,
        "reported {:e}, oracle {before:e}",
        report.depth_before
    );
    assert_eq!(report.status, Status::Converged);
    assert!(
        residual <= report.tolerance,
        "oracle depth after {residual:e}"
    );
}

/// A cylinder lying on a box, turned about the vertical by `tilt` so that
/// one end of its side line sinks `depth` and the other stands `gap`
/// above the box (module docs of `support_manifold`, "band").
fn tilted_lying_cylinder(depth: f64, gap: f64) -> constraint_stabilization::Scene {
    let (half, radius) = (0.4, 0.15);
    // The ends' lowest points are `2 half sin(tilt)` apart in height.
    let tilt = ((depth + gap) / (2.0 * half)).asin();
    let rotation = UnitQuaternion::from_scaled_axis(Vector3::z() * tilt)
        * UnitQuaternion::from_scaled_axis(Vector3::y() * std::f64::consts::FRAC_PI_2);
    // An end's lowest rim point lies `radius cos(tilt)` below its centre.
    let centre = half * tilt.sin() + radius * tilt.cos() - depth;
    scene_of(&[
        floor_slab("box", [1.0, 0.5, 1.0]),
        body(
            "cylinder",
            Shape::Cylinder {
                half_height: half,
                radius,
            },
            [0.0, centre, 0.0],
            xyzw(&rotation),
            MassSpec::Mass(1.0),
        ),
    ])
}

#[test]
fn support_tilted_lying_cylinder_has_a_row_at_each_end_within_the_margin() {
    let (depth, gap) = (1e-3, 2e-4);
    let mut scene = tilted_lying_cylinder(depth, gap);
    let (solid, boxed) = (&scene.bodies()[1], &scene.bodies()[0]);
    let measured = -support_signed_distance(solid, boxed);
    assert!(
        (measured - depth).abs() <= DEPTH_AGREEMENT,
        "depth {measured}"
    );
    // The raised end is a contact when the margin reaches it, and only
    // then: its height above the box plane (`gap`) is far outside the
    // feature window (`1e-3` of the cylinder's size, 4.3e-4 m, against
    // the ends' height difference of 1.2e-3 m).
    assert_eq!(
        support_points(solid, boxed, 2.0 * gap),
        2,
        "margin over the gap"
    );
    assert_eq!(
        support_points(solid, boxed, 0.5 * gap),
        1,
        "margin under the gap"
    );
    // The single row lifts the sunk end by turning the body, which sinks
    // the raised one (by 1.7 times the row's multiplier against 3.7 times
    // for the sunk end: 4.6e-4 m, over the gap); with both ends as rows
    // one pass leaves only the linearization's second-order error.
    let mut no_margin = tight_support();
    no_margin.contact_margin_relative = 1e-9;
    let mut single = tilted_lying_cylinder(depth, gap);
    let (report_single, residual_single) = stabilize_with(&mut single, no_margin);
    let (report, residual) = stabilize_with(&mut scene, tight_support());
    println!("{}", describe("tilted lying cylinder", &report, residual));
    println!(
        "{}",
        describe(
            "tilted lying cylinder, no margin",
            &report_single,
            residual_single
        )
    );
    for (r, residual) in [(&report, residual), (&report_single, residual_single)] {
        assert_eq!(r.status, Status::Converged);
        assert!(residual <= r.tolerance, "oracle depth after {residual:e}");
    }
    assert!(
        report.passes < report_single.passes,
        "passes {} with the margin's rows, {} with one row",
        report.passes,
        report_single.passes
    );
}
