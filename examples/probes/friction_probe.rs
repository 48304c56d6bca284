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
//! `solver=NAME`: `SolverSettings::choice` (`auto`, `lemke`, ...);
//! `lemke-max=N`: `Auto` takes Lemke up to N rows, the interior point
//! above. `rows=NAME`: `Settings::friction_rows` (`all`, `implied`,
//! `generated`). `target=REL`: `Settings::target_margin_relative`. `push=F`:
//! `LineSearchSettings::new_penetration_fraction`. `repeat=N`: the call N more times on fresh copies of the scene, for a
//! profiler, and their median time.

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
    if let Some(name) = args.iter().find_map(|a| a.strip_prefix("solver=")) {
        settings.solver.choice = constraint_stabilization::solver::SolverChoice::from_name(name)
            .ok_or_else(|| format!("unknown solver {name}"))?;
    }
    if let Some(rows) = args.iter().find_map(|a| a.strip_prefix("lemke-max=")) {
        settings.solver.auto_lemke_max_rows = rows.parse()?;
        settings.solver.auto_interior_point_min_rows = settings.solver.auto_lemke_max_rows + 1;
    }
    if args.iter().any(|a| a == "polish") {
        settings.solver.clarabel.polish_above = 0.0;
    }
    if let Some(rel) = args.iter().find_map(|a| a.strip_prefix("target=")) {
        settings.target_margin_relative = rel.parse()?;
    }
    if let Some(fraction) = args.iter().find_map(|a| a.strip_prefix("push=")) {
        settings.line_search.new_penetration_fraction = fraction.parse()?;
    }
    if let Some(fraction) = args.iter().find_map(|a| a.strip_prefix("ip-step=")) {
        settings.solver.interior_point.step_fraction = fraction.parse()?;
    }
    if let Some(count) = args.iter().find_map(|a| a.strip_prefix("ipc=")) {
        settings.solver.interior_point.centrality_correctors = count.parse()?;
    }
    if let Some(name) = args.iter().find_map(|a| a.strip_prefix("rows=")) {
        settings.friction_rows = constraint_stabilization::FrictionRows::ALL
            .into_iter()
            .find(|rows| rows.name() == name)
            .ok_or_else(|| format!("unknown friction rows {name}"))?;
    }
    for body in 0..scene.bodies().len() {
        scene.body_mut(body)?.set_friction(Some(mu))?;
    }
    let repeats: usize = args
        .iter()
        .find_map(|a| a.strip_prefix("repeat="))
        .map_or(Ok(0), str::parse)?;
    let input = scene.clone();
    let mut stabilizer = Stabilizer::new(settings.clone())?;
    let start = Instant::now();
    let report = stabilizer.stabilize(&mut scene)?;
    let call_ms = start.elapsed().as_secs_f64() * 1e3;
    let mut times_ms = Vec::with_capacity(repeats);
    for _ in 0..repeats {
        let mut copy = input.clone();
        let mut fresh = Stabilizer::new(settings.clone())?;
        let t = Instant::now();
        fresh.stabilize(&mut copy)?;
        times_ms.push(t.elapsed().as_secs_f64() * 1e3);
    }
    if !times_ms.is_empty() {
        times_ms.sort_by(f64::total_cmp);
        println!("{repeats} repeats, median {:.3} ms", times_ms[repeats / 2]);
    }
    println!(
        "{}: {} passes, {:.1} ms, depth {:.3e} -> {:.3e}",
        report.status.name(),
        report.passes,
        call_ms,
        report.depth_before,
        report.depth_after
    );
    print_correction(&input, &scene);
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

/// The size of the call's correction: the largest translation of a centre
/// of mass, the largest rotation, and the mass-weighted translation norm
/// `sqrt(sum_i m_i |dx_i|^2)` over the moving bodies.
fn print_correction(
    before: &constraint_stabilization::Scene,
    after: &constraint_stabilization::Scene,
) {
    let (mut largest_dx, mut largest_angle, mut weighted) = (0.0_f64, 0.0_f64, 0.0_f64);
    for (a, b) in before.bodies().iter().zip(after.bodies()) {
        let Some(mass) = a.mass() else { continue };
        let dx = (b.com_world() - a.com_world()).norm();
        let angle = a.com_pose().rotation.angle_to(&b.com_pose().rotation);
        largest_dx = largest_dx.max(dx);
        largest_angle = largest_angle.max(angle);
        weighted += mass.mass * dx * dx;
    }
    println!(
        "correction: largest translation {:.4e} m, largest rotation {:.4e} rad, sqrt(sum m dx^2) {:.17e}",
        largest_dx,
        largest_angle,
        weighted.sqrt()
    );
}
