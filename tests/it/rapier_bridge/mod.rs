//! The Rapier bridge against hand-built Rapier worlds: frames (body,
//! collider offset, hull points off their origin), the correction written
//! back by the depth with velocities untouched, skipped colliders counted,
//! kinematic and fixed bodies never moved, the scene kept across calls.
//! The submodules (`compound`, `coupling`, `kept_scene`, `round_off`): bodies added and removed
//! between steps, the coupling modes, the f32 round-off of the write-back.

mod compound;
mod coupling;
mod joints;
mod kept_scene;
mod limbo;
mod rest;
mod round;
mod round_off;
mod round_off_bound;
mod stack;
mod struck;
mod wedged;
mod world_from_scene;
mod worlds;

use constraint_stabilization::rapier_bridge::{
    BridgeReport, BridgeSettings, CouplingMode, RapierBridge, SkipReason, pose_to_f64,
};
use constraint_stabilization::testbed::verify::parry_penetration;
use nalgebra::{Isometry3, Point3};
use rapier3d::prelude::*;

/// f32 rounding of a pose component near 1 (a few ulps of 2^-23 ≈ 1.2e-7):
/// what separates the bridge's f64 poses from the f32 poses in Rapier.
const F32_POSE_TOLERANCE: f64 = 1e-6;

/// Penetration left that parry may still measure after a corrected call:
/// the stabilizer's tolerance (1e-6 of the smallest body) plus f32 rounding.
const DEPTH_LEFT_TOLERANCE: f64 = 2e-6;

/// How far the box starts below the ground's top face.
const SINK_DEPTH: f32 = 0.05;

fn ground(world: &mut PhysicsWorld) -> ColliderHandle {
    let ground = world.insert_body(RigidBodyBuilder::fixed());
    let collider = ColliderBuilder::cuboid(5.0, 0.5, 5.0).translation(Vector::new(0.0, -0.5, 0.0));
    world.insert_collider(collider, Some(ground))
}

fn dynamic_box_at(world: &mut PhysicsWorld, y: f32) -> (RigidBodyHandle, ColliderHandle) {
    let body = RigidBodyBuilder::dynamic()
        .translation(Vector::new(0.3, y, -0.2))
        .linvel(Vector::new(1.0, -2.0, 0.5))
        .angvel(Vector::new(0.1, 0.2, 0.3))
        .sleeping(false);
    world.insert(body, ColliderBuilder::cuboid(0.5, 0.5, 0.5).density(10.0))
}

/// A world of the ground and one dynamic box at height `y`.
fn world_with_box_at(y: f32) -> (PhysicsWorld, RigidBodyHandle) {
    let mut world = PhysicsWorld::default();
    ground(&mut world);
    let (body, _) = dynamic_box_at(&mut world, y);
    (world, body)
}

/// A positions-only bridge without friction (positions only, velocities untouched): the
/// mode the tests of reading, writing and rounding pin down.
fn bridge() -> RapierBridge {
    RapierBridge::with_settings(BridgeSettings {
        coupling: CouplingMode::PositionsOnly,
        collider_friction: false,
        ..BridgeSettings::default()
    })
    .expect("default settings are valid")
}

fn run(bridge: &mut RapierBridge, world: &mut PhysicsWorld) -> BridgeReport {
    bridge
        .stabilize(
            &mut world.bodies,
            &mut world.colliders,
            &world.impulse_joints,
            &world.multibody_joints,
            &world.integration_parameters,
        )
        .expect("the bridge call succeeds")
}

/// The tolerance the bridge states for the world it wrote.
fn stated_tolerance(report: &BridgeReport) -> f64 {
    report
        .stated_tolerance
        .expect("the world has dynamic bodies")
}

/// The exact deepest penetration of the world as Rapier holds it (f32
/// poses): the world read by a fresh bridge, measured by the brute-force
/// separating-axis oracle.
fn f32_world_depth(world: &PhysicsWorld) -> f64 {
    let mut reader = bridge();
    reader
        .sync(&world.bodies, &world.colliders)
        .expect("the world is read");
    dev_support::sat::sat_deepest(reader.scene()).0
}

/// The exact deepest penetration of the world as Rapier holds it (f32
/// poses) over the pairs with an awake dynamic body: what a call reads and
/// states its tolerance for (a pair of two sleeping bodies keeps Rapier's
/// depth).
fn f32_awake_depth(world: &PhysicsWorld) -> f64 {
    let mut reader = bridge();
    reader
        .sync(&world.bodies, &world.colliders)
        .expect("the world is read");
    let (scene, map) = (reader.scene(), reader.body_map());
    let awake = |i: usize| map.is_awake_dynamic(i, &world.bodies);
    dev_support::sat::pair_depths(scene, |a, b| dev_support::sat::sat_depth(scene, a, b))
        .into_iter()
        .filter(|((a, b), _)| awake(*a) || awake(*b))
        .fold(0.0, |deepest, (_, depth)| deepest.max(depth))
}

fn deepest_left(bridge: &RapierBridge) -> f64 {
    parry_penetration(bridge.scene(), 0.0)
        .expect("parry measures the scene")
        .deepest
}

#[test]
fn box_sunk_into_ground_is_lifted_by_its_depth_velocity_unchanged() {
    let (mut world, body) = world_with_box_at(0.5 - SINK_DEPTH);
    let mut bridge = bridge();
    let report = run(&mut bridge, &mut world);

    let rb = &world.bodies[body];
    let t = pose_to_f64(rb.position()).translation.vector;
    assert!((t.y - 0.5).abs() < F32_POSE_TOLERANCE, "y after = {}", t.y);
    assert!((t.x - 0.3).abs() < F32_POSE_TOLERANCE && (t.z + 0.2).abs() < F32_POSE_TOLERANCE);
    assert!(rb.rotation().angle_between(Rotation::IDENTITY) < 1e-6);
    assert_eq!(rb.linvel(), Vector::new(1.0, -2.0, 0.5));
    assert_eq!(rb.angvel(), Vector::new(0.1, 0.2, 0.3));
    assert_eq!(report.bodies_written, 1);
    assert!(report.sync.skipped.is_empty());
    assert!(
        report
            .stabilizer
            .expect("a dynamic body")
            .status
            .is_resolved()
    );
    assert!(report.write_back_round_off.translation < F32_POSE_TOLERANCE);
    assert!(deepest_left(&bridge) < DEPTH_LEFT_TOLERANCE);
}

#[test]
fn box_sunk_after_a_rapier_step_is_corrected_by_the_depth_left() {
    let (mut world, body) = world_with_box_at(0.5 - SINK_DEPTH);
    world.step();
    let before = pose_to_f64(world.bodies[body].position());
    let velocity_before = (world.bodies[body].linvel(), world.bodies[body].angvel());
    let mut bridge = bridge();
    let report = run(&mut bridge, &mut world);

    // The depth after Rapier's step, measured on the scene as read.
    let depth_read = report
        .stabilizer
        .as_ref()
        .expect("a dynamic body")
        .depth_before;
    assert!(
        depth_read > 0.01,
        "the step left the box sunk by {depth_read}"
    );
    let after = pose_to_f64(world.bodies[body].position());
    let lowest_before = lowest_world_y(&before);
    let lowest_after = lowest_world_y(&after);
    assert!(lowest_before < -0.01);
    assert!(
        lowest_after.abs() < DEPTH_LEFT_TOLERANCE,
        "lowest = {lowest_after}"
    );
    let velocity_after = (world.bodies[body].linvel(), world.bodies[body].angvel());
    assert_eq!(velocity_before, velocity_after);
    assert!(deepest_left(&bridge) < DEPTH_LEFT_TOLERANCE);
}

/// Lowest corner of the unit box (half extents 0.5) at `pose`.
fn lowest_world_y(pose: &Isometry3<f64>) -> f64 {
    let mut lowest = f64::INFINITY;
    for i in 0..8 {
        let corner = Point3::new(
            if i & 1 == 0 { -0.5 } else { 0.5 },
            if i & 2 == 0 { -0.5 } else { 0.5 },
            if i & 4 == 0 { -0.5 } else { 0.5 },
        );
        lowest = lowest.min((pose * corner).y);
    }
    lowest
}

/// Points of a box with half extents (0.4, 0.3, 0.2) centred at (0.5, 0, 0)
/// of the collider frame: the hull's centre of mass is off its frame origin.
fn off_centre_hull_points() -> Vec<Vector> {
    let mut points = Vec::new();
    for i in 0..8 {
        points.push(Vector::new(
            0.5 + if i & 1 == 0 { -0.4 } else { 0.4 },
            if i & 2 == 0 { -0.3 } else { 0.3 },
            if i & 4 == 0 { -0.2 } else { 0.2 },
        ));
    }
    points
}

#[test]
fn hull_with_collider_offset_is_read_and_written_in_the_right_frames() {
    let mut world = PhysicsWorld::default();
    ground(&mut world);
    let body = world.insert_body(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(1.0, 0.2, -0.5))
            .rotation(Vector::new(0.3, -0.2, 0.5)),
    );
    let offset = Pose::from_parts(
        Vector::new(0.1, -0.2, 0.3),
        Rotation::from_scaled_axis(Vector::new(-0.4, 0.1, 0.2)),
    );
    let hull = ColliderBuilder::convex_hull(&off_centre_hull_points())
        .expect("a solid hull")
        .position(offset);
    let collider = world.insert_collider(hull, Some(body));
    let mut bridge = bridge();
    bridge
        .sync(&world.bodies, &world.colliders)
        .expect("the world is read");

    // Read: the scene body's user pose is B P, its points those of Rapier.
    let index = bridge
        .body_map()
        .scene_index(collider)
        .expect("the hull is read");
    assert_eq!(bridge.body_map().scene_index_of_body(body), Some(index));
    let b_pose = pose_to_f64(world.bodies[body].position());
    let p_pose = pose_to_f64(&offset);
    let u_expected = b_pose * p_pose;
    let u_read = bridge.scene().bodies()[index].user_pose();
    assert!((u_read.translation.vector - u_expected.translation.vector).norm() < 1e-12);
    assert!(u_read.rotation.angle_to(&u_expected.rotation) < 1e-12);
    let depth_read = deepest_left(&bridge);
    assert!(
        depth_read > 0.05,
        "the hull starts in the ground ({depth_read})"
    );

    run(&mut bridge, &mut world);
    // Written: every hull point placed by Rapier's new body pose (f32) and
    // the collider offset is where the scene put it (f64).
    let b_written = pose_to_f64(world.bodies[body].position());
    let u_scene = bridge.scene().bodies()[index].user_pose();
    for p in off_centre_hull_points() {
        let p_collider = Point3::new(f64::from(p.x), f64::from(p.y), f64::from(p.z));
        let by_rapier = b_written * p_pose * p_collider;
        let by_scene = u_scene * p_collider;
        assert!((by_rapier - by_scene).norm() < F32_POSE_TOLERANCE);
        assert!(
            by_rapier.y > -DEPTH_LEFT_TOLERANCE,
            "point below ground: {by_rapier}"
        );
    }
    assert!(deepest_left(&bridge) < DEPTH_LEFT_TOLERANCE);
}

#[test]
fn unsupported_shape_and_sensor_colliders_are_skipped_and_counted() {
    let mut world = PhysicsWorld::default();
    ground(&mut world);
    // A rounded cylinder: a shape the library has no form of (balls are
    // read since issue 25).
    let odd_body = RigidBodyBuilder::dynamic().translation(Vector::new(3.0, 0.2, 0.0));
    let (_, odd) = world.insert(odd_body, ColliderBuilder::round_cylinder(0.3, 0.3, 0.05));
    let sensor = world.insert_collider(ColliderBuilder::cuboid(1.0, 1.0, 1.0).sensor(true), None);
    dynamic_box_at(&mut world, 0.5 - SINK_DEPTH);
    let mut bridge = bridge();
    let report = run(&mut bridge, &mut world);

    let reason_of = |handle| {
        report
            .skipped()
            .iter()
            .find(|s| s.collider == handle)
            .map(|s| s.reason.clone())
    };
    assert_eq!(report.skipped().len(), 2);
    assert_eq!(
        reason_of(odd),
        Some(SkipReason::Shape("RoundCylinder".into()))
    );
    assert_eq!(reason_of(sensor), Some(SkipReason::Sensor));
    assert_eq!(bridge.scene().len(), 2, "ground and the single box");
    assert_eq!(report.bodies_written, 1);
}

#[test]
fn kinematic_body_is_never_moved_the_dynamic_one_is() {
    let mut world = PhysicsWorld::default();
    let kinematic =
        RigidBodyBuilder::kinematic_position_based().translation(Vector::new(0.0, 0.0, 0.0));
    let (kinematic, _) = world.insert(kinematic, ColliderBuilder::cuboid(1.0, 0.25, 1.0));
    let (body, _) = dynamic_box_at(&mut world, 0.7);
    let kinematic_before = *world.bodies[kinematic].position();
    let body_before = *world.bodies[body].position();
    let mut bridge = bridge();
    let report = run(&mut bridge, &mut world);

    assert_eq!(*world.bodies[kinematic].position(), kinematic_before);
    assert_ne!(*world.bodies[body].position(), body_before);
    assert_eq!(report.bodies_written, 1);
    let dynamic_flags: Vec<bool> = bridge
        .body_map()
        .entries()
        .iter()
        .map(|e| e.is_dynamic())
        .collect();
    assert_eq!(dynamic_flags, vec![false, true]);
    assert!(deepest_left(&bridge) < DEPTH_LEFT_TOLERANCE);
}

#[test]
fn separated_world_is_not_written() {
    let (mut world, body) = world_with_box_at(0.75);
    let before = *world.bodies[body].position();
    let mut bridge = bridge();
    let report = run(&mut bridge, &mut world);

    assert_eq!(report.bodies_written, 0);
    assert_eq!(*world.bodies[body].position(), before);
}

#[test]
fn world_without_dynamic_bodies_is_read_and_left_alone() {
    let mut world = PhysicsWorld::default();
    ground(&mut world);
    world.insert_collider(ColliderBuilder::cuboid(1.0, 1.0, 1.0), None);
    let mut bridge = bridge();
    let report = run(&mut bridge, &mut world);

    assert!(report.stabilizer.is_none());
    assert_eq!(report.sync.scene_bodies, 2);
}

#[test]
fn blown_up_pose_is_a_typed_error_and_nothing_is_written() {
    let (mut world, body) = world_with_box_at(0.5 - SINK_DEPTH);
    let mut bridge = bridge();
    run(&mut bridge, &mut world);
    world.bodies[body].set_translation(Vector::new(f32::NAN, 0.0, 0.0), false);
    let result = bridge.stabilize(
        &mut world.bodies,
        &mut world.colliders,
        &world.impulse_joints,
        &world.multibody_joints,
        &world.integration_parameters,
    );

    assert!(result.is_err());
    assert!(world.bodies[body].translation().x.is_nan());
}

#[cfg(feature = "serde")]
#[test]
fn rapier_engine_states_read_back_with_their_body_counts() {
    use constraint_stabilization::io::scene_file::read_scene;
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/engine");
    for (file, bodies) in [
        ("rp01_pile_200.json", 205),
        ("rp03_heavy_on_stack_100x.json", 6),
        ("rp04_heavy_on_stack_1000x.json", 6),
        ("rp05_pyramid.json", 56),
        ("rp06_thrown_box.json", 8),
        ("rp07_jumble_midfall.json", 81),
    ] {
        let scene = read_scene(&dir.join(file)).expect("the file is a valid scene");
        assert_eq!(scene.len(), bodies, "{file}");
        let penetration = parry_penetration(&scene, 0.0).expect("parry measures it");
        assert!(
            penetration.penetrating_pairs > 0,
            "{file} is an engine state with contacts"
        );
    }
}
