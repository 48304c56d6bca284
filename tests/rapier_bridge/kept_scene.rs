//! The scene kept across calls: bodies added, removed and changed between
//! steps without a rebuild (shapes and warm starts of the others kept), the
//! handle map both ways, and the answer of a kept bridge equal to a fresh
//! bridge's on the same world; kinematic bodies read as fixed.

use std::sync::Arc;

use constraint_stabilization::rapier_bridge::pose_to_f64;
use rapier3d::prelude::*;

use super::{
    SINK_DEPTH, bridge, dynamic_box_at, f32_world_depth, ground, run, stated_tolerance,
    world_with_box_at,
};

/// Largest distance (length, or radians) between the poses written by a
/// kept bridge and by a fresh one on the same world. Both write f32 poses
/// rounded from the same f64 answer; only the f64 renormalization of the
/// read quaternions differs in the last bits (measured: 2.7e-20).
const KEPT_VS_FRESH_TOLERANCE: f64 = 1e-12;

/// Bodies kept in the loop: the oldest is removed when there are more.
const LIVE_BOXES: usize = 3;

#[test]
fn scene_is_kept_across_calls_appended_to_and_removed_from() {
    let (mut world, first) = world_with_box_at(0.5 - SINK_DEPTH);
    let mut bridge = bridge();
    let report = run(&mut bridge, &mut world);
    assert_eq!((report.sync.appended, report.sync.removed), (2, 0));
    let shape_before = bridge.scene().bodies()[1].polyhedron().clone();

    world.step();
    let report = run(&mut bridge, &mut world);
    assert_eq!((report.sync.appended, report.sync.removed), (0, 0));
    assert!(
        Arc::ptr_eq(&shape_before, bridge.scene().bodies()[1].polyhedron()),
        "the shape is kept, not rebuilt"
    );

    let body = RigidBodyBuilder::dynamic().translation(Vector::new(3.0, 0.45, 0.0));
    let (added, _) = world.insert(body, ColliderBuilder::cuboid(0.5, 0.5, 0.5));
    let report = run(&mut bridge, &mut world);
    assert_eq!((report.sync.appended, report.sync.removed), (1, 0));
    assert_eq!(bridge.body_map().scene_index_of_body(added), Some(2));
    let added_shape = bridge.scene().bodies()[2].polyhedron().clone();

    world.remove_body(first);
    let report = run(&mut bridge, &mut world);
    assert_eq!((report.sync.appended, report.sync.removed), (0, 1));
    let tolerance = stated_tolerance(&report);
    assert_eq!(bridge.scene().len(), 2);
    assert_eq!(bridge.body_map().scene_index_of_body(added), Some(1));
    assert_eq!(bridge.body_map().body_of(1), Some(added));
    assert!(
        Arc::ptr_eq(&added_shape, bridge.scene().bodies()[1].polyhedron()),
        "the body left is moved down, not rebuilt"
    );
    assert!(f32_world_depth(&world) <= tolerance);
}

/// A changed collider (new shape) is removed and appended again; the
/// others keep their shapes.
#[test]
fn changed_collider_is_replaced_the_others_kept() {
    let mut world = PhysicsWorld::default();
    let ground_collider = ground(&mut world);
    let (_, changed) = dynamic_box_at(&mut world, 0.5 - SINK_DEPTH);
    let mut bridge = bridge();
    run(&mut bridge, &mut world);
    let ground_shape = bridge.scene().bodies()[0].polyhedron().clone();

    world.colliders[changed].set_shape(SharedShape::cuboid(0.5, 0.6, 0.5));
    let report = run(&mut bridge, &mut world);
    assert_eq!((report.sync.appended, report.sync.removed), (1, 1));
    assert_eq!(bridge.body_map().scene_index(ground_collider), Some(0));
    assert_eq!(bridge.body_map().scene_index(changed), Some(1));
    assert!(Arc::ptr_eq(
        &ground_shape,
        bridge.scene().bodies()[0].polyhedron()
    ));
    assert!(f32_world_depth(&world) <= stated_tolerance(&report));
}

/// Where the `k`-th box of the loop enters: sunk, tilted, on a grid, some
/// of them on top of an earlier one.
fn loop_box(k: usize) -> RigidBodyBuilder {
    let x = (k % 4) as f32 * 1.6 - 2.4;
    let y = if k % 3 == 2 { 1.45 } else { 0.5 - SINK_DEPTH };
    RigidBodyBuilder::dynamic()
        .translation(Vector::new(x, y, 0.1 * k as f32))
        .rotation(Vector::new(0.02 * k as f32, 0.0, -0.01 * k as f32))
}

/// Twelve steps: each adds a box (sunk into the ground or into a box)
/// and, above three boxes, removes the oldest; a Rapier step and a bridge
/// call follow. A kept bridge writes the same poses as a fresh bridge on
/// a copy of the same world, and never rebuilds: every call removes and
/// appends exactly what changed, and the map stays a bijection.
#[test]
fn bodies_added_and_removed_in_a_loop_match_a_fresh_bridge() {
    let mut world = PhysicsWorld::default();
    ground(&mut world);
    let mut kept = bridge();
    let mut live = std::collections::VecDeque::new();
    let mut largest_difference: f64 = 0.0;
    for k in 0..12 {
        let (body, _) = world.insert(loop_box(k), ColliderBuilder::cuboid(0.5, 0.5, 0.5));
        live.push_back(body);
        let removed = live.len() > LIVE_BOXES;
        if removed {
            let oldest = live.pop_front().expect("more than three boxes live");
            world.remove_body(oldest);
        }
        world.step();

        let mut fresh_bodies = world.bodies.clone();
        bridge()
            .stabilize(
                &mut fresh_bodies,
                &world.colliders,
                &world.integration_parameters,
            )
            .expect("the fresh call succeeds");
        let report = run(&mut kept, &mut world);

        let new_colliders = if k == 0 { 2 } else { 1 };
        assert_eq!(report.sync.appended, new_colliders, "step {k}");
        assert_eq!(report.sync.removed, usize::from(removed), "step {k}");
        assert_eq!(kept.scene().len(), world.colliders.len(), "step {k}");
        for index in 0..kept.scene().len() {
            let collider = kept.body_map().collider_of(index).expect("mapped");
            assert_eq!(kept.body_map().scene_index(collider), Some(index));
        }
        for &body in &live {
            let a = pose_to_f64(world.bodies[body].position());
            let b = pose_to_f64(fresh_bodies[body].position());
            let difference = (a.translation.vector - b.translation.vector)
                .norm()
                .max(a.rotation.angle_to(&b.rotation));
            largest_difference = largest_difference.max(difference);
        }
        let tolerance = stated_tolerance(&report);
        let depth = f32_world_depth(&world);
        assert!(
            depth <= tolerance,
            "step {k}: depth {depth:e} > {tolerance:e}"
        );
    }
    println!("largest kept-vs-fresh pose difference: {largest_difference:e}");
    assert!(largest_difference <= KEPT_VS_FRESH_TOLERANCE);
}

/// Kinematic bodies, position- or velocity-based, are read as fixed: they
/// are never written, even when a dynamic box is sunk into them and the
/// kinematic body moved between calls; the dynamic box is pushed out.
#[test]
fn kinematic_bodies_are_fixed_even_when_they_move_into_a_box() {
    let mut world = PhysicsWorld::default();
    let platform = RigidBodyBuilder::kinematic_velocity_based()
        .translation(Vector::new(0.3, -0.25, -0.2))
        .linvel(Vector::new(0.0, 3.0, 0.0));
    let (platform, _) = world.insert(platform, ColliderBuilder::cuboid(2.0, 0.25, 2.0));
    let (body, _) = dynamic_box_at(&mut world, 0.5);
    let mut bridge = bridge();
    for step in 0..3 {
        world.step();
        let platform_before = *world.bodies[platform].position();
        let body_before = *world.bodies[body].position();
        let report = run(&mut bridge, &mut world);
        assert_eq!(
            *world.bodies[platform].position(),
            platform_before,
            "step {step}"
        );
        assert!(!bridge.body_map().entries()[0].is_dynamic());
        assert!(bridge.scene().bodies()[0].is_fixed());
        if report.bodies_written > 0 {
            assert_ne!(*world.bodies[body].position(), body_before);
        }
        let (depth, tolerance) = (f32_world_depth(&world), stated_tolerance(&report));
        assert!(depth <= tolerance, "step {step}: {depth:e} > {tolerance:e}");
    }
}
