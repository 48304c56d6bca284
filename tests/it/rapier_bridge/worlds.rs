//! The z-up Rapier worlds of the rest, stack, struck and coupling tests: a
//! fixed ground slab whose top face is at z = 0, and dynamic boxes on it.

use rapier3d::prelude::*;

/// Thickness of the ground slab under z = 0 (m).
const GROUND_THICKNESS: f32 = 1.0;

/// A world with gravity along -z and a fixed ground slab of half width
/// `half_width` (m) whose top face is at z = 0.
pub(super) fn ground_world(half_width: f32) -> PhysicsWorld {
    let mut world = PhysicsWorld {
        gravity: Vector::new(0.0, 0.0, -9.81),
        ..PhysicsWorld::default()
    };
    let ground = world.insert_body(RigidBodyBuilder::fixed());
    let half_thickness = GROUND_THICKNESS / 2.0;
    let floor = ColliderBuilder::cuboid(half_width, half_width, half_thickness)
        .translation(Vector::new(0.0, 0.0, -half_thickness));
    world.insert_collider(floor, Some(ground));
    world
}

/// A dynamic box of half extent `half` (m) and mass `mass` (kg), its centre
/// at `at`.
pub(super) fn box_at(
    world: &mut PhysicsWorld,
    at: Vector,
    half: f32,
    mass: f32,
) -> RigidBodyHandle {
    let body = RigidBodyBuilder::dynamic().translation(at);
    world
        .insert(body, ColliderBuilder::cuboid(half, half, half).mass(mass))
        .0
}

/// Four 1 kg boxes of 20 cm in an aligned column, 1 mm apart, under a box
/// of `ratio` kg, on a 4 m ground: the `aligned_heavy_stack_world` of the
/// examples (`examples/common/rapier_scenes.rs`). Handles bottom to top.
pub(super) fn aligned_heavy_stack(ratio: f32) -> (PhysicsWorld, Vec<RigidBodyHandle>) {
    let mut world = ground_world(2.0);
    let handles = (0..5)
        .map(|level| {
            let mass = if level == 4 { ratio } else { 1.0 };
            let z = 0.1 + level as f32 * 0.201;
            box_at(&mut world, Vector::new(0.0, 0.0, z), 0.1, mass)
        })
        .collect();
    (world, handles)
}
