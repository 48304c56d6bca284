//! The friction models side by side (issue 10): the exact cone
//! (`FrictionModel::Cone`, clarabel's second-order cones) against the
//! pyramid of 4 and of 8 facets (`FrictionModel::Pyramid`), on the same
//! inputs, interleaved, median wall time of the stabilizer call.
//!
//! ```text
//! cargo run --release --features rapier,testbed --example friction_models -- [--steps N] [--repeats R] [--pile BODIES]
//! ```
//!
//! Inputs: (1) the scenes that the Rapier bridge's stabilizer receives on
//! the 1:1000 aligned stack of `examples/probes/slide_probe.rs` (Rapier's
//! colliders' friction, 0.5), recorded once with the bridge's default
//! settings over `--steps` steps; (2) the demonstration pile of
//! `--pile` bodies (`demo_scene`, 5 seeds) with `Settings::friction = 0.5`.
//! For each model and input: the median over `--repeats` interleaved runs
//! of the call's time, summed over the inputs of a family; the sliding
//! (the bodies' displacement orthogonal to the up axis, summed over bodies
//! and inputs) and the largest difference of a body's position from the
//! cone's answer.

#[path = "common/rapier_scenes.rs"]
mod scenes;

use std::time::Instant;

use constraint_stabilization::rapier_bridge::{BridgeSettings, CouplingMode, RapierBridge};
use constraint_stabilization::scene::Scene;
use constraint_stabilization::testbed::demo::demo_scene;
use constraint_stabilization::{FrictionModel, Settings, Stabilizer};
use nalgebra::Vector3;

/// The models compared: name, model, pyramid directions.
const MODELS: [(&str, FrictionModel, usize); 3] = [
    ("cone", FrictionModel::Cone, 4),
    ("pyramid 4", FrictionModel::Pyramid, 4),
    ("pyramid 8", FrictionModel::Pyramid, 8),
];

/// One input and the axis that points up in it.
struct Input {
    scene: Scene,
    up: Vector3<f64>,
}

/// The scenes the bridge's stabilizer receives on the 1:1000 stack.
fn recorded_stack(steps: usize) -> Result<Vec<Input>, Box<dyn std::error::Error>> {
    let (mut world, _) = scenes::aligned_heavy_stack_world(1000.0);
    // Velocity consistency, the coupling the table of
    // benchmarks/results/friction_models.md was measured with (the
    // default before `ClosedContacts`).
    let mut bridge = RapierBridge::with_settings(BridgeSettings {
        coupling: CouplingMode::VelocityConsistency,
        ..BridgeSettings::default()
    })?;
    let mut inputs = Vec::new();
    for _ in 0..steps {
        world.step();
        bridge.sync(&world.bodies, &world.colliders)?;
        inputs.push(Input {
            scene: bridge.scene().clone(),
            up: Vector3::z(),
        });
        bridge.stabilize(
            &mut world.bodies,
            &mut world.colliders,
            &world.impulse_joints,
            &world.multibody_joints,
            &world.integration_parameters,
        )?;
    }
    Ok(inputs)
}

/// The demonstration piles with friction 0.5.
fn piles(bodies: usize) -> Vec<Input> {
    (0..5)
        .map(|seed| Input {
            scene: demo_scene(bodies, seed),
            up: Vector3::y(),
        })
        .collect()
}

/// What one model did on one input: seconds of each repeat, and the
/// corrected scene.
struct Run {
    seconds: Vec<f64>,
    output: Scene,
}

fn median(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

fn settings(base: &Settings, model: FrictionModel, directions: usize) -> Settings {
    {
        let mut settings = base.clone();
        settings.friction_model = model;
        settings.friction_directions = directions;
        settings
    }
}

/// Every model on every input, `repeats` times, interleaved.
fn run_family(
    name: &str,
    inputs: &[Input],
    base: &Settings,
    repeats: usize,
) -> Result<(), Box<dyn std::error::Error>> {
    let mut runs: Vec<Vec<Run>> = MODELS
        .iter()
        .map(|_| {
            inputs
                .iter()
                .map(|input| Run {
                    seconds: Vec::new(),
                    output: input.scene.clone(),
                })
                .collect()
        })
        .collect();
    let mut unresolved = vec![0usize; MODELS.len()];
    for _ in 0..repeats {
        for (m, &(_, model, directions)) in MODELS.iter().enumerate() {
            let mut stabilizer = Stabilizer::new(settings(base, model, directions))?;
            for (i, input) in inputs.iter().enumerate() {
                let mut scene = input.scene.clone();
                let start = Instant::now();
                let report = stabilizer.stabilize(&mut scene)?;
                runs[m][i].seconds.push(start.elapsed().as_secs_f64());
                unresolved[m] += usize::from(!report.status.is_resolved());
                runs[m][i].output = scene;
            }
        }
    }
    println!("{name} ({} inputs, {repeats} repeats):", inputs.len());
    let cone_time: f64 = runs[0].iter_mut().map(|r| median(&mut r.seconds)).sum();
    for (m, (label, _, _)) in MODELS.iter().enumerate() {
        let time: f64 = runs[m].iter_mut().map(|r| median(&mut r.seconds)).sum();
        let (mut slide, mut from_cone) = (0.0_f64, 0.0_f64);
        for (i, input) in inputs.iter().enumerate() {
            let bodies = input.scene.bodies().iter().zip(runs[m][i].output.bodies());
            for (k, (before, after)) in bodies.enumerate() {
                let moved = after.translation_user() - before.translation_user();
                slide += (moved - input.up * moved.dot(&input.up)).norm();
                let cone = runs[0][i].output.bodies()[k].translation_user();
                from_cone = from_cone.max((after.translation_user() - cone).norm());
            }
        }
        println!(
            "  {label:10} median time {:8.3} ms ({:.2}x the cone's), sliding {slide:.4e}, \
             largest difference from the cone {from_cone:.3e}, unresolved calls {}",
            1e3 * time,
            time / cone_time,
            unresolved[m] / repeats
        );
    }
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let value = |flag: &str| {
        args.iter()
            .position(|a| a == flag)
            .and_then(|i| args.get(i + 1).cloned())
    };
    let steps: usize = value("--steps").map_or(Ok(120), |s| s.parse())?;
    let repeats: usize = value("--repeats").map_or(Ok(5), |s| s.parse())?;
    let pile: usize = value("--pile").map_or(Ok(60), |s| s.parse())?;
    let stack = recorded_stack(steps)?;
    let bridge_settings = BridgeSettings::default().stabilizer;
    run_family("1:1000 stack (Rapier)", &stack, &bridge_settings, repeats)?;
    let with_friction = {
        let mut settings = Settings::default();
        settings.friction = 0.5;
        settings
    };
    run_family("demo pile, mu 0.5", &piles(pile), &with_friction, repeats)?;
    Ok(())
}
