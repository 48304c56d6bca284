use constraint_stabilization::settings::SceneSettings;
use constraint_stabilization::{Body, BodyDesc};
use nalgebra::Isometry3;
use nalgebra::{Translation3, UnitQuaternion, Vector3};

use constraint_stabilization::body::{MassSpec, Shape};
use constraint_stabilization::scene::*;

fn scene(n: usize) -> Scene {
    let descs = (0..n).map(|i| BodyDesc {
        name: format!("box {i}"),
        shape: Shape::Cuboid {
            half_extents: Vector3::new(0.5, 0.5, 0.5),
        },
        translation: Vector3::new(2.0 * i as f64, 0.0, 0.0),
        rotation_xyzw: [0.0, 0.0, 0.0, 1.0],
        mass: MassSpec::Mass(1.0),
    });
    Scene::from_descs(descs, SceneSettings::default()).expect("valid boxes")
}

fn names(scene: &Scene) -> Vec<&str> {
    scene.bodies().iter().map(Body::name).collect()
}

#[test]
fn remove_bodies_keeps_the_order_of_the_others() {
    let mut scene = scene(5);
    let map = scene.remove_bodies(&[3, 0, 3]).expect("indices in range");
    assert_eq!(names(&scene), ["box 1", "box 2", "box 4"]);
    assert_eq!(map.old_to_new(), [None, Some(0), Some(1), None, Some(2)]);
    assert_eq!((map.new_index(4), map.new_index(9)), (Some(2), None));
    assert_eq!(map.old_len(), 5);
    assert!(!map.is_identity());
    assert!(scene.remove_bodies(&[]).expect("nothing").is_identity());
}

#[test]
fn remove_bodies_out_of_range_removes_nothing() {
    let mut scene = scene(3);
    let error = scene.remove_bodies(&[1, 3]).unwrap_err();
    assert_eq!(error, SceneError::NoSuchBody { index: 3, len: 3 });
    assert_eq!(scene.len(), 3);
}

#[test]
fn set_user_poses_is_all_or_nothing() {
    let mut scene = scene(3);
    let rotation = UnitQuaternion::from_euler_angles(0.1, 0.2, 0.3);
    let moved = Isometry3::from_parts(Translation3::new(1.0, 2.0, 3.0), rotation);
    scene
        .set_user_poses([(0, moved), (2, moved)])
        .expect("valid poses");
    assert_eq!(scene.bodies()[2].user_pose().translation, moved.translation);
    assert!(scene.bodies()[2].user_pose().rotation.angle_to(&rotation) < 1e-15);

    let before: Vec<_> = scene.bodies().iter().map(Body::user_pose).collect();
    let blown_up = Isometry3::translation(f64::NAN, 0.0, 0.0);
    let error = scene
        .set_user_poses([(1, moved), (0, Isometry3::identity()), (2, blown_up)])
        .unwrap_err();
    assert!(
        matches!(error, SceneError::Body { index: 2, .. }),
        "{error}"
    );
    let after: Vec<_> = scene.bodies().iter().map(Body::user_pose).collect();
    assert_eq!(after, before);
    let error = scene.set_user_poses([(7, moved)]).unwrap_err();
    assert_eq!(error, SceneError::NoSuchBody { index: 7, len: 3 });
}
