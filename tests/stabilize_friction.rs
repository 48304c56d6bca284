//! Friction in the projection (issue 10): a resting contact slides at most
//! `mu` times its normal correction (the pyramid of
//! `projector::friction`). Closed forms and the frictionless answer as the
//! contrast; depths by the brute-force separating-axis oracle.

mod stabilize_support;

use constraint_stabilization::body::MassSpec;
use constraint_stabilization::scene::Scene;
use constraint_stabilization::solver::SolverChoice;
use constraint_stabilization::{Settings, Status};
use nalgebra::{UnitQuaternion, Vector3};
use stabilize_support::{
    IDENTITY_XYZW, cuboid, ground, sat_deepest, scene_of, stabilize_with, unit_cube_sunk, xyzw,
};

/// Sideways motion that counts as none (the bound).
const NO_SLIDE: f64 = 1e-9;

fn with_friction(mu: f64) -> Settings {
    Settings {
        friction: mu,
        ..Settings::default()
    }
}

/// Half width (x and z) of the light box: narrower than the heavy one, so
/// that its top corners are the ones inside the heavy box and the contact
/// normal is the heavy box's (tilted) face normal.
const LIGHT_HALF_WIDTH: f64 = 0.3;

/// A light box (half extents 0.3, 0.5, 0.3) resting flat on the ground and
/// a unit box `ratio` times heavier on it, turned by `tilt` about z (so the
/// contact normals are tilted, as after an engine step), placed so that
/// the light box's deepest top corner is `depth` inside it.
fn heavy_on_light(ratio: f64, tilt: f64, depth: f64) -> Scene {
    let rotation = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), tilt);
    let w = LIGHT_HALF_WIDTH;
    let light = cuboid(
        "light",
        [w, 0.5, w],
        [0.0, 0.5, 0.0],
        IDENTITY_XYZW,
        MassSpec::Mass(1.0),
    );
    // Depth of a top corner (x, 1) below the heavy box's bottom face, for
    // its centre at height y: -x sin(tilt) + (1 - y) cos(tilt) + 0.5,
    // largest at x = -w.
    let y = 1.0 + (0.5 + w * tilt.sin() - depth) / tilt.cos();
    let heavy = cuboid(
        "heavy",
        [0.5, 0.5, 0.5],
        [0.0, y, 0.0],
        xyzw(&rotation),
        MassSpec::Mass(ratio),
    );
    scene_of(&[ground(), light, heavy])
}

fn translation(before: &Scene, after: &Scene, index: usize) -> Vector3<f64> {
    after.bodies()[index].translation_user() - before.bodies()[index].translation_user()
}

#[test]
fn a_heavy_box_on_a_tilted_light_one_is_lifted_and_the_light_one_stays() {
    let (ratio, tilt, depth) = (1000.0, 1e-4, 2e-3);
    let input = heavy_on_light(ratio, tilt, depth);

    let mut frictionless = input.clone();
    let (report, _) = stabilize_with(&mut frictionless, Settings::default());
    assert!(report.status.is_resolved(), "{report:#?}");
    let slide = translation(&input, &frictionless, 1);
    let turn = input.bodies()[1]
        .com_pose()
        .rotation
        .angle_to(&frictionless.bodies()[1].com_pose().rotation);
    println!(
        "frictionless: light box moved {slide:?} turned {turn:e}, heavy {:?}",
        translation(&input, &frictionless, 2)
    );
    assert!(
        slide.x.abs() > 1e3 * NO_SLIDE,
        "the contrast: without friction the light box slides ({slide:?})"
    );

    for choice in [
        SolverChoice::Auto,
        SolverChoice::Clarabel,
        SolverChoice::Lemke,
    ] {
        let mut scene = input.clone();
        let mut settings = with_friction(0.5);
        settings.solver.choice = choice;
        let (report, _) = stabilize_with(&mut scene, settings);
        assert!(report.status.is_resolved(), "{choice:?}: {report:#?}");
        let (deepest, pair) = sat_deepest(&scene);
        assert!(
            deepest <= report.tolerance,
            "{choice:?}: {deepest:e} at {pair:?}"
        );
        let light = translation(&input, &scene, 1);
        let heavy = translation(&input, &scene, 2);
        let turn = input.bodies()[1]
            .com_pose()
            .rotation
            .angle_to(&scene.bodies()[1].com_pose().rotation);
        println!("{choice:?}: light moved {light:?} turned {turn:e}, heavy moved {heavy:?}");
        // Sideways: not at all; up: at most the target margin that its
        // resting contact with the ground is opened to.
        let target = Settings::default().target_margin_relative * report.scale;
        let sideways = Vector3::new(light.x, 0.0, light.z).norm();
        assert!(sideways <= NO_SLIDE, "{choice:?}: light box slid {light:?}");
        assert!(
            light.y.abs() <= 1.01 * target,
            "{choice:?}: light box rose {light:?}"
        );
        assert!(turn <= NO_SLIDE, "{choice:?}: light box turned {turn:e}");
        // The heavy box turns flat about the light box's deepest corner,
        // which lowers its centre by about `tilt * LIGHT_HALF_WIDTH`.
        let expected = depth - tilt * LIGHT_HALF_WIDTH;
        assert!(
            (heavy.y - expected).abs() <= 1e-2 * depth,
            "{choice:?}: heavy lifted by {} for a depth {depth}",
            heavy.y
        );
    }
}

/// A fixed plane tilted by `theta` (a large box turned about z) and a unit
/// box resting on it, face to face, pushed straight down by `sink` (as
/// gravity moves it in a step): its overlap along the plane normal is
/// `sink cos(theta)`.
fn box_on_tilted_plane(theta: f64, sink: f64) -> (Scene, Vector3<f64>) {
    let rotation = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), theta);
    let normal = rotation * Vector3::y();
    let plane = cuboid(
        "plane",
        [20.0, 0.5, 20.0],
        (rotation * Vector3::new(0.0, -0.5, 0.0)).into(),
        xyzw(&rotation),
        MassSpec::Fixed,
    );
    let resting = normal * 0.5 - Vector3::y() * sink;
    let block = cuboid(
        "block",
        [0.5, 0.5, 0.5],
        resting.into(),
        xyzw(&rotation),
        MassSpec::Mass(1.0),
    );
    (scene_of(&[plane, block]), normal)
}

#[test]
fn a_box_on_a_plane_below_its_friction_angle_does_not_slide() {
    let (theta, sink) = (0.3_f64, 0.01);
    let mu = 0.5;
    assert!(theta.tan() < mu, "below the friction angle");
    let (input, normal) = box_on_tilted_plane(theta, sink);
    let mut scene = input.clone();
    let (report, _) = stabilize_with(&mut scene, with_friction(mu));
    assert_eq!(report.status, Status::Converged);
    let moved = translation(&input, &scene, 1);
    let along_normal = moved.dot(&normal);
    let tangential = (moved - normal * along_normal).norm();
    let overlap = sink * theta.cos();
    let target = Settings::default().target_margin_relative * report.scale;
    println!("moved {moved:?}: {along_normal} along the normal, {tangential:e} along the plane");
    assert!(tangential <= NO_SLIDE, "slid by {tangential:e}");
    assert!(
        (along_normal - overlap - target).abs() <= 1e-3 * target,
        "{along_normal} for an overlap of {overlap}"
    );
    let rotation = scene.bodies()[1].com_pose().rotation;
    let turned = input.bodies()[1].com_pose().rotation.angle_to(&rotation);
    assert!(turned <= NO_SLIDE, "turned by {turned:e}");
}

/// Where nothing slides (a box sunk flat into the ground, a stack sunk
/// straight down), friction changes nothing: the same poses to rounding.
#[test]
fn friction_and_no_friction_agree_where_nothing_slides() {
    let column = |sink: f64| {
        let mut descs = vec![ground(), unit_cube_sunk("bottom", sink)];
        for i in 1..4 {
            descs.push(cuboid(
                &format!("box{i}"),
                [0.5, 0.5, 0.5],
                [0.0, 0.5 + i as f64 - sink, 0.0],
                IDENTITY_XYZW,
                MassSpec::Mass(1.0 + i as f64),
            ));
        }
        scene_of(&descs)
    };
    for scene in [
        scene_of(&[ground(), unit_cube_sunk("box", 0.05)]),
        column(0.03),
    ] {
        let mut plain = scene.clone();
        let (plain_report, _) = stabilize_with(&mut plain, Settings::default());
        let mut rough = scene.clone();
        let (rough_report, _) = stabilize_with(&mut rough, with_friction(0.8));
        assert!(plain_report.status.is_resolved() && rough_report.status.is_resolved());
        for (a, b) in plain.bodies().iter().zip(rough.bodies()) {
            let gap = (a.translation_user() - b.translation_user()).norm();
            let turn = a.com_pose().rotation.angle_to(&b.com_pose().rotation);
            assert!(
                gap <= 1e-12 && turn <= 1e-12,
                "{}: {gap:e}, {turn:e}",
                a.name()
            );
        }
    }
}

#[test]
fn invalid_friction_is_rejected() {
    for mu in [-0.1, f64::NAN, f64::INFINITY] {
        assert!(constraint_stabilization::Stabilizer::new(with_friction(mu)).is_err());
    }
    let settings = Settings {
        friction_directions: 2,
        ..Settings::default()
    };
    assert!(constraint_stabilization::Stabilizer::new(settings).is_err());
    let mut scene = scene_of(&[ground(), unit_cube_sunk("box", 0.05)]);
    let body = scene.body_mut(1).expect("body 1");
    assert!(body.set_friction(Some(-1.0)).is_err());
    assert!(body.set_friction(Some(0.3)).is_ok());
    assert_eq!(body.friction(), Some(0.3));
}
