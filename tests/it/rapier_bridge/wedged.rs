//! A body wedged by bodies held still (`rapier_bridge/wedged.rs`): an
//! awake ball appears between the ground and a sleeping plank, 1 cm into
//! each. Held still, the plank leaves the ball no way out (its problem is
//! infeasible), so the call releases the plank, lifts it, and resolves;
//! without held bodies nothing is released.

use constraint_stabilization::rapier_bridge::{BridgeSettings, RapierBridge};
use rapier3d::prelude::*;

use super::{f32_world_depth, stated_tolerance, worlds};

/// Half height of the plank (m).
const PLANK_HALF_HEIGHT: f32 = 0.02;

/// Two blocks of 10 cm on the ground and a plank on them, all asleep, and
/// a ball awake under the plank, 1 cm into the ground and 1 cm into the
/// plank. Returns the world and the plank.
fn ball_under_sleeping_plank() -> (PhysicsWorld, RigidBodyHandle) {
    let mut world = worlds::ground_world(5.0);
    let mut sleepers = Vec::new();
    for x in [-0.2f32, 0.2] {
        sleepers.push(worlds::box_at(
            &mut world,
            Vector::new(x, 0.0, 0.05),
            0.05,
            1.0,
        ));
    }
    let plank_z = 0.1 + PLANK_HALF_HEIGHT;
    let plank = RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 0.0, plank_z));
    let (plank, _) = world.insert(
        plank,
        ColliderBuilder::cuboid(0.3, 0.1, PLANK_HALF_HEIGHT).mass(1.0),
    );
    sleepers.push(plank);
    for handle in sleepers {
        world.bodies[handle].sleep();
    }
    // The gap under the plank is 10 cm; the ball is 12 cm across.
    let radius = 0.06f32;
    let ball = RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 0.0, radius - 0.01));
    world.insert(ball, ColliderBuilder::ball(radius).density(1000.0));
    (world, plank)
}

#[test]
fn a_ball_wedged_under_a_sleeping_plank_releases_it() {
    let (mut world, plank) = ball_under_sleeping_plank();
    let plank_z = world.bodies[plank].translation().z;
    let mut bridge =
        RapierBridge::with_settings(BridgeSettings::default()).expect("valid defaults");
    let report = bridge
        .stabilize_world(&mut world)
        .expect("the call succeeds");
    let stabilizer = report.stabilizer.as_ref().expect("an awake body");
    assert!(stabilizer.status.is_resolved(), "{:?}", stabilizer.status);
    assert!(report.bodies_released >= 1, "the plank was released");
    assert!(
        world.bodies[plank].translation().z > plank_z + 0.005,
        "the plank was lifted"
    );
    let depth = f32_world_depth(&world);
    assert!(depth <= stated_tolerance(&report), "depth {depth:e}");
}

/// The same ball under a plank that is awake: the call resolves without
/// releasing anything (nothing is held).
#[test]
fn without_held_bodies_nothing_is_released() {
    let (mut world, plank) = ball_under_sleeping_plank();
    world.bodies[plank].wake_up(true);
    let mut bridge =
        RapierBridge::with_settings(BridgeSettings::default()).expect("valid defaults");
    let report = bridge
        .stabilize_world(&mut world)
        .expect("the call succeeds");
    assert!(
        report
            .stabilizer
            .as_ref()
            .is_some_and(|r| r.status.is_resolved())
    );
    assert_eq!(report.bodies_released, 0);
}
