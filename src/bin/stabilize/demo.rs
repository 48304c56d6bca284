//! `stabilize demo`: the built-in scene (a pile of boxes and random convex
//! hulls with overlaps, fixed seed, a few hundred bodies) stabilized once,
//! with the penetration before and after measured independently by parry.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use constraint_stabilization::io::scene_file::write_scene;
use constraint_stabilization::scene::Scene;
use constraint_stabilization::settings::GaussSeidelSettings;
use constraint_stabilization::solver::SolverChoice;
use constraint_stabilization::stabilizer::report_json::report_to_json;
use constraint_stabilization::testbed::demo::{DEFAULT_BODY_COUNT, DEFAULT_SEED, demo_scene};
use constraint_stabilization::testbed::verify::parry_penetration;
use constraint_stabilization::{Method, Report, Settings, Stabilizer};

use crate::exit;
use crate::progress::PassProgress;

/// Arguments of `stabilize demo`.
#[derive(Debug, Args)]
pub struct DemoArgs {
    /// Number of bodies (including the fixed ground).
    #[arg(long, default_value_t = DEFAULT_BODY_COUNT)]
    bodies: usize,
    /// Random seed of the scene.
    #[arg(long, default_value_t = DEFAULT_SEED)]
    seed: u64,
    /// Solver: auto, clarabel, clarabel_dual, lemke, pgs,
    /// augmented_lagrangian or interior_point.
    #[arg(long, default_value = "auto")]
    solver: String,
    /// Method: projection, or gauss_seidel (the game-engine baseline,
    /// Box2D's position correction; `--solver` is then unused).
    #[arg(long, default_value = "projection")]
    method: String,
    /// Sweeps of the gauss_seidel method (Box2D's position iterations).
    #[arg(long, default_value_t = GaussSeidelSettings::default().iterations)]
    iterations: usize,
    /// Also write the corrected scene (with its report) to this file.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Also write the scene as generated, before stabilization.
    #[arg(long)]
    before: Option<PathBuf>,
}

/// Runs the subcommand.
pub fn run(args: &DemoArgs) -> ExitCode {
    let Some(choice) = SolverChoice::from_name(&args.solver) else {
        return exit::bad_input(&format!("unknown solver `{}`", args.solver));
    };
    let Some(method) = Method::from_name(&args.method) else {
        return exit::bad_input(&format!("unknown method `{}`", args.method));
    };
    let mut settings = Settings::default();
    settings.solver.choice = choice;
    settings.method = method;
    settings.gauss_seidel.iterations = args.iterations;
    if let Err(error) = settings.validate() {
        return exit::bad_input(&error);
    }
    let mut scene = demo_scene(args.bodies, args.seed);
    if let Some(path) = &args.before
        && let Err(error) = write_scene(path, &scene, None)
    {
        return exit::bad_input(&error);
    }
    println!(
        "demo scene: {} bodies ({} fixed), seed {}",
        scene.len(),
        scene.fixed_flags().iter().filter(|&&f| f).count(),
        args.seed
    );
    let result = Stabilizer::new(settings).and_then(|mut s| {
        let before = parry_penetration(&scene, 0.0)?;
        let mut progress = PassProgress::start("stabilizing");
        let report = s.stabilize_observed(&mut scene, &mut |pass| progress.pass(pass));
        progress.finish();
        Ok((before, report?))
    });
    let (before, report) = match result {
        Ok(outcome) => outcome,
        Err(error) => return exit::not_solved(&error),
    };
    println!(
        "before: {} penetrating pairs (parry), deepest {:.4e}",
        before.penetrating_pairs, before.deepest
    );
    let after = match parry_penetration(&scene, report.tolerance) {
        Ok(after) => after,
        Err(error) => return exit::not_solved(&error),
    };
    print_report(&report, &scene);
    println!(
        "after:  {} pairs penetrating deeper than the tolerance {:.1e} (parry), deepest {:.4e}",
        after.penetrating_pairs, report.tolerance, after.deepest
    );
    if let Some(path) = &args.output {
        let json = report_to_json(&report, &scene);
        if let Err(error) = write_scene(path, &scene, Some(&json)) {
            return exit::bad_input(&error);
        }
    }
    if report.status.is_resolved() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(exit::NOT_SOLVED)
    }
}

fn print_report(report: &Report, scene: &Scene) {
    let times = &report.times;
    let share = |t: f64| 100.0 * t / times.total.max(f64::MIN_POSITIVE);
    println!(
        "stabilized: {} in {} passes, {} islands solved, {} line-search trials, {} of {} bodies moved",
        report.status.name(),
        report.passes,
        report.islands_solved(),
        report.line_search_trials(),
        report.bodies_moved,
        scene.len()
    );
    println!(
        "penetration (exact depth): {:.4e} -> {:.4e}; mass-weighted displacement {:.4e}",
        report.depth_before, report.depth_after, report.displacement
    );
    println!(
        "time {:.2} ms: broad phase {:.0}%, narrow phase {:.0}%, solve {:.0}%, line search {:.0}% (stage times summed over islands)",
        times.total * 1e3,
        share(times.broad_phase),
        share(times.narrow_phase),
        share(times.solve),
        share(times.line_search)
    );
}
