//! Redundant contacts and deep overlaps: boxes face to face, a box on four
//! supports, a box in a tight fixed slot; overlaps of 50 % and 90 %, a hull
//! inside another, identical hulls at identical poses, two bars crossing
//! edge to edge with no vertex inside either. Each must converge (exact
//! depth by brute-force separating axes within the tolerance) and, where
//! the minimal correction is known in closed form, make it. Boxes at one
//! pose and a box inside a box are in `scenes`; here are the
//! cases it does not cover.
//!
//! `cargo test --test it stabilize::deep:: -- --nocapture` prints each run.

use crate::stabilize::extreme::{assert_converged, assert_translated, run, target_margin};
use constraint_stabilization::Settings;
use constraint_stabilization::body::{BodyDesc, MassSpec};
use constraint_stabilization::scene::Scene;
use dev_support::scene::{IDENTITY_XYZW, cuboid, ground, hull, scene_of, xyzw};
use nalgebra::{Point3, UnitQuaternion, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Overlap of the resting contacts, a fraction of a unit box.
const OVERLAP: f64 = 0.01;

/// Passes allowed for a resting contact (one solve, one refinement).
const RESTING_PASSES: usize = 2;

/// Passes allowed for a deep overlap (several trust-region steps).
const DEEP_PASSES: usize = 12;

fn unit_box(name: &str, at: [f64; 3]) -> BodyDesc {
    cuboid(name, [0.5; 3], at, IDENTITY_XYZW, MassSpec::Mass(1.0))
}

fn fixed_box(name: &str, half: [f64; 3], at: [f64; 3]) -> BodyDesc {
    cuboid(name, half, at, IDENTITY_XYZW, MassSpec::Fixed)
}

#[test]
fn boxes_face_to_face_split_the_overlap() {
    let descs = [
        unit_box("a", [0.0; 3]),
        unit_box("b", [1.0 - OVERLAP, 0.0, 0.0]),
    ];
    let run = run("face to face", &descs, Settings::default());
    assert_converged("face to face", &run, RESTING_PASSES);
    let half = (OVERLAP + target_margin(&run)) / 2.0;
    assert_translated(&run, 0, -Vector3::x() * half);
    assert_translated(&run, 1, Vector3::x() * half);
}

#[test]
fn box_on_four_supports_lifts_flat() {
    let mut descs: Vec<_> = [[-0.8, -0.8], [-0.8, 0.8], [0.8, -0.8], [0.8, 0.8]]
        .iter()
        .enumerate()
        .map(|(k, [x, z])| fixed_box(&format!("support{k}"), [0.1, 0.5, 0.1], [*x, 0.5, *z]))
        .collect();
    let start = [0.0, 1.2 - OVERLAP, 0.0];
    descs.push(cuboid(
        "slab",
        [1.0, 0.2, 1.0],
        start,
        IDENTITY_XYZW,
        MassSpec::Mass(1.0),
    ));
    let run = run("box on four supports", &descs, Settings::default());
    assert_converged("box on four supports", &run, RESTING_PASSES);
    assert_translated(&run, 4, Vector3::y() * (OVERLAP + target_margin(&run)));
}

/// A unit box sunk `OVERLAP` into the floor of a fixed slot whose walls
/// leave it `clearance` on each side.
fn box_in_slot(clearance: f64) -> Vec<BodyDesc> {
    let wall_x = 1.5 + clearance;
    vec![
        ground(),
        fixed_box("left wall", [1.0, 2.0, 2.0], [-wall_x, 2.0, 0.0]),
        fixed_box("right wall", [1.0, 2.0, 2.0], [wall_x, 2.0, 0.0]),
        unit_box("box", [0.0, 0.5 - OVERLAP, 0.0]),
    ]
}

#[test]
fn box_in_a_slot_with_clearance_rises_without_touching_the_walls() {
    // Clearance of twice the target margin: the wall rows hold at dq = 0.
    let clearance = 2.0 * Settings::default().target_margin_relative * 0.5 * 3f64.sqrt();
    let run = run(
        "slot with clearance",
        &box_in_slot(clearance),
        Settings::default(),
    );
    assert_converged("slot with clearance", &run, RESTING_PASSES);
    assert_translated(&run, 3, Vector3::y() * (OVERLAP + target_margin(&run)));
}

#[test]
fn box_in_an_exactly_fitting_slot_rises_with_no_target_margin() {
    // The walls touch the box's sides (gap 0). With no target margin the
    // wall rows hold at dq = 0 and the box rises.
    let settings = {
        let mut settings = Settings::default();
        settings.target_margin_absolute = Some(0.0);
        settings
    };
    let run = run("exact slot, no target margin", &box_in_slot(0.0), settings);
    assert_converged("exact slot, no target margin", &run, RESTING_PASSES);
    assert_translated(&run, 3, Vector3::y() * OVERLAP);
}

/// Formerly a known failure: every row, including a separated pair's
/// within the contact margin, asks for the target margin, so walls
/// touching both sides ask the box to move away from both: the linearized
/// problem is infeasible (Lemke: ray, clarabel: primal infeasible) and the
/// call ended `unsolved` with the poses as they came. Such an island is
/// now solved again with the rows within the tolerance of contact holding
/// their gap (`Settings::hold_open_gaps`, `projector::step::held_rows`):
/// the walls ask only not to close, and the box rises straight out of the
/// floor by its overlap and the target margin, as with clearance.
#[test]
fn box_in_an_exactly_fitting_slot_rises_with_the_default_settings() {
    let run = run("exact slot", &box_in_slot(0.0), Settings::default());
    assert_converged("exact slot", &run, RESTING_PASSES);
    assert_translated(&run, 3, Vector3::y() * (OVERLAP + target_margin(&run)));
    let first = &run.report.pass_reports[0].solved[0];
    assert!(first.rows_held, "{first:#?}");
}

/// Without the retry on held rows (`hold_open_gaps = false`) the exact slot is still
/// infeasible and the call returns the input: the flag is what fixes it.
#[test]
fn box_in_an_exactly_fitting_slot_is_infeasible_with_the_seeds_rows() {
    let settings = {
        let mut settings = Settings::default();
        settings.hold_open_gaps = false;
        settings
    };
    let run = run("exact slot, no retry", &box_in_slot(0.0), settings);
    assert!(!run.report.status.is_resolved(), "{:?}", run.report.status);
    assert_eq!(run.report.bodies_moved, 0);
}

#[test]
fn overlaps_of_half_and_nine_tenths_separate_along_the_shortest_axis() {
    for fraction in [0.5, 0.9] {
        let label = format!("overlap {fraction}");
        let offset = 1.0 - fraction;
        let descs = [unit_box("a", [0.0; 3]), unit_box("b", [offset, 0.0, 0.0])];
        let run = run(&label, &descs, Settings::default());
        assert_converged(&label, &run, DEEP_PASSES);
        let half = (fraction + target_margin(&run)) / 2.0;
        assert_translated(&run, 0, -Vector3::x() * half);
        assert_translated(&run, 1, Vector3::x() * half);
    }
}

/// Random points on a sphere of radius `radius` about the origin.
fn round_hull_points(rng: &mut ChaCha8Rng, count: usize, radius: f64) -> Vec<Point3<f64>> {
    (0..count)
        .map(|_| {
            let v = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0));
            Point3::from(v.normalize() * radius)
        })
        .collect()
}

#[test]
fn hull_inside_a_hull_escapes() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let descs = [
        hull(
            "big",
            round_hull_points(&mut rng, 40, 1.0),
            [0.0; 3],
            IDENTITY_XYZW,
            MassSpec::Density(1.0),
        ),
        hull(
            "small",
            round_hull_points(&mut rng, 20, 0.3),
            [0.1, -0.05, 0.2],
            IDENTITY_XYZW,
            MassSpec::Density(1.0),
        ),
    ];
    let run = run("hull inside a hull", &descs, Settings::default());
    assert_converged("hull inside a hull", &run, DEEP_PASSES);
}

#[test]
fn identical_hulls_at_identical_poses_separate() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let points = round_hull_points(&mut rng, 30, 0.5);
    let turned = xyzw(&UnitQuaternion::from_scaled_axis(Vector3::new(
        0.4, 0.1, -0.3,
    )));
    let descs: Vec<_> = (0..2)
        .map(|k| {
            hull(
                &format!("twin{k}"),
                points.clone(),
                [1.0, 2.0, 3.0],
                turned,
                MassSpec::Mass(1.0),
            )
        })
        .collect();
    let run = run("identical hulls", &descs, Settings::default());
    assert_converged("identical hulls", &run, DEEP_PASSES);
}

/// Half width of the crossing bars' square section.
const BAR_HALF: f64 = 0.2;

/// The two bars: A along x turned 45 degrees about x (its top an edge
/// along x), B along z turned 45 degrees about z (its bottom an edge along
/// z), B's bottom edge `OVERLAP` below A's top edge.
fn crossing_bars() -> [BodyDesc; 2] {
    let ridge = BAR_HALF * std::f64::consts::SQRT_2;
    let quarter = std::f64::consts::FRAC_PI_4;
    let a = UnitQuaternion::from_scaled_axis(Vector3::x() * quarter);
    let b = UnitQuaternion::from_scaled_axis(Vector3::z() * quarter);
    [
        cuboid(
            "a",
            [1.0, BAR_HALF, BAR_HALF],
            [0.0; 3],
            xyzw(&a),
            MassSpec::Mass(1.0),
        ),
        cuboid(
            "b",
            [BAR_HALF, BAR_HALF, 1.0],
            [0.0, 2.0 * ridge - OVERLAP, 0.0],
            xyzw(&b),
            MassSpec::Mass(1.0),
        ),
    ]
}

/// Vertices of body `a` strictly inside body `b` (behind every face plane).
fn vertices_inside(scene: &Scene, a: usize, b: usize) -> usize {
    let (body_a, body_b) = (&scene.bodies()[a], &scene.bodies()[b]);
    let to_b = body_b.com_pose().inverse() * body_a.com_pose();
    body_a
        .polyhedron()
        .expect("a convex body")
        .vertices()
        .iter()
        .filter(|v| {
            let p = to_b * **v;
            body_b
                .polyhedron()
                .expect("a convex body")
                .faces()
                .iter()
                .all(|f| f.plane.signed_distance(&p) < 0.0)
        })
        .count()
}

#[test]
fn bars_crossing_edge_to_edge_separate_along_the_edges_normal() {
    let descs = crossing_bars();
    let input = scene_of(&descs);
    assert_eq!(
        vertices_inside(&input, 0, 1) + vertices_inside(&input, 1, 0),
        0
    );
    let run = run("crossing bars", &descs, Settings::default());
    assert_converged("crossing bars", &run, RESTING_PASSES);
    // One contact at the crossing, on the line of both centres: no lever,
    // equal masses: each moves half the overlap along y.
    let half = (OVERLAP + target_margin(&run)) / 2.0;
    assert_translated(&run, 0, -Vector3::y() * half);
    assert_translated(&run, 1, Vector3::y() * half);
}
