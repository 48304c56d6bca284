use constraint_stabilization::body::{BodyDesc, MassSpec, Shape};
use constraint_stabilization::scene::Scene;
use constraint_stabilization::{Settings, Stabilizer};
use nalgebra::Vector3;

fn main() {
    env_logger::init();
    let mut scene = Scene::new();
    scene
        .add_body(BodyDesc {
            name: "ground".into(),
            shape: Shape::Cuboid {
                half_extents: Vector3::new(10.0, 0.5, 10.0),
            },
            translation: Vector3::new(0.0, -0.5, 0.0),
            rotation_xyzw: [0.0, 0.0, 0.0, 1.0],
            mass: MassSpec::Fixed,
        })
        .unwrap();
    scene
        .add_body(BodyDesc {
            name: "box".into(),
            shape: Shape::Cuboid {
                half_extents: Vector3::new(0.5, 0.5, 0.5),
            },
            translation: Vector3::new(0.0, 0.49, 0.0),
            rotation_xyzw: [0.0, 0.0, 0.0, 1.0],
            mass: MassSpec::Mass(1.0),
        })
        .unwrap();
    let mut stabilizer = Stabilizer::new(Settings::default()).unwrap();
    let report = stabilizer.stabilize(&mut scene).unwrap();
    println!(
        "{:?} passes {} depth {} -> {}",
        report.status, report.passes, report.depth_before, report.depth_after
    );
    println!(
        "{:?} {:?}",
        scene.bodies()[1].translation_user(),
        scene.bodies()[1].rotation_user_xyzw()
    );
    let n = std::env::args()
        .nth(1)
        .map(|s| s.parse().unwrap())
        .unwrap_or(100);
    let mut demo = constraint_stabilization::demo::demo_scene(n, 7);
    let report = stabilizer.stabilize(&mut demo).unwrap();
    println!(
        "{:?} passes {} depth {} -> {} islands {} times {:?} moved {}",
        report.status,
        report.passes,
        report.depth_before,
        report.depth_after,
        report.islands_solved(),
        report.times,
        report.bodies_moved
    );
}
