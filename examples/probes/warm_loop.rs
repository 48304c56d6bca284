//! The solver's warm starts on the states of an engine run (issue 21,
//! item 2): one plain Rapier run per scene and, after every step, two
//! stabilizer calls on copies of the same state, read into a scene by
//! `RapierBridge::sync` (so the shapes keep their identity from call to
//! call, as under the bridge): one by a stabilizer with the default
//! settings, one by a stabilizer identical but for
//! `SolverSettings::warm_starts = false`. Nothing is written back: both
//! see Rapier's own trajectory, and each keeps its caches across calls.
//! The two calls of a step alternate in order (interleaved).
//!
//! ```text
//! cargo run --release --features rapier,serde --example probes -- warm [--steps N] [--scenes A,B] [--bridge-solvers]
//! ```
//!
//! `--bridge-solvers` takes the solvers of `BridgeSettings::default()`
//! (the dual active-set method off) in place of the stabilizer's
//! defaults. Per scene, over the calls that had something to solve:
//! medians of the call's time and of its solver iterations (summed over
//! its islands and passes), the share of islands that were warm-started,
//! and the largest distance between the two calls' results: a body's
//! translation difference over the call's largest translation and over
//! the call's tolerance, and the calls whose passes differ. Each pass's
//! minimizer is unique in `dq`, so one pass's answers differ by the
//! solvers' tolerances; a call stops once its depth is within its
//! tolerance, so two calls can stop a pass apart, and their results then
//! differ by about that tolerance. On stderr, per scene and variant:
//! the passes summed over the calls, and per solver that answered its
//! islands, warm-started islands, iterations and factorizations.

use crate::certificates_loop::{steps_and_scenes, world_of};

use std::collections::BTreeMap;
use std::time::Instant;

use constraint_stabilization::rapier_bridge::{BridgeSettings, RapierBridge};
use constraint_stabilization::{Report, Scene, Settings, Stabilizer, Status};

/// Calls whose two results lie more than this many call tolerances apart
/// are listed on stderr (step, distance, largest translation, passes).
const LISTED_DIFFERENCE: f64 = 100.0;

/// What one variant measured per call that solved something.
#[derive(Default)]
struct Calls {
    call_ms: Vec<f64>,
    iterations: Vec<f64>,
    islands: usize,
    warm_islands: usize,
    passes: usize,
    /// Per solver that answered: islands, warm-started islands,
    /// iterations, factorizations (summed over the calls).
    by_solver: BTreeMap<String, [usize; 4]>,
}

impl Calls {
    fn record(&mut self, report: &Report, ms: f64) {
        let solved = report.pass_reports.iter().flat_map(|p| &p.solved);
        let (mut iterations, mut islands, mut warm) = (0, 0, 0);
        for island in solved {
            iterations += island.solver_iterations;
            islands += 1;
            warm += usize::from(island.warm_started);
            let kind = island
                .solver
                .map_or("none".to_string(), |k| format!("{k:?}"));
            let sums = self.by_solver.entry(kind).or_default();
            sums[0] += 1;
            sums[1] += usize::from(island.warm_started);
            sums[2] += island.solver_iterations;
            sums[3] += island.factorizations;
        }
        self.passes += report.passes;
        self.call_ms.push(ms);
        self.iterations.push(iterations as f64);
        self.islands += islands;
        self.warm_islands += warm;
    }
}

fn median(values: &[f64]) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    sorted.get(sorted.len() / 2).copied().unwrap_or(f64::NAN)
}

/// The largest translation of a body from `before` to `after`.
fn largest_translation(before: &Scene, after: &Scene) -> f64 {
    before
        .bodies()
        .iter()
        .zip(after.bodies())
        .map(|(a, b)| (a.com_pose().translation.vector - b.com_pose().translation.vector).norm())
        .fold(0.0, f64::max)
}

pub fn run(args: Vec<String>) -> Result<(), Box<dyn std::error::Error>> {
    let (steps, names) = steps_and_scenes(&args)?;
    let base = match args.iter().any(|a| a == "--bridge-solvers") {
        true => BridgeSettings::default().stabilizer,
        false => Settings::default(),
    };
    println!(
        "| scene | steps | calls that solved | call ms (median): warm / cold | solver iterations per call (median): warm / cold | islands warm-started | largest difference / largest translation | largest difference / call tolerance | calls with other passes | failed calls: warm / cold |\n|---|---|---|---|---|---|---|---|---|---|"
    );
    for name in names.split(',').map(str::trim) {
        let Some(mut world) = world_of(name) else {
            return Err(format!("no scene named {name}").into());
        };
        let mut reader = RapierBridge::with_settings(BridgeSettings::default())?;
        let mut stabilizers = [true, false].map(|warm_starts| {
            let mut settings = base.clone();
            settings.solver.warm_starts = warm_starts;
            Stabilizer::new(settings)
        });
        let mut calls = [Calls::default(), Calls::default()];
        let mut failed = [0, 0];
        let mut worst_difference: f64 = 0.0;
        let mut worst_over_tolerance: f64 = 0.0;
        let mut other_passes = 0;
        for step in 0..steps {
            world.step();
            reader.sync(&world.bodies, &world.colliders)?;
            let input = reader.scene();
            let order = if step % 2 == 0 { [0, 1] } else { [1, 0] };
            let mut results: [Option<(Scene, usize, f64)>; 2] = [None, None];
            for k in order {
                let stabilizer = stabilizers[k].as_mut().map_err(|e| e.to_string())?;
                let mut scene = input.clone();
                let start = Instant::now();
                let report = stabilizer.stabilize(&mut scene);
                let ms = start.elapsed().as_secs_f64() * 1e3;
                match report {
                    Ok(report) if report.status == Status::NothingToDo => {}
                    Ok(report) => {
                        calls[k].record(&report, ms);
                        results[k] = Some((scene, report.passes, report.tolerance));
                    }
                    Err(_) => failed[k] += 1,
                }
            }
            if let [
                Some((warm, warm_passes, _)),
                Some((cold, cold_passes, tolerance)),
            ] = &results
            {
                let difference = largest_translation(warm, cold);
                let moved = largest_translation(input, cold);
                if moved > 0.0 {
                    worst_difference = worst_difference.max(difference / moved);
                }
                worst_over_tolerance = worst_over_tolerance.max(difference / tolerance);
                if difference > LISTED_DIFFERENCE * tolerance {
                    eprintln!(
                        "{name}, step {step}: results {difference:.3e} m apart, largest translation {moved:.3e} m, passes {warm_passes} / {cold_passes}"
                    );
                }
                other_passes += usize::from(warm_passes != cold_passes);
            }
        }
        let [warm, cold] = &calls;
        for (label, variant) in [("warm", warm), ("cold", cold)] {
            eprintln!("{name}, {label}: passes {}", variant.passes);
            for (kind, [islands, warm_islands, iterations, factorizations]) in &variant.by_solver {
                eprintln!(
                    "{name}, {label}, {kind}: islands {islands}, warm-started {warm_islands}, iterations {iterations}, factorizations {factorizations}"
                );
            }
        }
        println!(
            "| {name} | {steps} | {} / {} | {:.3} / {:.3} | {:.0} / {:.0} | {} of {} | {worst_difference:.1e} | {worst_over_tolerance:.2} | {other_passes} | {} / {} |",
            warm.call_ms.len(),
            cold.call_ms.len(),
            median(&warm.call_ms),
            median(&cold.call_ms),
            median(&warm.iterations),
            median(&cold.iterations),
            warm.warm_islands,
            warm.islands,
            failed[0],
            failed[1],
        );
    }
    Ok(())
}
