//! Compound bodies (issue 10): one rigid body of several convex parts.
//! Oracles: the closed-form mass properties of a box (a box cut in two
//! is the same solid), the same scene with the uncut box, and the
//! brute-force separating-axis depth over every pair of parts of
//! different bodies (`dev_support::sat::sat_depth`), with parry's.

use crate::stabilize::support::{parry_shapes, stabilize_default, stabilize_with};
use approx::assert_relative_eq;
use constraint_stabilization::body::{Body, BodyDesc, BodyError, MassSpec, Shape, ShapePart};
#[cfg(feature = "serde")]
use constraint_stabilization::io::scene_file::{parse_scene, scene_to_string};
use constraint_stabilization::stabilizer::{BodyVelocity, VelocityFriction};
use constraint_stabilization::{Method, Settings, Stabilizer, Status};
use dev_support::sat::{sat_deepest, sat_depth};
use dev_support::scene::{IDENTITY_XYZW, body, cuboid, ground, pose_bits, scene_of, xyzw};
use nalgebra::{UnitQuaternion, Vector3};

/// Relative agreement of quantities computed two ways in f64.
const SAME: f64 = 1e-12;

/// A part: a box with half extents `h` at `translation`, rotated.
fn box_part(h: [f64; 3], translation: [f64; 3], rotation_xyzw: [f64; 4]) -> ShapePart {
    ShapePart {
        shape: Shape::Cuboid {
            half_extents: Vector3::from(h),
        },
        translation: Vector3::from(translation),
        rotation_xyzw,
    }
}

fn compound(
    name: &str,
    parts: Vec<ShapePart>,
    translation: [f64; 3],
    rotation_xyzw: [f64; 4],
    mass: MassSpec,
) -> BodyDesc {
    body(
        name,
        Shape::Compound { parts },
        translation,
        rotation_xyzw,
        mass,
    )
}

/// The box `[-1, 1] x [-0.5, 0.5] x [-0.25, 0.25]` cut in two along x; the
/// right half is given turned by 90 degrees about x (its y and z half
/// extents swapped), so that the parts' rotations are exercised.
fn cut_box_parts() -> Vec<ShapePart> {
    let quarter = xyzw(&UnitQuaternion::from_axis_angle(
        &Vector3::x_axis(),
        std::f64::consts::FRAC_PI_2,
    ));
    vec![
        box_part([0.5, 0.5, 0.25], [-0.5, 0.0, 0.0], IDENTITY_XYZW),
        box_part([0.5, 0.25, 0.5], [0.5, 0.0, 0.0], quarter),
    ]
}

#[test]
fn a_box_cut_in_two_has_the_mass_properties_of_the_box() {
    let tilt = xyzw(&UnitQuaternion::from_euler_angles(0.3, -0.2, 0.5));
    let whole = Body::new(cuboid(
        "whole",
        [1.0, 0.5, 0.25],
        [1.0, 2.0, 3.0],
        tilt,
        MassSpec::Mass(3.0),
    ))
    .expect("valid box");
    let cut = Body::new(compound(
        "cut",
        cut_box_parts(),
        [1.0, 2.0, 3.0],
        tilt,
        MassSpec::Mass(3.0),
    ))
    .expect("valid compound");
    assert!(cut.is_compound() && cut.polyhedron().is_none());
    assert_eq!(cut.parts().len(), 2);
    let (m_whole, m_cut) = (whole.mass().expect("dynamic"), cut.mass().expect("dynamic"));
    assert_relative_eq!(m_cut.density, m_whole.density, max_relative = SAME);
    assert_relative_eq!(
        m_cut.inertia_body,
        m_whole.inertia_body,
        max_relative = SAME,
        epsilon = SAME
    );
    assert_relative_eq!(
        cut.com_pose().translation.vector,
        whole.com_pose().translation.vector,
        epsilon = SAME
    );
    // The parts cover the box: the same world box, the same vertices'
    // extreme heights.
    let (min_w, max_w) = whole.world_aabb();
    let (min_c, max_c) = cut.world_aabb();
    assert_relative_eq!(min_w, min_c, epsilon = SAME);
    assert_relative_eq!(max_w, max_c, epsilon = SAME);
}

#[test]
fn a_compound_rests_like_the_box_it_is_cut_from() {
    let depth = 0.05;
    let centre = [0.0, 0.25 - depth, 0.0];
    let mut whole = scene_of(&[
        ground(),
        cuboid(
            "whole",
            [1.0, 0.25, 0.5],
            centre,
            IDENTITY_XYZW,
            MassSpec::Mass(2.0),
        ),
    ]);
    // Lying on its side: the box of `cut_box_parts` turned so that its
    // 0.25 half extent is vertical.
    let lying = xyzw(&UnitQuaternion::from_axis_angle(
        &Vector3::x_axis(),
        std::f64::consts::FRAC_PI_2,
    ));
    let mut cut = scene_of(&[
        ground(),
        compound("cut", cut_box_parts(), centre, lying, MassSpec::Mass(2.0)),
    ]);
    // The same lengths for both (by default they follow the smallest
    // convex piece, here a half of the box).
    let settings = {
        let mut settings = Settings::default();
        settings.tolerance_absolute = Some(1e-6);
        settings.contact_margin_absolute = Some(1e-3);
        settings.target_margin_absolute = Some(1e-6);
        settings
    };
    let (report_whole, _) = stabilize_with(&mut whole, settings.clone());
    let (report_cut, _) = stabilize_with(&mut cut, settings.clone());
    assert_eq!(report_cut.status, Status::Converged, "{report_cut:?}");
    assert_eq!(report_whole.status, Status::Converged);
    let (deepest, _) = sat_deepest(&cut);
    assert!(
        deepest <= report_cut.tolerance,
        "exact depth {deepest:e} left"
    );
    // Both are lifted straight up by the same amount; nothing turns.
    let (a, b) = (whole.bodies()[1].com_pose(), cut.bodies()[1].com_pose());
    assert_relative_eq!(a.translation.vector, b.translation.vector, epsilon = 1e-9);
    assert!(a.translation.vector.y > centre[1] + depth);
    let turned = (b.rotation
        * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2)
            .inverse())
    .angle();
    assert!(turned < 1e-9, "the compound turned by {turned:e} rad");
}
/// An L of two boxes with one leg sunk into the ground and the other in a
/// box: every pair of parts of different bodies ends within the tolerance
/// (brute-force separating axes and parry), and the parts keep their
/// places in the body (they move rigidly).
#[test]
fn an_l_shaped_compound_is_pushed_out_of_the_ground_and_a_box() {
    let l_parts = vec![
        box_part([1.0, 0.2, 0.2], [0.0, 0.0, 0.0], IDENTITY_XYZW),
        box_part([0.2, 0.6, 0.2], [0.8, 0.8, 0.0], IDENTITY_XYZW),
    ];
    let tilt = xyzw(&UnitQuaternion::from_euler_angles(0.02, 0.01, -0.03));
    let mut scene = scene_of(&[
        ground(),
        compound("L", l_parts, [0.0, 0.15, 0.0], tilt, MassSpec::Density(1.0)),
        cuboid(
            "box",
            [0.3, 0.3, 0.3],
            [1.2, 1.1, 0.0],
            IDENTITY_XYZW,
            MassSpec::Density(1.0),
        ),
    ]);
    let before = sat_deepest(&scene).0;
    assert!(before > 0.04, "the scene penetrates ({before:e})");
    let offset_before = parts_offset(&scene);
    let (report, _) = stabilize_default(&mut scene);
    assert_eq!(report.status, Status::Converged, "{report:?}");
    let (deepest, pair) = sat_deepest(&scene);
    assert!(
        deepest <= report.tolerance,
        "exact depth {deepest:e} left in {pair:?}"
    );
    let shapes = parry_shapes(&scene);
    for (a, b) in [(0, 1), (0, 2), (1, 2)] {
        let parry = crate::stabilize::support::parry_pair_depth(&scene, &shapes, a, b);
        assert!(parry <= report.tolerance, "parry: {parry:e} in ({a}, {b})");
    }
    // The offset between the parts, in the world, turned with the body.
    let offset_after = parts_offset(&scene);
    assert_relative_eq!(
        offset_after.norm(),
        offset_before.norm(),
        max_relative = SAME
    );
    // Both parts touched something: each is within the contact margin of
    // the ground or the box (the correction did not just lift one part).
    assert!(sat_depth(&scene, 1, 2) <= report.tolerance);
}

/// World vector from the L's first part to its second.
fn parts_offset(scene: &constraint_stabilization::scene::Scene) -> Vector3<f64> {
    let poses: Vec<_> = scene.bodies()[1].part_poses().collect();
    poses[1].translation.vector - poses[0].translation.vector
}

/// Parts of one body that overlap each other (a cross of two boxes) are
/// not a penetration: alone on the ground the cross is not touched.
#[test]
fn overlapping_parts_of_one_body_are_not_a_penetration() {
    let cross = vec![
        box_part([1.0, 0.1, 0.1], [0.0, 0.0, 0.0], IDENTITY_XYZW),
        box_part([0.1, 0.1, 1.0], [0.0, 0.0, 0.0], IDENTITY_XYZW),
    ];
    let mut scene = scene_of(&[
        ground(),
        compound(
            "cross",
            cross,
            [0.0, 0.1, 0.0],
            IDENTITY_XYZW,
            MassSpec::Mass(1.0),
        ),
    ]);
    let before = pose_bits(&scene);
    let (report, _) = stabilize_default(&mut scene);
    assert_eq!(report.status, Status::NothingToDo);
    assert_eq!(report.passes, 0);
    assert!(report.penetrations_before.is_empty());
    assert_eq!(pose_bits(&scene), before);
}

/// Two crosses dropped into each other: the report names the bodies and
/// their parts, the call resolves every part pair, and the Gauss–Seidel
/// method works on the same parts.
#[test]
fn two_compounds_interpenetrating_are_separated_by_both_methods() {
    let cross = || {
        vec![
            box_part([0.6, 0.1, 0.1], [0.0, 0.0, 0.0], IDENTITY_XYZW),
            box_part([0.1, 0.1, 0.6], [0.0, 0.0, 0.0], IDENTITY_XYZW),
        ]
    };
    let turned = xyzw(&UnitQuaternion::from_euler_angles(0.05, 0.7, 0.02));
    let descs = [
        ground(),
        compound(
            "lower",
            cross(),
            [0.0, 0.08, 0.0],
            IDENTITY_XYZW,
            MassSpec::Mass(1.0),
        ),
        compound(
            "upper",
            cross(),
            [0.1, 0.22, 0.05],
            turned,
            MassSpec::Mass(1.0),
        ),
    ];
    let mut scene = scene_of(&descs);
    let mut stabilizer = Stabilizer::new(Settings::default()).expect("valid settings");
    let found = stabilizer.penetrations(&scene).expect("valid scene");
    assert!(
        found.iter().any(|p| (p.body_a, p.body_b) == (1, 2)),
        "{found:?}"
    );
    assert!(found.iter().all(|p| p.parts.iter().all(|&k| k < 2)));
    let report = stabilizer.stabilize(&mut scene).expect("valid scene");
    assert_eq!(report.status, Status::Converged, "{report:?}");
    let (deepest, pair) = sat_deepest(&scene);
    assert!(
        deepest <= report.tolerance,
        "projection: {deepest:e} left in {pair:?}"
    );

    let mut scene = scene_of(&descs);
    let before = sat_deepest(&scene).0;
    let settings = {
        let mut settings = Settings::default();
        settings.method = Method::GaussSeidel;
        settings
    };
    let (report, _) = stabilize_with(&mut scene, settings);
    let (after, _) = sat_deepest(&scene);
    // The baseline is slow with its defaults (an uncut box sunk by 0.05
    // keeps 0.036 after its sweeps); it must make progress.
    assert!(
        after < 0.9 * before,
        "Gauss–Seidel: {before:e} -> {after:e} ({:?})",
        report.status
    );
}

/// The velocity projection acts on the body through its parts: a compound
/// falling onto the ground with its leg touching stops approaching.
#[test]
fn the_velocity_projection_stops_a_compound_landing_on_one_part() {
    let l_parts = vec![
        box_part([1.0, 0.2, 0.2], [0.0, 0.0, 0.0], IDENTITY_XYZW),
        box_part([0.2, 0.3, 0.2], [0.8, -0.5, 0.0], IDENTITY_XYZW),
    ];
    // The leg's bottom is 0.8 below the shape origin: at this height it
    // sinks 1e-3 into the ground and the bar is in the air.
    let y = 0.8 - 1e-3;
    let mut scene = scene_of(&[
        ground(),
        compound(
            "L",
            l_parts,
            [0.0, y, 0.0],
            IDENTITY_XYZW,
            MassSpec::Mass(1.0),
        ),
    ]);
    let mut stabilizer = Stabilizer::new(Settings::default()).expect("valid settings");
    let report = stabilizer.stabilize(&mut scene).expect("valid scene");
    assert_eq!(report.status, Status::Converged);
    let mut velocities = vec![BodyVelocity::default(); 2];
    velocities[1].linear = Vector3::new(0.0, -1.0, 0.0);
    let velocity = stabilizer
        .project_velocities(&scene, &mut velocities, &[1], None, VelocityFriction::None)
        .expect("valid velocities");
    assert!(velocity.approach_before > 0.5, "{velocity:?}");
    assert!(velocity.approach_after <= 1e-9, "{velocity:?}");
    // Stopped at the leg, off the centre of mass: the body now turns about
    // it (the bar's free end keeps falling).
    assert!(velocities[1].angular.norm() > 0.1, "{:?}", velocities[1]);
}

#[cfg(feature = "serde")]
#[test]
fn a_compound_round_trips_through_a_scene_file() {
    let scene = scene_of(&[
        ground(),
        compound(
            "cut",
            cut_box_parts(),
            [0.1, 0.3, 0.0],
            IDENTITY_XYZW,
            MassSpec::Density(2.0),
        ),
    ]);
    let text = scene_to_string(&scene, None);
    assert!(text.contains("\"compound\""), "{text}");
    let read = parse_scene(&text).expect("the written file reads back");
    assert_eq!(read.bodies()[1].shape(), scene.bodies()[1].shape());
    assert_eq!(scene_to_string(&read, None), text);
}

#[test]
fn invalid_compounds_are_typed_errors() {
    let with = |parts| {
        Body::new(compound(
            "c",
            parts,
            [0.0; 3],
            IDENTITY_XYZW,
            MassSpec::Mass(1.0),
        ))
    };
    assert_eq!(with(vec![]).unwrap_err(), BodyError::CompoundPartCount(0));
    let nested = ShapePart {
        shape: Shape::Compound {
            parts: cut_box_parts(),
        },
        translation: Vector3::zeros(),
        rotation_xyzw: IDENTITY_XYZW,
    };
    let error = with(vec![box_part([1.0; 3], [0.0; 3], IDENTITY_XYZW), nested]).unwrap_err();
    assert!(
        matches!(error, BodyError::CompoundPart { index: 1, ref error } if **error == BodyError::NestedCompound)
    );
    let bad_rotation = box_part([1.0; 3], [0.0; 3], [0.0, 0.0, 0.0, 2.0]);
    let error = with(vec![bad_rotation]).unwrap_err();
    assert!(
        matches!(error, BodyError::CompoundPart { index: 0, ref error } if matches!(**error, BodyError::RotationNotUnit { .. }))
    );
    let far = box_part([1.0; 3], [f64::NAN, 0.0, 0.0], IDENTITY_XYZW);
    assert!(matches!(
        with(vec![far]).unwrap_err(),
        BodyError::CompoundPart { index: 0, .. }
    ));
}

#[cfg(feature = "serde")]
#[test]
fn a_nested_compound_in_a_scene_file_is_an_error_naming_the_field() {
    let text = r#"{"bodies": [{"name": "c", "shape": {"compound": [{"shape": {"compound": []}, "translation": [0,0,0], "rotation": [0,0,0,1]}]}, "translation": [0,0,0], "rotation": [0,0,0,1], "mass": 1}]}"#;
    let error = parse_scene(text).unwrap_err().to_string();
    assert!(
        error.contains("shape.compound[0].shape.compound"),
        "{error}"
    );
}

/// Removing a body keeps the warm starts of the compound's part pairs
/// under their new indices: the next call queries them warm.
#[test]
fn removing_a_body_keeps_a_compounds_warm_starts() {
    let mut scene = scene_of(&[
        cuboid(
            "spare",
            [0.1; 3],
            [5.0, 5.0, 5.0],
            IDENTITY_XYZW,
            MassSpec::Mass(1.0),
        ),
        ground(),
        compound(
            "cut",
            cut_box_parts(),
            [0.0, 0.2, 0.0],
            IDENTITY_XYZW,
            MassSpec::Mass(1.0),
        ),
    ]);
    let mut stabilizer = Stabilizer::new(Settings::default()).expect("valid settings");
    stabilizer.stabilize(&mut scene).expect("valid scene");
    let warm = stabilizer.warm_starts();
    assert!(warm >= 2, "both parts touch the ground: {warm} warm starts");
    stabilizer
        .remove_bodies(&mut scene, &[0])
        .expect("in range");
    assert_eq!(stabilizer.warm_starts(), warm);
}
