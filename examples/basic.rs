//! The library in twenty lines: a scene built in code, stabilized, and its
//! report. `cargo run --example basic` (add `RUST_LOG=debug` with an
//! env_logger-style logger in your own program to follow the method).

use constraint_stabilization::body::{BodyDesc, MassSpec, Shape};
use constraint_stabilization::scene::Scene;
use constraint_stabilization::{Settings, Stabilizer};
use nalgebra::Vector3;

fn main() -> Result<(), constraint_stabilization::Error> {
    let cuboid = |name: &str, half: [f64; 3], at: [f64; 3], mass| BodyDesc {
        name: name.into(),
        shape: Shape::Cuboid {
            half_extents: half.into(),
        },
        translation: Vector3::from(at),
        rotation_xyzw: [0.0, 0.0, 0.0, 1.0],
        mass,
    };
    let mut scene = Scene::new();
    scene.add_body(cuboid(
        "ground",
        [5.0, 0.5, 5.0],
        [0.0, -0.5, 0.0],
        MassSpec::Fixed,
    ))?;
    scene.add_body(cuboid(
        "low",
        [0.5, 0.5, 0.5],
        [0.0, 0.45, 0.0],
        MassSpec::Mass(1.0),
    ))?;
    scene.add_body(cuboid(
        "high",
        [0.5, 0.5, 0.5],
        [0.2, 1.4, 0.0],
        MassSpec::Density(500.0),
    ))?;
    let report = Stabilizer::new(Settings::default())?.stabilize(&mut scene)?;
    println!(
        "{}: {} passes, deepest penetration {:.3e} -> {:.3e} (tolerance {:.1e}), {} bodies moved",
        report.status.name(),
        report.passes,
        report.depth_before,
        report.depth_after,
        report.tolerance,
        report.bodies_moved
    );
    for body in scene.bodies() {
        println!(
            "{:>6} at {:.6?}",
            body.name(),
            body.translation_user().as_slice()
        );
    }
    Ok(())
}
