//! Bodies at rest under the bridge: sleeping bodies are held still and
//! never written, a body that an awake newcomer penetrates is woken and
//! corrected, a box settled on the ground is a fixed point (nothing written
//! once it sleeps), the world is consistent when the call returns (a scene
//! query sees the corrected collider), and a compound of two densities is
//! corrected about Rapier's centre of mass.

use constraint_stabilization::rapier_bridge::{BridgeSettings, RapierBridge, pose_to_f64};
use nalgebra::{Point3, Vector3};
use rapier3d::prelude::*;

use super::{f32_world_depth, stated_tolerance, worlds};

/// Steps within which a box dropped 1 cm onto the ground falls asleep
/// under Rapier alone (0.5 s of Rapier's time until sleep, plus landing).
const SLEEP_STEPS: usize = 120;

/// f32 rounding of a world point near 1 (a few ulps of 2^-23).
const F32_POINT_TOLERANCE: f64 = 1e-6;

/// The ground of these tests: a 10 m slab.
fn ground() -> PhysicsWorld {
    worlds::ground_world(5.0)
}

/// A 20 cm box of `mass` kg with its centre at `(x, 0, z)`.
fn box_at(world: &mut PhysicsWorld, x: f32, z: f32, mass: f32) -> RigidBodyHandle {
    worlds::box_at(world, Vector::new(x, 0.0, z), 0.1, mass)
}

fn default_bridge() -> RapierBridge {
    RapierBridge::with_settings(BridgeSettings::default()).expect("default settings are valid")
}

/// Steps the world with a bridge call after each step until `body`
/// sleeps; returns the step at which it fell asleep.
fn settle(world: &mut PhysicsWorld, bridge: &mut RapierBridge, body: RigidBodyHandle) -> usize {
    for step in 1..=SLEEP_STEPS {
        world.step();
        bridge.stabilize_world(world).expect("the call succeeds");
        if world.bodies[body].is_sleeping() {
            return step;
        }
    }
    panic!("the box did not fall asleep within {SLEEP_STEPS} steps");
}

/// A box dropped 1 cm settles and falls asleep under the bridge about when
/// it does under Rapier alone; from then on no call writes a body and the
/// box stays asleep, its pose unchanged bit for bit.
#[test]
fn a_settled_box_on_the_ground_is_a_fixed_point() {
    let sleeps_alone = {
        let mut world = ground();
        let body = box_at(&mut world, 0.0, 0.11, 8.0);
        (1..=SLEEP_STEPS)
            .find(|_| {
                world.step();
                world.bodies[body].is_sleeping()
            })
            .expect("Rapier alone puts the box to sleep")
    };
    let mut world = ground();
    let body = box_at(&mut world, 0.0, 0.11, 8.0);
    let mut bridge = default_bridge();
    let sleeps = settle(&mut world, &mut bridge, body);
    assert!(
        sleeps as f64 <= 1.2 * sleeps_alone as f64,
        "asleep at step {sleeps} under the bridge, {sleeps_alone} alone"
    );
    let pose = *world.bodies[body].position();
    for _ in 0..30 {
        world.step();
        let report = bridge.stabilize_world(&mut world).expect("succeeds");
        assert_eq!(report.bodies_written, 0);
        assert_eq!(report.bodies_left_asleep, 1);
        assert!(world.bodies[body].is_sleeping());
        assert_eq!(*world.bodies[body].position(), pose);
    }
}

/// A sleeping box pushed 1 cm into the ground without waking it is held
/// still: not written, left asleep.
#[test]
fn a_sleeping_body_is_never_written() {
    let mut world = ground();
    let body = box_at(&mut world, 0.0, 0.09, 8.0);
    world.bodies[body].sleep();
    let mut bridge = default_bridge();
    let report = bridge.stabilize_world(&mut world).expect("succeeds");
    assert_eq!(report.bodies_written, 0);
    assert_eq!(report.bodies_left_asleep, 1);
    assert!(world.bodies[body].is_sleeping());
    assert_eq!(world.bodies[body].translation().z, 0.09);
}

/// A heavy box dropped into a sleeping light one: Rapier's step wakes the
/// light box, and the call corrects both, the exact depth of the world
/// within the call's tolerance.
#[test]
fn a_body_woken_by_a_penetrating_newcomer_is_corrected() {
    let mut world = ground();
    let light = box_at(&mut world, 0.0, 0.1, 1.0);
    let mut bridge = default_bridge();
    settle(&mut world, &mut bridge, light);
    let light_before = *world.bodies[light].position();
    // The newcomer overlaps the light box by 2 cm.
    box_at(&mut world, 0.05, 0.28, 100.0);
    world.step();
    assert!(!world.bodies[light].is_sleeping(), "Rapier wakes the box");
    let report = bridge.stabilize_world(&mut world).expect("succeeds");
    assert_eq!(report.bodies_left_asleep, 0);
    assert!(report.bodies_written >= 1);
    let depth = f32_world_depth(&world);
    assert!(depth <= stated_tolerance(&report));
    assert_ne!(*world.bodies[light].position(), light_before);
}

/// After the call the colliders are where the written bodies put them: a
/// ray cast down onto a box lifted out of the ground hits its corrected
/// top face, and the collider's pose is its body's.
#[test]
fn a_scene_query_after_the_call_sees_the_corrected_collider() {
    let mut world = ground();
    let body = box_at(&mut world, 0.0, 0.05, 8.0);
    let mut bridge = default_bridge();
    // One step puts the colliders in the broad phase; Rapier pushes the
    // box out over several steps, so it is still 5 cm deep or so.
    world.step();
    bridge.stabilize_world(&mut world).expect("succeeds");
    let top = f64::from(world.bodies[body].translation().z) + 0.1;
    assert!(top > 0.2 - 1e-3, "the box is lifted out of the ground");
    let collider = world.bodies[body].colliders()[0];
    let written = pose_to_f64(world.bodies[body].position());
    let seen = pose_to_f64(world.colliders[collider].position());
    assert!((written.translation.vector - seen.translation.vector).norm() <= F32_POINT_TOLERANCE);
    let ray = Ray::new(Vector::new(0.0, 0.0, 1.0), Vector::new(0.0, 0.0, -1.0));
    let (hit, distance) = world
        .cast_ray(&ray, 2.0, true, QueryFilter::default())
        .expect("the ray hits the box");
    assert_eq!(hit, collider);
    assert!((1.0 - f64::from(distance) - top).abs() <= F32_POINT_TOLERANCE);
}

/// A bar of two cubes, one nine times denser than the other, sunk into
/// the ground: the scene body's centre of mass, mass and inertia are
/// Rapier's (not a uniform density's), and the write-back leaves no
/// penetration.
#[test]
fn a_compound_of_two_densities_is_corrected_about_rapiers_centre_of_mass() {
    let mut world = ground();
    let rotation = Rotation::from_rotation_z(0.4);
    let body = world.insert_body(
        RigidBodyBuilder::dynamic().pose(Pose::from_parts(Vector::new(0.3, 0.2, 0.08), rotation)),
    );
    for (x, density) in [(-0.1, 100.0), (0.1, 900.0)] {
        let cube = ColliderBuilder::cuboid(0.1, 0.1, 0.1)
            .translation(Vector::new(x, 0.0, 0.0))
            .density(density);
        world.insert_collider(cube, Some(body));
    }
    let mut bridge = default_bridge();
    bridge
        .sync(&world.bodies, &world.colliders)
        .expect("the world is read");
    let index = bridge
        .body_map()
        .scene_index_of_body(body)
        .expect("the compound is read");
    let read = &bridge.scene().bodies()[index];
    let com_rapier = world.bodies[body].center_of_mass();
    let com_rapier = Point3::new(com_rapier.x, com_rapier.y, com_rapier.z).cast::<f64>();
    // Uniform density would put the centre on the body origin; Rapier's is
    // 8 cm towards the dense cube.
    assert!((read.com_world() - com_rapier).norm() <= F32_POINT_TOLERANCE);
    let mass = read.mass().expect("dynamic");
    assert!((mass.mass - f64::from(world.bodies[body].mass())).abs() <= 1e-4);
    let principal = world.bodies[body]
        .mass_properties()
        .local_mprops
        .principal_inertia();
    let trace: f64 = mass.inertia_body.trace();
    let rapier_trace = f64::from(principal.x + principal.y + principal.z);
    assert!((trace - rapier_trace).abs() <= 1e-5 * rapier_trace);
    let offset = read.com_offset();
    assert!((offset - Vector3::new(0.08, 0.0, 0.0)).norm() <= F32_POINT_TOLERANCE);
    let report = bridge.stabilize_world(&mut world).expect("succeeds");
    assert_eq!(report.bodies_written, 1);
    let depth = f32_world_depth(&world);
    assert!(depth <= stated_tolerance(&report));
}
