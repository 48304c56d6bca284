use constraint_stabilization::{Scene, Shape};
use nalgebra::Vector3;
use nalgebra::{Point3, UnitQuaternion};
use rapier3d::math::Vector;

use constraint_stabilization::body::{BodyDesc, MassSpec};
use constraint_stabilization::internals::rapier_bridge::world::*;
use constraint_stabilization::rapier_bridge::RapierBridge;
use constraint_stabilization::settings::Settings;

/// f32 rounding of numbers of order 1, a few ulps.
const F32_TOLERANCE: f64 = 1e-6;

fn desc(name: &str, shape: Shape, translation: [f64; 3], mass: MassSpec) -> BodyDesc {
    let rotation = UnitQuaternion::from_euler_angles(0.3, -0.2, 0.7);
    let q = rotation.quaternion();
    BodyDesc {
        name: name.into(),
        shape,
        translation: Vector3::from(translation),
        rotation_xyzw: [q.i, q.j, q.k, q.w],
        mass,
    }
}

fn scene() -> Scene {
    let hull: Vec<Point3<f64>> = [
        [0.5, 0.25, 0.0],
        [0.9, 0.2, 0.1],
        [0.6, 0.7, -0.1],
        [0.55, 0.3, 0.5],
        [0.7, 0.4, 0.2],
    ]
    .iter()
    .map(|&p| Point3::from(p))
    .collect();
    let mut ground = desc(
        "ground",
        Shape::Cuboid {
            half_extents: Vector3::new(3.0, 3.0, 0.5),
        },
        [0.0, 0.0, -0.5],
        MassSpec::Fixed,
    );
    ground.rotation_xyzw = [0.0, 0.0, 0.0, 1.0];
    let descs = [
        ground,
        desc(
            "box",
            Shape::Cuboid {
                half_extents: Vector3::new(0.1, 0.2, 0.3),
            },
            [0.2, -0.1, 0.4],
            MassSpec::Mass(2.5),
        ),
        desc(
            "hull",
            Shape::ConvexHull { points: hull },
            [-0.4, 0.3, 0.8],
            MassSpec::Density(700.0),
        ),
    ];
    let mut scene = Scene::new();
    for desc in descs {
        scene.add_body(desc).expect("valid body");
    }
    scene
}

/// The world read back through the bridge is the scene: fixed flags,
/// shapes, user poses and masses equal up to f32 rounding; gravity and
/// Rapier's default time step.
#[test]
fn world_read_back_through_the_bridge_is_the_scene() {
    let scene = scene();
    let built = world_from_scene(&scene, GRAVITY_Z_UP).expect("valid world");
    assert_eq!(built.world.gravity, Vector::new(0.0, 0.0, -9.81));
    assert_eq!(built.world.integration_parameters.dt, 1.0 / 60.0);
    assert_eq!(built.colliders.len(), scene.len());
    let mut bridge = RapierBridge::new(Settings::default()).expect("valid settings");
    let sync = bridge
        .sync(&built.world.bodies, &built.world.colliders)
        .expect("the world is read");
    assert!(sync.skipped.is_empty());
    let read = bridge.scene();
    assert_eq!(read.len(), scene.len());
    for (i, (a, b)) in scene.bodies().iter().zip(read.bodies()).enumerate() {
        assert_eq!(bridge.body_map().entries()[i].collider, built.colliders[i]);
        assert_eq!(a.is_fixed(), b.is_fixed(), "body {i}");
        let (pa, pb) = (a.user_pose(), b.user_pose());
        assert!((pa.translation.vector - pb.translation.vector).norm() <= F32_TOLERANCE);
        assert!(pa.rotation.angle_to(&pb.rotation) <= F32_TOLERANCE);
        let mass = |body: &constraint_stabilization::body::Body| body.mass().map(|m| m.mass);
        if let (Some(ma), Some(mb)) = (mass(a), mass(b)) {
            assert!(
                (ma - mb).abs() <= F32_TOLERANCE * ma,
                "body {i}: {ma} vs {mb}"
            );
        }
        match (a.shape(), b.shape()) {
            (Shape::Cuboid { half_extents: ha }, Shape::Cuboid { half_extents: hb }) => {
                assert!((ha - hb).norm() <= F32_TOLERANCE);
            }
            (Shape::ConvexHull { points: pa }, Shape::ConvexHull { points: pb }) => {
                for p in pb {
                    let nearest = pa.iter().map(|q| (p - q).norm()).fold(f64::MAX, f64::min);
                    assert!(nearest <= F32_TOLERANCE, "hull point {p} not given");
                }
                let volume = |s: &Shape| s.build().expect("hull").volume();
                let (va, vb) = (volume(a.shape()), volume(b.shape()));
                assert!((va - vb).abs() <= F32_TOLERANCE * va);
            }
            (sa, sb) => panic!("body {i}: shape {sa:?} read back as {sb:?}"),
        }
    }
}
