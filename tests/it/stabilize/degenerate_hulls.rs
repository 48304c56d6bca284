//! Hulls near the edge of what the geometry accepts, each sunk into the
//! ground and into a second copy of itself: a sliver (a tetrahedron 1e-3
//! as tall as wide), a needle (1e-3 as wide as long), a box whose top is
//! made of points off its plane by 1e-9 (nearly coplanar faces), and a box
//! with every corner repeated at 1e-11 and 1e-9 from itself (nearly
//! duplicate points, below and above the hull's merge tolerance). Each
//! must converge, judged by the brute-force separating-axis depth.
//!
//! `cargo test --test it stabilize::degenerate_hulls:: -- --nocapture` prints
//! each run.

use crate::stabilize::extreme::{assert_converged, run};
use constraint_stabilization::Settings;
use constraint_stabilization::body::{BodyDesc, MassSpec};
use dev_support::scene::{ground, hull, xyzw};
use nalgebra::{Point3, UnitQuaternion, Vector3};

/// Passes allowed (tilted thin bodies take refinements).
const PASSES: usize = 12;

/// How deep each body is sunk, relative to its thinnest dimension.
const SINK: f64 = 0.1;

fn sliver() -> Vec<Point3<f64>> {
    vec![
        Point3::new(-0.5, 0.0, -0.5),
        Point3::new(0.5, 0.0, -0.5),
        Point3::new(0.0, 0.0, 0.5),
        Point3::new(0.0, 1e-3, 0.0),
    ]
}

fn needle() -> Vec<Point3<f64>> {
    let w = 5e-4;
    vec![
        Point3::new(-0.5, 0.0, 0.0),
        Point3::new(0.5, 0.0, 0.0),
        Point3::new(0.0, -w, -w),
        Point3::new(0.0, w, -w),
        Point3::new(0.0, -w, w),
        Point3::new(0.0, w, w),
    ]
}

fn box_corners(h: f64) -> Vec<Point3<f64>> {
    let mut corners = Vec::new();
    for x in [-h, h] {
        for y in [-h, h] {
            for z in [-h, h] {
                corners.push(Point3::new(x, y, z));
            }
        }
    }
    corners
}

/// A box of half extent 0.5 whose top face carries a grid of points off
/// its plane by up to 1e-9 (nearly coplanar facets).
fn nearly_coplanar_top() -> Vec<Point3<f64>> {
    let mut points = box_corners(0.5);
    for i in 0..5 {
        for k in 0..5 {
            let bump = 1e-9 * (((i * 5 + k) % 3) as f64 - 1.0);
            points.push(Point3::new(
                -0.4 + 0.2 * i as f64,
                0.5 + bump,
                -0.4 + 0.2 * k as f64,
            ));
        }
    }
    points
}

/// A box with every corner repeated at 1e-11 and 1e-9 from itself.
fn nearly_duplicate_corners() -> Vec<Point3<f64>> {
    let corners = box_corners(0.5);
    let mut points = corners.clone();
    for (step, c) in [1e-11, 1e-9]
        .iter()
        .flat_map(|s| corners.iter().map(move |c| (s, c)))
    {
        points.push(c + Vector3::new(*step, -step, 0.5 * step));
    }
    points
}

/// The body sunk by `SINK` of `thickness` into the ground (turned a
/// little, so that the contact is a corner), and a copy above sunk as deep
/// into it.
fn pair_on_ground(name: &str, points: Vec<Point3<f64>>, thickness: f64) -> Vec<BodyDesc> {
    let turned = xyzw(&UnitQuaternion::from_scaled_axis(Vector3::new(
        0.0, 0.5, 0.0,
    )));
    let tilt = UnitQuaternion::from_scaled_axis(Vector3::new(0.1 * thickness, 0.7, 0.0));
    let sink = SINK * thickness;
    let (min_y, max_y) = points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p.y), hi.max(p.y))
        });
    vec![
        ground(),
        hull(
            &format!("{name} low"),
            points.clone(),
            [0.0, -min_y - sink, 0.0],
            turned,
            MassSpec::Density(1.0),
        ),
        hull(
            &format!("{name} high"),
            points,
            [0.05, max_y - 2.0 * min_y - 2.0 * sink, 0.03],
            xyzw(&tilt),
            MassSpec::Density(1.0),
        ),
    ]
}

fn check(name: &str, points: Vec<Point3<f64>>, thickness: f64) {
    let descs = pair_on_ground(name, points, thickness);
    let run = run(name, &descs, Settings::default());
    assert!(
        run.depth_before > run.report.tolerance,
        "{name}: must penetrate"
    );
    assert_converged(name, &run, PASSES);
}

#[test]
fn sliver_tetrahedra_on_the_ground() {
    check("sliver", sliver(), 1e-3);
}

#[test]
fn needles_on_the_ground() {
    check("needle", needle(), 1e-3);
}

#[test]
fn nearly_coplanar_faces_on_the_ground() {
    check("nearly coplanar", nearly_coplanar_top(), 1.0);
}

#[test]
fn nearly_duplicate_points_on_the_ground() {
    check("nearly duplicate", nearly_duplicate_corners(), 1.0);
}
