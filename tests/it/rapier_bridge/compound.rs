//! Dynamic bodies with several colliders (issue 10): read as one compound
//! scene body in the rigid body's frame, each collider a part at its
//! offset, corrected and written back whole. The depth left is measured on
//! Rapier's own poses (`B P_i` of each collider) by the brute-force
//! separating-axis oracle, not through the bridge's reading.

use constraint_stabilization::body::{MassSpec, Shape, ShapePart};
use constraint_stabilization::internals::geometry::ConvexPolyhedron;
use constraint_stabilization::rapier_bridge::{
    GRAVITY_Z_UP, SkipReason, pose_to_f64, world_from_scene,
};
use constraint_stabilization::scene::Scene;
use dev_support::sat::sat_overlap;
use dev_support::scene::{IDENTITY_XYZW, body, ground as scene_ground};
use nalgebra::{Isometry3, Vector3};
use rapier3d::prelude::*;

use super::{F32_POSE_TOLERANCE, bridge, ground, run, stated_tolerance};

/// Exact overlap of two cuboid colliders at their world poses `B P` as
/// Rapier holds them.
fn cuboid_overlap(world: &PhysicsWorld, a: ColliderHandle, b: ColliderHandle) -> f64 {
    let posed = |handle: ColliderHandle| {
        let collider = &world.colliders[handle];
        let h = collider.shape().as_cuboid().expect("a cuboid").half_extents;
        let pose = match collider.parent() {
            Some(parent) => {
                let offset = collider.position_wrt_parent().copied().unwrap_or_default();
                pose_to_f64(world.bodies[parent].position()) * pose_to_f64(&offset)
            }
            None => pose_to_f64(collider.position()),
        };
        let h = Vector3::new(f64::from(h.x), f64::from(h.y), f64::from(h.z));
        (ConvexPolyhedron::cuboid(h).expect("a valid box"), pose)
    };
    let ((poly_a, pose_a), (poly_b, pose_b)) = (posed(a), posed(b));
    sat_overlap(&poly_a, &pose_a, &poly_b, &pose_b)
}

#[test]
fn a_body_with_two_colliders_is_one_compound_lifted_whole() {
    let mut world = PhysicsWorld::default();
    let ground = ground(&mut world);
    let tilt = Rotation::from_scaled_axis(Vector::new(0.0, 0.0, 0.05));
    let body = world.insert_body(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(0.1, 0.15, 0.0))
            .rotation(tilt.to_scaled_axis())
            .sleeping(false),
    );
    // A bar sunk a little and a leg, turned about the vertical and offset,
    // sunk by about 0.25.
    let bar = world.insert_collider(ColliderBuilder::cuboid(0.6, 0.2, 0.2), Some(body));
    let leg = world.insert_collider(
        ColliderBuilder::cuboid(0.2, 0.3, 0.2)
            .translation(Vector::new(0.4, -0.1, 0.0))
            .rotation(Vector::new(0.0, 0.3, 0.0)),
        Some(body),
    );
    let sunk = cuboid_overlap(&world, leg, ground);
    assert!(sunk > 0.2);
    let mut bridge = bridge();
    let report = run(&mut bridge, &mut world);

    assert!(report.skipped().is_empty(), "{:?}", report.skipped());
    assert_eq!(bridge.scene().len(), 2, "the ground and one compound");
    let map = bridge.body_map();
    let index = map.scene_index_of_body(body).expect("the body is mapped");
    assert_eq!(map.scene_index(bar), Some(index));
    assert_eq!(map.scene_index(leg), Some(index));
    assert_eq!(map.entries()[index].colliders(), vec![bar, leg]);
    let read = &bridge.scene().bodies()[index];
    assert!(read.is_compound());
    assert_eq!(read.parts().len(), 2);
    assert_eq!(
        read.mass().expect("dynamic").mass,
        f64::from(world.bodies[body].mass())
    );
    assert_eq!(report.bodies_written, 1);
    let tolerance = stated_tolerance(&report);
    for collider in [bar, leg] {
        let left = cuboid_overlap(&world, collider, ground);
        assert!(
            left <= tolerance,
            "collider {collider:?}: {left:e} left (tolerance {tolerance:e})"
        );
    }
    // The body was lifted about the leg's depth, not flung: the leg ends
    // within a few hundredths of that depth above the ground (the steps
    // turn the body as they lift it, so it need not end touching).
    let gap = -cuboid_overlap(&world, leg, ground);
    assert!(gap < 0.05 * sunk, "the leg ends {gap:e} above the ground");

    // Read again unchanged: kept, nothing removed or appended.
    world.step();
    let report = run(&mut bridge, &mut world);
    assert_eq!((report.sync.appended, report.sync.removed), (0, 0));
}

#[test]
fn a_compound_with_an_unsupported_shape_is_skipped_whole_with_its_reason() {
    let mut world = PhysicsWorld::default();
    ground(&mut world);
    let body =
        world.insert_body(RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 1.0, 0.0)));
    let cube = world.insert_collider(ColliderBuilder::cuboid(0.2, 0.2, 0.2), Some(body));
    let odd = world.insert_collider(
        ColliderBuilder::round_cylinder(0.2, 0.2, 0.05).translation(Vector::new(0.5, 0.0, 0.0)),
        Some(body),
    );
    let mut bridge = bridge();
    let report = run(&mut bridge, &mut world);
    for collider in [cube, odd] {
        let skipped = report.skipped().iter().find(|s| s.collider == collider);
        assert_eq!(
            skipped.map(|s| s.reason.clone()),
            Some(SkipReason::Shape("RoundCylinder".into())),
            "{collider:?}"
        );
    }
    assert_eq!(bridge.scene().len(), 1, "the ground only");
}

/// A scene's compound through `world_from_scene` and back: one rigid body
/// with a collider per part, read as the same compound.
#[test]
fn a_scene_compound_round_trips_through_a_rapier_world() {
    let turned = [0.0, (0.15f64).sin(), 0.0, (0.15f64).cos()];
    let parts = vec![
        ShapePart {
            shape: Shape::Cuboid {
                half_extents: Vector3::new(0.5, 0.1, 0.1),
            },
            translation: Vector3::zeros(),
            rotation_xyzw: IDENTITY_XYZW,
        },
        ShapePart {
            shape: Shape::Cuboid {
                half_extents: Vector3::new(0.1, 0.25, 0.1),
            },
            translation: Vector3::new(0.5, 0.25, 0.0),
            rotation_xyzw: turned,
        },
    ];
    let mut scene = Scene::new();
    scene.add_body(scene_ground()).expect("valid ground");
    let shape = Shape::Compound { parts };
    let compound = body(
        "T",
        shape.clone(),
        [0.0, 0.3, 0.0],
        IDENTITY_XYZW,
        MassSpec::Mass(2.0),
    );
    scene.add_body(compound).expect("valid compound");
    let built = world_from_scene(&scene, GRAVITY_Z_UP).expect("the world is built");
    assert_eq!(built.part_colliders[1].len(), 2);
    let mut reader = bridge();
    reader
        .sync(&built.world.bodies, &built.world.colliders)
        .expect("the world is read");
    let read = &reader.scene().bodies()[1];
    assert!((read.mass().expect("dynamic").mass - 2.0).abs() < F32_POSE_TOLERANCE);
    let (Shape::Compound { parts: read_parts }, Shape::Compound { parts }) = (read.shape(), &shape)
    else {
        panic!("read as {:?}", read.shape());
    };
    assert_eq!(read_parts.len(), 2);
    for (read_part, part) in read_parts.iter().zip(parts) {
        let offset = |p: &ShapePart| {
            let [x, y, z, w] = p.rotation_xyzw;
            Isometry3::from_parts(
                p.translation.into(),
                nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(w, x, y, z)),
            )
        };
        let (a, b) = (offset(read_part), offset(part));
        assert!((a.translation.vector - b.translation.vector).norm() < F32_POSE_TOLERANCE);
        assert!(a.rotation.angle_to(&b.rotation) < F32_POSE_TOLERANCE);
    }
    let (a, b) = (read.com_pose(), scene.bodies()[1].com_pose());
    assert!((a.translation.vector - b.translation.vector).norm() < F32_POSE_TOLERANCE);
}
