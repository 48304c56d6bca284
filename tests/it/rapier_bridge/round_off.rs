//! f32 round-off of the write-back: far from the origin, where an f32 ulp
//! of a coordinate is larger than the stabilizer's default tolerance, the
//! bridge raises its lengths ([`constraint_stabilization::rapier_bridge::round_off`])
//! so that the f32 world after a call is within the tolerance it states.

use constraint_stabilization::rapier_bridge::round_off::{
    F32_UNIT_ROUND_OFF, TOLERANCE_PER_ROUND_OFF,
};
use rapier3d::prelude::*;

use super::{bridge, f32_world_depth, run, stated_tolerance};

/// Where the scene sits: an f32 ulp there is 2^-14 ≈ 6.1e-5 (positions in
/// [256, 512)), sixty times the default tolerance of a unit box (8.7e-7).
const FAR: f32 = 300.0;

/// Largest distance of a unit box's vertex from its body origin
/// (`sqrt(3) / 2`): the lever of its rotation round-off.
const UNIT_BOX_LEVER: f64 = 0.866_025_403_784_438_6;

/// A ground slab at `(FAR, 0, FAR)` and unit boxes sunk into it, tilted, on
/// a 3 x 3 grid, with one box resting on another (sunk into it too).
fn far_world() -> PhysicsWorld {
    let mut world = PhysicsWorld::default();
    let ground =
        world.insert_body(RigidBodyBuilder::fixed().translation(Vector::new(FAR, -0.5, FAR)));
    world.insert_collider(ColliderBuilder::cuboid(8.0, 0.5, 8.0), Some(ground));
    for k in 0..9 {
        let (i, j) = ((k % 3) as f32, (k / 3) as f32);
        let body = RigidBodyBuilder::dynamic()
            .translation(Vector::new(FAR + 2.0 * i - 2.0, 0.47, FAR + 2.0 * j - 2.0))
            .rotation(Vector::new(0.01 * i, 0.3 * j, -0.01 * j));
        world.insert(body, ColliderBuilder::cuboid(0.5, 0.5, 0.5));
    }
    let top = RigidBodyBuilder::dynamic().translation(Vector::new(FAR, 1.45, FAR));
    world.insert(top, ColliderBuilder::cuboid(0.5, 0.5, 0.5));
    world
}

#[test]
fn far_from_the_origin_the_f32_world_is_within_the_stated_tolerance() {
    let mut world = far_world();
    let depth_before = f32_world_depth(&world);
    let report = run(&mut bridge(), &mut world);
    let tolerance = stated_tolerance(&report);
    let delta = report.round_off_bound;

    // The bound: an f32 ulp of the largest body coordinate (about 300 *
    // sqrt(2) from the origin) and of a rotation at the box's lever.
    assert!(delta >= F32_UNIT_ROUND_OFF * f64::from(FAR) * 2f64.sqrt());
    assert!(tolerance >= TOLERANCE_PER_ROUND_OFF * delta);
    // The rounding measured on the written poses is within the bound.
    let measured = report.write_back_round_off;
    assert!(measured.translation + measured.rotation * UNIT_BOX_LEVER <= delta);
    assert_eq!(report.bodies_written, 10);

    let depth = f32_world_depth(&world);
    println!(
        "depth before {depth_before:e}, after in f32 {depth:e}, tolerance {tolerance:e}, \
         delta {delta:e}, measured rounding {:e} + {:e} rad",
        measured.translation, measured.rotation
    );
    assert!(depth_before > 0.02);
    assert!(depth <= tolerance, "depth {depth:e} > {tolerance:e}");
    let bound = report.written_depth_bound().expect("dynamic bodies");
    assert!(
        depth <= bound && bound <= 1.25 * tolerance,
        "bound {bound:e}"
    );
}

/// The call's tolerance is the larger of the stabilizer's own (1e-6 of
/// the smallest body) and the rule's `8 delta`; for a unit box at the
/// origin the rotation term of `delta` (`4 u` at lever 0.87) already makes
/// the rule's the larger, about twice the default.
#[test]
fn call_tolerance_is_the_larger_of_the_default_and_the_rule() {
    let mut world = PhysicsWorld::default();
    super::ground(&mut world);
    let body = RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 0.45, 0.0));
    world.insert(body, ColliderBuilder::cuboid(0.5, 0.5, 0.5));
    let report = run(&mut bridge(), &mut world);
    let stabilizer = report.stabilizer.as_ref().expect("a dynamic body");
    let default = 1e-6 * stabilizer.scale;
    let rule = TOLERANCE_PER_ROUND_OFF * report.round_off_bound;
    let stated = stated_tolerance(&report);
    assert_eq!(stated, default.max(rule));
    assert!(
        rule > default && rule < 3.0 * default,
        "{rule:e} vs {default:e}"
    );
    assert!(f32_world_depth(&world) <= stated);
}

/// A body far from the origin and from every other body (a projectile)
/// does not raise the tolerance of a call whose contacts are near the
/// origin: its rounding cannot change any depth, and it is not written.
#[test]
fn a_lone_far_body_does_not_raise_the_tolerance() {
    let near_only = || {
        let mut world = PhysicsWorld::default();
        super::ground(&mut world);
        let body = RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 0.45, 0.0));
        world.insert(body, ColliderBuilder::cuboid(0.5, 0.5, 0.5));
        world
    };
    let mut world = near_only();
    let alone = run(&mut bridge(), &mut world);

    let mut world = near_only();
    let far = RigidBodyBuilder::dynamic().translation(Vector::new(350.0, 20.0, 0.0));
    world.insert(far, ColliderBuilder::cuboid(0.1, 0.1, 0.1));
    let with_far = run(&mut bridge(), &mut world);

    assert_eq!(stated_tolerance(&with_far), stated_tolerance(&alone));
    assert_eq!(with_far.round_off_bound, alone.round_off_bound);
    assert_eq!(with_far.bodies_written, 1);
    assert!(f32_world_depth(&world) <= stated_tolerance(&with_far));
    // Without the restriction the far body's rounding (an f32 ulp at 350 m,
    // 3e-5 m) would have raised the tolerance about 30 times.
    let far_delta = F32_UNIT_ROUND_OFF * 350.0;
    assert!(TOLERANCE_PER_ROUND_OFF * far_delta > 20.0 * stated_tolerance(&alone));
}
