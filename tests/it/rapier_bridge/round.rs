//! Round and curved colliders (issue 25): balls, capsules (along `y`, as
//! Rapier builds them), rounded cuboids and convex polyhedra, cylinders and
//! cones are read, also as parts of a compound body, corrected, and
//! written back. The depth left is measured on Rapier's own colliders and
//! f32 poses by parry's contact query (f32, what Rapier itself uses), and
//! on the world read again by the support-function oracle.

use rapier3d::parry::query;
use rapier3d::prelude::*;

use super::{bridge, f32_world_depth, ground, run, stated_tolerance};

/// Depth parry (f32) may still see after a call: the tolerance plus f32
/// rounding of poses near 1 and parry's own f32 contact accuracy.
const PARRY_F32_DEPTH_LEFT: f64 = 1e-5;

/// A collider's world pose `B P` from its body's pose as the bridge wrote
/// it (Rapier refreshes `Collider::position` only at its next step).
fn posed(world: &PhysicsWorld, collider: &Collider) -> Pose {
    match collider.parent() {
        Some(parent) => {
            let offset = collider.position_wrt_parent().copied().unwrap_or_default();
            *world.bodies[parent].position() * offset
        }
        None => *collider.position(),
    }
}

/// The deepest overlap of any two colliders of `world` by parry.
fn parry_world_depth(world: &PhysicsWorld) -> f64 {
    let all: Vec<(ColliderHandle, &Collider)> = world.colliders.iter().collect();
    let mut deepest: f64 = 0.0;
    for (i, (_, a)) in all.iter().enumerate() {
        for (_, b) in &all[i + 1..] {
            if a.parent().is_some() && a.parent() == b.parent() {
                continue;
            }
            let (pa, pb) = (posed(world, a), posed(world, b));
            let contact = query::contact(&pa, a.shape(), &pb, b.shape(), 0.0);
            if let Ok(Some(contact)) = contact {
                deepest = deepest.max(f64::from(-contact.dist));
            }
        }
    }
    deepest
}

fn dynamic(world: &mut PhysicsWorld, at: Vector, collider: ColliderBuilder) -> RigidBodyHandle {
    let body = RigidBodyBuilder::dynamic()
        .translation(at)
        .rotation(Vector::new(0.0, 0.3, 0.0))
        .sleeping(false);
    world.insert(body, collider).0
}

#[test]
fn round_and_curved_colliders_are_read_and_lifted() {
    let mut world = PhysicsWorld::default();
    ground(&mut world);
    let sink = 0.04;
    dynamic(
        &mut world,
        Vector::new(-2.0, 0.3 - sink, 0.0),
        ColliderBuilder::ball(0.3),
    );
    // A capsule along y lying on its side (turned about z), and one standing.
    let lying = RigidBodyBuilder::dynamic()
        .translation(Vector::new(-1.0, 0.2 - sink, 0.0))
        .rotation(Vector::new(0.0, 0.0, std::f32::consts::FRAC_PI_2))
        .sleeping(false);
    world.insert(lying, ColliderBuilder::capsule_y(0.4, 0.2));
    dynamic(
        &mut world,
        Vector::new(0.0, 0.6 - sink, 0.0),
        ColliderBuilder::capsule_y(0.4, 0.2),
    );
    dynamic(
        &mut world,
        Vector::new(1.0, 0.35 - sink, 0.0),
        ColliderBuilder::round_cuboid(0.3, 0.25, 0.2, 0.1),
    );
    let hull = [
        Vector::new(-0.3, -0.2, -0.3),
        Vector::new(0.3, -0.2, -0.3),
        Vector::new(0.0, -0.2, 0.3),
        Vector::new(0.0, 0.3, 0.0),
    ];
    dynamic(
        &mut world,
        Vector::new(2.0, 0.25 - sink, 0.0),
        ColliderBuilder::round_convex_hull(&hull, 0.05).expect("a hull"),
    );
    dynamic(
        &mut world,
        Vector::new(0.0, 0.3 - sink, 1.5),
        ColliderBuilder::cylinder(0.3, 0.4),
    );
    dynamic(
        &mut world,
        Vector::new(1.5, 0.3 - sink, 1.5),
        ColliderBuilder::cone(0.3, 0.4),
    );
    // A compound: a capsule bar with a ball at each end, the balls sunk.
    let dumbbell = world.insert_body(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(0.0, 0.25 - sink, -1.5))
            .sleeping(false),
    );
    world.insert_collider(
        ColliderBuilder::capsule_x(0.5, 0.1).translation(Vector::new(0.0, 0.1, 0.0)),
        Some(dumbbell),
    );
    for x in [-0.6, 0.6] {
        world.insert_collider(
            ColliderBuilder::ball(0.25).translation(Vector::new(x, 0.0, 0.0)),
            Some(dumbbell),
        );
    }
    let before = parry_world_depth(&world);
    assert!(before > 0.03, "sunk by {before}");
    let mut bridge = bridge();
    let report = run(&mut bridge, &mut world);
    assert!(
        report.skipped().is_empty(),
        "skipped: {:?}",
        report.skipped()
    );
    assert_eq!(
        bridge.scene().len(),
        9,
        "ground, seven bodies and the compound"
    );
    let tolerance = stated_tolerance(&report);
    let parry_after = parry_world_depth(&world);
    let oracle_after = f32_world_depth(&world);
    println!(
        "depth {before:e} -> parry {parry_after:e}, oracle {oracle_after:e}, tolerance {tolerance:e}"
    );
    assert!(
        parry_after <= tolerance + PARRY_F32_DEPTH_LEFT,
        "parry {parry_after:e}"
    );
    // The read world's cylinders and cones are their circumscribed
    // polyhedra: the oracle on the true shapes sees at most their depth.
    assert!(
        oracle_after <= tolerance + PARRY_F32_DEPTH_LEFT,
        "oracle {oracle_after:e}"
    );
}
