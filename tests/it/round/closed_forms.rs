//! Closed forms: a sphere sunk into the ground is lifted by exactly its
//! depth; two free spheres separate along their centre line in the inverse
//! ratio of their masses without turning; a capsule lying across a box's
//! edge; a rounded box's depth is the Minkowski-sum depth of its core and
//! radius; a capsule lying on a face has two contact points, a rounded box
//! on a face four.

use super::{part_geometry, signed_distance};
use crate::stabilize::support::{describe, stabilize_with};
use constraint_stabilization::body::{MassSpec, Shape};
use constraint_stabilization::internals::contact::contact_points;
use constraint_stabilization::{Settings, Status};
use dev_support::scene::{IDENTITY_XYZW, body, cuboid, ground, scene_of, xyzw};
use dev_support::support_oracle::body_depth;
use nalgebra::{UnitQuaternion, Vector3};

/// Tight tolerance and target margin, relative to the scene's scale.
const TIGHT: f64 = 1e-9;

/// Agreement of a motion with its closed form, relative to the motion.
const MOTION_AGREEMENT: f64 = 1e-6;

/// Agreement of a depth with its closed form, relative to the body's size
/// (rounding only).
const DEPTH_AGREEMENT: f64 = 1e-12;

fn tight() -> Settings {
    let mut settings = Settings::default();
    settings.tolerance_relative = TIGHT;
    settings.target_margin_relative = TIGHT;
    settings
}

fn sphere(
    name: &str,
    radius: f64,
    at: [f64; 3],
    mass: MassSpec,
) -> constraint_stabilization::BodyDesc {
    body(name, Shape::Sphere { radius }, at, IDENTITY_XYZW, mass)
}

#[test]
fn sphere_sunk_into_the_ground_is_lifted_by_its_depth() {
    let (radius, depth) = (0.4, 0.05);
    let start = [0.3, radius - depth, -0.2];
    let mut scene = scene_of(&[ground(), sphere("ball", radius, start, MassSpec::Mass(2.0))]);
    let measured = -signed_distance(&scene.bodies()[1], &scene.bodies()[0]);
    assert!(
        (measured - depth).abs() <= DEPTH_AGREEMENT,
        "depth {measured}"
    );
    let (report, residual) = stabilize_with(&mut scene, tight());
    println!("{}", describe("sphere on ground", &report, residual));
    assert_eq!(report.status, Status::Converged);
    let margin = TIGHT * report.scale;
    let moved = scene.bodies()[1].translation_user() - Vector3::from(start);
    let expected = Vector3::y() * (depth + margin);
    assert!(
        (moved - expected).norm() <= MOTION_AGREEMENT * expected.norm(),
        "moved {moved:?}, expected {expected:?}"
    );
    assert!(
        residual <= report.tolerance,
        "oracle depth after {residual:e}"
    );
}

#[test]
fn two_free_spheres_separate_along_their_centre_line_in_mass_ratio() {
    let (ra, rb, depth) = (0.5, 0.3, 0.04);
    let direction = Vector3::new(0.3, -0.5, 0.8).normalize();
    let centre_a = Vector3::new(0.1, 2.0, 0.0);
    let centre_b = centre_a + direction * (ra + rb - depth);
    for (ma, mb) in [(1.0, 3.0), (1.0, 1e3)] {
        // Turned spheres: a correction that turns them is visible.
        let turn = xyzw(&UnitQuaternion::from_scaled_axis(Vector3::new(
            0.3, 0.2, -0.4,
        )));
        let mut scene = scene_of(&[
            body(
                "a",
                Shape::Sphere { radius: ra },
                centre_a.into(),
                turn,
                MassSpec::Mass(ma),
            ),
            body(
                "b",
                Shape::Sphere { radius: rb },
                centre_b.into(),
                turn,
                MassSpec::Mass(mb),
            ),
        ]);
        let (report, residual) = stabilize_with(&mut scene, tight());
        println!("{}", describe("two spheres", &report, residual));
        assert_eq!(report.status, Status::Converged);
        let gap = depth + TIGHT * report.scale;
        let expected_a = -direction * gap * mb / (ma + mb);
        let expected_b = direction * gap * ma / (ma + mb);
        for (index, start, expected) in [(0, centre_a, expected_a), (1, centre_b, expected_b)] {
            let body = &scene.bodies()[index];
            let moved = body.translation_user() - start;
            assert!(
                (moved - expected).norm() <= MOTION_AGREEMENT * gap,
                "masses {ma}, {mb}: body {index} moved {moved:?}, expected {expected:?}"
            );
            let start_rotation = UnitQuaternion::from_scaled_axis(Vector3::new(0.3, 0.2, -0.4));
            let turned = body.user_pose().rotation.angle_to(&start_rotation);
            assert!(turned <= 1e-12, "body {index} turned by {turned:e}");
        }
        assert!(residual <= report.tolerance);
    }
}

#[test]
fn capsule_lying_across_a_box_edge() {
    // A box whose top face is y = 0, edge along z at x = 0.5; a capsule
    // along x centred on the edge, sunk by `depth`: half of it lies on the
    // face, half hangs past the edge. The depth is `depth` (along y).
    let (radius, half, depth) = (0.1, 0.6, 0.02);
    let turn_z_to_x = xyzw(&UnitQuaternion::from_scaled_axis(
        Vector3::y() * std::f64::consts::FRAC_PI_2,
    ));
    let mut scene = scene_of(&[
        cuboid(
            "box",
            [0.5, 0.5, 0.5],
            [0.0, -0.5, 0.0],
            IDENTITY_XYZW,
            MassSpec::Fixed,
        ),
        body(
            "capsule",
            Shape::Capsule {
                half_height: half,
                radius,
            },
            [0.5, radius - depth, 0.0],
            turn_z_to_x,
            MassSpec::Mass(1.0),
        ),
    ]);
    let measured = -signed_distance(&scene.bodies()[1], &scene.bodies()[0]);
    assert!(
        (measured - depth).abs() <= DEPTH_AGREEMENT,
        "depth {measured}"
    );
    let oracle = body_depth(&scene.bodies()[1], &scene.bodies()[0]);
    assert!((oracle - depth).abs() <= 1e-9, "oracle {oracle}");
    // The contact points: the end on the face and the point above the edge.
    let queries = super::part_queries(&scene.bodies()[1], &scene.bodies()[0]);
    let (capsule, boxed) = (&scene.bodies()[1], &scene.bodies()[0]);
    let points = contact_points(
        &queries[0],
        &part_geometry(capsule, 0),
        &part_geometry(boxed, 0),
        0.01,
        &Settings::default(),
    )
    .points;
    let xs: Vec<f64> = points.iter().map(|p| p.point_a_world.x).collect();
    println!("capsule across edge: points at x {xs:?}");
    assert_eq!(points.len(), 2, "{points:?}");
    assert!(
        xs.iter().any(|x| (x - (0.5 - half)).abs() < 1e-12),
        "the end on the face"
    );
    assert!(
        xs.iter().any(|x| (x - 0.5).abs() < 1e-12),
        "the point above the edge"
    );
    let (report, residual) = stabilize_with(&mut scene, tight());
    println!("{}", describe("capsule across edge", &report, residual));
    assert_eq!(report.status, Status::Converged);
    assert!(
        residual <= report.tolerance,
        "oracle depth after {residual:e}"
    );
}

#[test]
fn rounded_box_depth_is_the_minkowski_sum_depth() {
    // Core box (0.4, 0.3, 0.2) grown by 0.1, tilted onto an edge and a
    // corner: the depth in the ground is the core's lowest vertex's depth
    // plus the radius, and a face-down one's is the core face's plus the
    // radius.
    let (h, r) = (Vector3::new(0.4, 0.3, 0.2), 0.1);
    for rotation in [
        UnitQuaternion::identity(),
        UnitQuaternion::from_scaled_axis(Vector3::new(0.0, 0.0, 0.5)),
        UnitQuaternion::from_scaled_axis(Vector3::new(0.4, 0.3, 0.7)),
    ] {
        let lowest = (0..8)
            .map(|i| {
                let sign = |bit: usize| if i & (1 << bit) != 0 { 1.0 } else { -1.0 };
                (rotation * Vector3::new(sign(0) * h.x, sign(1) * h.y, sign(2) * h.z)).y
            })
            .fold(f64::INFINITY, f64::min);
        let depth = 0.03;
        // The solid's lowest point is `lowest - r` below its centre.
        let y = -lowest + r - depth;
        let scene = scene_of(&[
            ground(),
            body(
                "rounded",
                Shape::RoundCuboid {
                    half_extents: h,
                    radius: r,
                },
                [0.0, y, 0.0],
                xyzw(&rotation),
                MassSpec::Mass(1.0),
            ),
        ]);
        let measured = -signed_distance(&scene.bodies()[1], &scene.bodies()[0]);
        assert!(
            (measured - depth).abs() <= DEPTH_AGREEMENT,
            "{rotation:?}: depth {measured}"
        );
        let oracle = body_depth(&scene.bodies()[1], &scene.bodies()[0]);
        assert!((oracle - depth).abs() <= 1e-9, "oracle {oracle}");
    }
}

#[test]
fn flat_contacts_give_two_and_four_points() {
    let settings = Settings::default();
    let depth = 0.01;
    let turn_z_to_x = xyzw(&UnitQuaternion::from_scaled_axis(
        Vector3::y() * std::f64::consts::FRAC_PI_2,
    ));
    let cases = [
        (
            Shape::Capsule {
                half_height: 0.5,
                radius: 0.1,
            },
            0.1,
            turn_z_to_x,
            2,
        ),
        (
            Shape::RoundCuboid {
                half_extents: Vector3::new(0.4, 0.2, 0.3),
                radius: 0.05,
            },
            0.25,
            IDENTITY_XYZW,
            4,
        ),
    ];
    for (shape, bottom, rotation, expected) in cases {
        let scene = scene_of(&[
            ground(),
            body(
                "lying",
                shape.clone(),
                [0.0, bottom - depth, 0.0],
                rotation,
                MassSpec::Mass(1.0),
            ),
        ]);
        let (lying, floor) = (&scene.bodies()[1], &scene.bodies()[0]);
        let queries = super::part_queries(lying, floor);
        let points = contact_points(
            &queries[0],
            &part_geometry(lying, 0),
            &part_geometry(floor, 0),
            0.001,
            &settings,
        )
        .points;
        assert_eq!(points.len(), expected, "{shape:?}: {points:?}");
        for p in &points {
            assert!((p.separation + depth).abs() <= 1e-12, "{shape:?}: {p:?}");
            assert!((p.normal_world - Vector3::y()).norm() <= 1e-12);
        }
    }
}
