//! Rapier scenes of round shapes with joints (issue 25), shared by the
//! examples (`with_and_without`): a ragdoll-like figure of capsules and a
//! ball on Rapier impulse joints, dropped on the ground. Rapier's defaults
//! (60 Hz, contacts between jointed bodies enabled), z up, gravity -9.81,
//! SI units, density 1000 kg/m^3.

#![allow(dead_code)]

use rapier3d::prelude::*;

/// Density of every part (kg/m^3).
pub const DENSITY: f32 = 1000.0;

/// Height of the figure's axis above the ground when dropped (m).
pub const DROP_HEIGHT: f32 = 0.6;

/// An empty world with gravity along -z and Rapier's default parameters.
fn round_world() -> PhysicsWorld {
    PhysicsWorld {
        gravity: Vector::new(0.0, 0.0, -9.81),
        ..PhysicsWorld::default()
    }
}

/// A dynamic body at `at` with one collider.
fn limb(world: &mut PhysicsWorld, collider: ColliderBuilder, at: Vector) -> RigidBodyHandle {
    let body = world.insert_body(RigidBodyBuilder::dynamic().translation(at));
    world.insert_collider(collider.density(DENSITY), Some(body));
    body
}

/// The local anchors on `a` and `b` of the world point `at` (the bodies
/// are not rotated yet).
fn anchors(
    world: &PhysicsWorld,
    a: RigidBodyHandle,
    b: RigidBodyHandle,
    at: Vector,
) -> [Vector; 2] {
    [
        at - world.bodies[a].translation(),
        at - world.bodies[b].translation(),
    ]
}

/// A ragdoll-like figure lying along x, `DROP_HEIGHT` above the ground, to
/// be dropped: a capsule torso (a segment of 30 cm, radius 10 cm), a ball
/// head (radius 9 cm), arms and legs of two capsules each along x (upper
/// arm radius 4 cm, forearm 3.5 cm, thigh 5.5 cm, shin 4.5 cm); spherical
/// joints at the neck, shoulders and hips, hinges about y limited to
/// [-0.05, 2.3] rad at the elbows and knees, each joint's anchor in the
/// 2-4 cm gap between its two parts (no part touches another at the start).
pub fn capsule_ragdoll_world() -> PhysicsWorld {
    let mut world = round_world();
    let floor = ColliderBuilder::cuboid(20.0, 20.0, 0.5).translation(Vector::new(0.0, 0.0, -0.5));
    let ground = world.insert_body(RigidBodyBuilder::fixed());
    world.insert_collider(floor, Some(ground));
    let z = DROP_HEIGHT;
    let at = |x: f32, y: f32| Vector::new(x, y, z);
    let torso = limb(
        &mut world,
        ColliderBuilder::capsule_x(0.15, 0.1),
        at(0.0, 0.0),
    );
    let head = limb(&mut world, ColliderBuilder::ball(0.09), at(0.38, 0.0));
    let ball = |world: &mut PhysicsWorld, a, b, joint_at: Vector| {
        let [anchor_a, anchor_b] = anchors(world, a, b, joint_at);
        let joint = SphericalJointBuilder::new()
            .local_anchor1(anchor_a)
            .local_anchor2(anchor_b);
        world.insert_impulse_joint(a, b, joint);
    };
    let hinge = |world: &mut PhysicsWorld, a, b, joint_at: Vector| {
        let [anchor_a, anchor_b] = anchors(world, a, b, joint_at);
        let joint = RevoluteJointBuilder::new(Vector::Y)
            .local_anchor1(anchor_a)
            .local_anchor2(anchor_b)
            .limits([-0.05, 2.3]);
        world.insert_impulse_joint(a, b, joint);
    };
    ball(&mut world, torso, head, at(0.27, 0.0));
    for side in [-1.0_f32, 1.0] {
        // Arm: upper arm and forearm along -x from the shoulder, beside
        // the torso.
        let upper = limb(
            &mut world,
            ColliderBuilder::capsule_x(0.08, 0.04),
            at(0.1, side * 0.19),
        );
        let fore = limb(
            &mut world,
            ColliderBuilder::capsule_x(0.075, 0.035),
            at(-0.16, side * 0.19),
        );
        ball(&mut world, torso, upper, at(0.23, side * 0.15));
        hinge(&mut world, upper, fore, at(-0.035, side * 0.19));
        // Leg: thigh and shin along -x from the hip.
        let thigh = limb(
            &mut world,
            ColliderBuilder::capsule_x(0.12, 0.055),
            at(-0.45, side * 0.07),
        );
        let shin = limb(
            &mut world,
            ColliderBuilder::capsule_x(0.12, 0.045),
            at(-0.81, side * 0.07),
        );
        ball(&mut world, torso, thigh, at(-0.262, side * 0.07));
        hinge(&mut world, thigh, shin, at(-0.635, side * 0.07));
    }
    world
}
