//! Friction in the projection (issue 10): a resting contact slides at most
//! `mu` times its normal correction (the pyramid or the cone of
//! `projector::friction`; every test runs under both models). Closed forms
//! and the frictionless answer as the contrast; depths by the brute-force
//! separating-axis oracle.

use crate::stabilize::support::{
    LIGHT_HALF_WIDTH, heavy_on_floating_light, heavy_on_light, stabilize_with,
};
use constraint_stabilization::body::MassSpec;
use constraint_stabilization::scene::Scene;
use constraint_stabilization::solver::SolverChoice;
use constraint_stabilization::{FrictionModel, Report, Settings, Status};
use dev_support::sat::sat_deepest;
use dev_support::scene::{IDENTITY_XYZW, cuboid, ground, scene_of, unit_cube_sunk, xyzw};
use nalgebra::{UnitQuaternion, Vector3};

/// Sideways motion that counts as none (the bound).
const NO_SLIDE: f64 = 1e-9;

fn with_friction(mu: f64, model: FrictionModel) -> Settings {
    {
        let mut settings = Settings::default();
        settings.friction = mu;
        settings.friction_model = model;
        settings
    }
}

/// The default settings under `model` (for scenes with their bodies' own
/// friction).
fn with_model(model: FrictionModel) -> Settings {
    {
        let mut settings = Settings::default();
        settings.friction_model = model;
        settings
    }
}

/// `input` stabilized with `settings` and solver `choice`: resolved, and
/// no penetration beyond the tolerance left (separating-axis oracle).
fn stabilized_by(input: &Scene, mut settings: Settings, choice: SolverChoice) -> (Scene, Report) {
    let mut scene = input.clone();
    settings.solver.choice = choice;
    let (report, _) = stabilize_with(&mut scene, settings);
    assert!(report.status.is_resolved(), "{choice:?}: {report:#?}");
    let (deepest, pair) = sat_deepest(&scene);
    assert!(
        deepest <= report.tolerance,
        "{choice:?}: {deepest:e} at {pair:?}"
    );
    (scene, report)
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

    for (model, choice) in FrictionModel::ALL.into_iter().flat_map(|model| {
        [
            SolverChoice::Auto,
            SolverChoice::Clarabel,
            SolverChoice::Lemke,
        ]
        .map(|choice| (model, choice))
    }) {
        let (scene, report) = stabilized_by(&input, with_friction(0.5, model), choice);
        let light = translation(&input, &scene, 1);
        let heavy = translation(&input, &scene, 2);
        let turn = input.bodies()[1]
            .com_pose()
            .rotation
            .angle_to(&scene.bodies()[1].com_pose().rotation);
        println!(
            "{model:?} {choice:?}: light moved {light:?} turned {turn:e}, heavy moved {heavy:?}"
        );
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

/// Gap of the light box's open contact with the ground in
/// [`an_open_contact_slides_at_most_the_gap_it_keeps`], relative to the
/// scene's scale: beyond the tolerance and the target margin (1e-6 of the
/// scale each), within the contact margin (1e-2), so that the contact is a
/// row of the problem that starts open.
const OPEN_GAP_RELATIVE: f64 = 1e-3;

/// Largest ratio of a sliding distance allowed by the friction pyramid to
/// the one allowed by the cone: `1 / cos(pi / K)` for `K = 4` facets
/// (`projector::friction`).
const PYRAMID_CORNER: f64 = std::f64::consts::SQRT_2;

/// Issue 10's drift inside the call: a contact open at the start of the
/// call got no friction rows, and the correction closed it while sliding it
/// freely (the 1:1000 stack of `examples/probes/slide_probe.rs`: 6e-5 to 2.4e-4 m
/// per call, whatever `mu`). A light box floating just above the ground
/// under a tilted box 1,000 times heavier that penetrates it: the cheap
/// correction pushes the light box down along the heavy box's tilted
/// normal. The light and heavy boxes have no friction of their own and the
/// ground `2 mu`, so only the light box's open contact with the ground has
/// friction (`mu`, the mean). Every row now has the friction cone with its
/// apex where the row reaches its target, so the light box slides at most
/// `1 / mu` times the gap its ground contact keeps (Anitescu and Tasora's
/// relaxation); without friction it closes the gap and slides dozens of
/// times further (the contrast), and so it did with friction before (no
/// friction row on a contact open at the start).
#[test]
fn an_open_contact_slides_at_most_the_gap_it_keeps() {
    let (ratio, tilt, depth, mu) = (1000.0, 2e-2, 2e-3, 0.5);
    let scale = heavy_on_light(ratio, tilt, depth).bodies()[1]
        .polyhedron()
        .expect("a convex body")
        .scale();
    let mut input = heavy_on_floating_light(ratio, tilt, depth, OPEN_GAP_RELATIVE * scale);
    for (body, own) in [(0, 2.0 * mu), (1, 0.0), (2, 0.0)] {
        let body = input.body_mut(body).expect("a body of the scene");
        body.set_friction(Some(own)).expect("a valid coefficient");
    }
    let sideways = |scene: &Scene| {
        let moved = translation(&input, scene, 1);
        moved.x.hypot(moved.z)
    };
    let mut frictionless = input.clone();
    for body in 0..3 {
        let body = frictionless.body_mut(body).expect("a body of the scene");
        body.set_friction(None).expect("no coefficient");
    }
    let (report, _) = stabilize_with(&mut frictionless, Settings::default());
    assert!(report.status.is_resolved(), "{report:#?}");
    let free = sideways(&frictionless);
    for (model, choice) in FrictionModel::ALL.into_iter().flat_map(|model| {
        [SolverChoice::Auto, SolverChoice::Clarabel].map(|choice| (model, choice))
    }) {
        let (scene, report) = stabilized_by(&input, with_model(model), choice);
        // The cone allows `1 / mu` times the gap kept; the pyramid up to
        // `1 / cos(pi / K)` more in its corners.
        let excess = match model {
            FrictionModel::Cone => 1.0,
            FrictionModel::Pyramid => PYRAMID_CORNER,
        };
        // The light box is not turned (its rotation is second order), so
        // its gap is its height above the ground less its half height.
        let kept = scene.bodies()[1].translation_user().y - 0.5;
        let target = Settings::default().target_margin_relative * report.scale;
        let slid = sideways(&scene);
        println!(
            "{model:?} {choice:?}: slid {slid:e} keeping a gap of {kept:e}; frictionless {free:e}"
        );
        assert!(
            mu * slid <= excess * (kept - target).max(0.0) + report.tolerance,
            "{model:?} {choice:?}: slid {slid:e} keeping a gap of {kept:e}"
        );
        assert!(
            free > 10.0 * slid,
            "the contrast: frictionless {free:e}, with {slid:e}"
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
    for model in FrictionModel::ALL {
        box_stays_on_the_tilted_plane(&input, normal, (theta, sink, mu), model);
    }
}

fn box_stays_on_the_tilted_plane(
    input: &Scene,
    normal: Vector3<f64>,
    (theta, sink, mu): (f64, f64, f64),
    model: FrictionModel,
) {
    let mut scene = input.clone();
    let (report, _) = stabilize_with(&mut scene, with_friction(mu, model));
    assert_eq!(report.status, Status::Converged);
    let moved = translation(input, &scene, 1);
    let along_normal = moved.dot(&normal);
    let tangential = (moved - normal * along_normal).norm();
    let overlap = sink * theta.cos();
    let target = Settings::default().target_margin_relative * report.scale;
    println!(
        "{model:?}: moved {moved:?}: {along_normal} along the normal, {tangential:e} along the plane"
    );
    assert!(tangential <= NO_SLIDE, "{model:?}: slid by {tangential:e}");
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
        assert!(plain_report.status.is_resolved());
        for model in FrictionModel::ALL {
            let mut rough = scene.clone();
            let (rough_report, _) = stabilize_with(&mut rough, with_friction(0.8, model));
            assert!(rough_report.status.is_resolved());
            // The pyramid's answer is the frictionless one to rounding (the
            // same active rows); the cone's is clarabel's interior point,
            // to its tolerance: the 1e-9.
            let agree = match model {
                FrictionModel::Pyramid => 1e-12,
                FrictionModel::Cone => NO_SLIDE,
            };
            for (a, b) in plain.bodies().iter().zip(rough.bodies()) {
                let gap = (a.translation_user() - b.translation_user()).norm();
                let turn = a.com_pose().rotation.angle_to(&b.com_pose().rotation);
                assert!(
                    gap <= agree && turn <= agree,
                    "{model:?} {}: {gap:e}, {turn:e}",
                    a.name()
                );
            }
        }
    }
}

#[test]
fn invalid_friction_is_rejected() {
    for mu in [-0.1, f64::NAN, f64::INFINITY] {
        for model in FrictionModel::ALL {
            assert!(constraint_stabilization::Stabilizer::new(with_friction(mu, model)).is_err());
        }
    }
    let settings = {
        let mut settings = Settings::default();
        settings.friction_directions = 2;
        settings
    };
    assert!(constraint_stabilization::Stabilizer::new(settings).is_err());
    let mut scene = scene_of(&[ground(), unit_cube_sunk("box", 0.05)]);
    let body = scene.body_mut(1).expect("body 1");
    assert!(body.set_friction(Some(-1.0)).is_err());
    assert!(body.set_friction(Some(0.3)).is_ok());
    assert_eq!(body.friction(), Some(0.3));
}
