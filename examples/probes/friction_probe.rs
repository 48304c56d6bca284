//! Probe: one call on an engine state with a friction coefficient on every
//! body, with the debug log (`RUST_LOG`).
//!
//! ```text
//! RUST_LOG=constraint_stabilization=debug cargo run --release --features rapier,serde \
//!     --example probes -- friction tests/data/engine/mj01_box_bin.json 1.0 [cone] [polish]
//! ```
//!
//! `cone`: `FrictionModel::Cone` (else the pyramid); `polish`: clarabel's
//! polish on every answer (`ClarabelSettings::polish_above` 0), whose trace line
//! (`RUST_LOG=constraint_stabilization::solver::clarabel_qp=trace`) gives
//! the acceptance measure of each clarabel answer unpolished and polished.

use std::time::Instant;

use constraint_stabilization::io::scene_file::read_scene;
use constraint_stabilization::{FrictionModel, Settings, Stabilizer};

pub fn run(args: Vec<String>) -> Result<(), Box<dyn std::error::Error>> {
    let _ = env_logger::try_init();
    let path = args.first().ok_or("a scene file")?;
    let mu: f64 = args.get(1).map_or(Ok(1.0), |s| s.parse())?;
    let mut scene = read_scene(std::path::Path::new(path))?;
    let mut settings = Settings::default();
    if args.iter().any(|a| a == "cone") {
        settings.friction_model = FrictionModel::Cone;
    }
    if args.iter().any(|a| a == "polish") {
        settings.solver.clarabel.polish_above = 0.0;
    }
    for body in 0..scene.bodies().len() {
        scene.body_mut(body)?.set_friction(Some(mu))?;
    }
    let mut stabilizer = Stabilizer::new(settings)?;
    let start = Instant::now();
    let report = stabilizer.stabilize(&mut scene)?;
    println!(
        "{}: {} passes, {:.1} ms, depth {:.3e} -> {:.3e}",
        report.status.name(),
        report.passes,
        start.elapsed().as_secs_f64() * 1e3,
        report.depth_before,
        report.depth_after
    );
    for (p, pass) in report.pass_reports.iter().enumerate() {
        for island in &pass.solved {
            println!(
                "pass {p}: island {} bodies, {} rows, solver {:?} ({} it), dropped {}, fallbacks {:?}",
                island.bodies.len(),
                island.constraints,
                island.solver,
                island.solver_iterations,
                island.friction_dropped,
                island.fallbacks
            );
        }
    }
    Ok(())
}
