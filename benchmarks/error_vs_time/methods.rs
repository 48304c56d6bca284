//! The methods compared, each as a list of configurations (points of a
//! work-precision line), and one run of a configuration.
//!
//! - **This library** (`Stabilizer::stabilize`, fresh stabilizer per run,
//!   default settings otherwise), per solver choice: a line over pass
//!   limits ([`PASS_LIMITS`], up to what the solver needs at the default
//!   tolerance), and for `auto` a line over tolerances ([`TOLERANCES`],
//!   relative to the scene scale, unlimited passes).
//! - **Nonlinear Gauss–Seidel position correction** (the library's
//!   `Method::GaussSeidel`, see `src/gauss_seidel/`), two parameter sets,
//!   [`GaussSeidelPreset`], over [`ITERATIONS`] sweeps.
//! - **Settling by simulation** (feature `rapier`): the scene's Rapier
//!   world (`rapier_bridge::world_from_scene`, Rapier's default integration
//!   parameters, gravity off), velocities set to zero after each step;
//!   the points are the poses after [`STEPS`] steps of one run, the time is
//!   the cumulative time of the steps and the zeroing.

use std::time::Instant;

use constraint_stabilization::scene::Scene;
use constraint_stabilization::solver::SolverChoice;
use constraint_stabilization::{Settings, Stabilizer};

/// Pass limits of the library's pass line (those below the passes the
/// solver needs; the unlimited run closes the line).
pub const PASS_LIMITS: [usize; 7] = [1, 2, 3, 5, 10, 20, 50];
/// Pass limits in the quick run.
pub const PASS_LIMITS_QUICK: [usize; 1] = [1];
/// Tolerances of the library's tolerance line, relative to the scale.
pub const TOLERANCES: [f64; 7] = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9];
/// Tolerances in the quick run.
pub const TOLERANCES_QUICK: [f64; 3] = [1e-3, 1e-6, 1e-9];
/// Sweeps of the Gauss–Seidel lines.
pub const ITERATIONS: [usize; 8] = [1, 2, 3, 5, 10, 20, 50, 100];
/// Sweeps in the quick run.
pub const ITERATIONS_QUICK: [usize; 3] = [1, 10, 100];
/// Steps of the settling line.
pub const STEPS: [usize; 10] = [1, 2, 3, 5, 10, 20, 50, 100, 200, 300];
/// Steps in the quick run.
pub const STEPS_QUICK: [usize; 3] = [1, 10, 100];
/// The library's default relative tolerance (`Settings::default()`).
pub const DEFAULT_TOLERANCE: f64 = 1e-6;

/// The library's solver choices, with their names in the output.
pub const SOLVERS: [(SolverChoice, &str); 4] = [
    (SolverChoice::Auto, "auto"),
    (SolverChoice::Clarabel, "clarabel"),
    (SolverChoice::Lemke, "lemke"),
    (SolverChoice::Pgs, "pgs"),
];

/// A parameter set of the Gauss–Seidel baseline.
#[derive(Debug, Clone, Copy)]
pub struct GaussSeidelPreset {
    pub name: &'static str,
    pub baumgarte: f64,
    pub slop_relative: f64,
    pub max_correction_relative: f64,
    pub detect_every_sweep: bool,
}

/// Box2D v2.4 as it is (`b2_baumgarte`, `b2_linearSlop`,
/// `b2_maxLinearCorrection`, metres mapped to the scene scale; contacts
/// found once, their points re-measured at every visit), and the same
/// solver tuned to reach the library's tolerance: no slop, the full depth
/// per visit (the best of 0.5, 0.8 and 1 on a pyramid, a stack and a
/// pile), no cap, contacts found once or before every sweep.
pub const GAUSS_SEIDEL_PRESETS: [GaussSeidelPreset; 3] = [
    GaussSeidelPreset {
        name: "gs_box2d",
        baumgarte: 0.2,
        slop_relative: 0.005,
        max_correction_relative: 0.2,
        detect_every_sweep: false,
    },
    GaussSeidelPreset {
        name: "gs_tuned",
        baumgarte: 1.0,
        slop_relative: 0.0,
        max_correction_relative: f64::INFINITY,
        detect_every_sweep: false,
    },
    GaussSeidelPreset {
        name: "gs_tuned_redetect",
        baumgarte: 1.0,
        slop_relative: 0.0,
        max_correction_relative: f64::INFINITY,
        detect_every_sweep: true,
    },
];

/// What a configuration runs.
#[derive(Debug, Clone, Copy)]
pub enum Kind {
    Library {
        solver: SolverChoice,
        tolerance_relative: f64,
        max_passes: usize,
    },
    GaussSeidel {
        preset: GaussSeidelPreset,
        iterations: usize,
    },
    /// One simulation run; a point per checkpoint.
    Settle,
}

/// A configuration: a line (method) and its parameter.
#[derive(Debug, Clone)]
pub struct Config {
    /// The line it belongs to (`auto passes`, `gs_box2d`, `settle`, ...).
    pub line: String,
    /// The parameter along the line, as text (`passes=3`, `tol=1e-7`).
    pub parameter: String,
    pub kind: Kind,
}

/// One point produced by a run.
pub struct RunPoint {
    /// Parameter text (for settling, the step count).
    pub parameter: String,
    pub seconds: f64,
    pub scene: Scene,
    /// Passes, sweeps or steps done.
    pub iterations: usize,
    /// The method's own status (`resolved`, `max-passes`, `steps`).
    pub status: String,
    /// Rows of the largest island solved (library runs; 0 otherwise).
    pub largest_island_rows: usize,
    /// Rows of every island solved in every pass, summed (the work the
    /// call did; library runs, 0 otherwise).
    pub rows_solved: usize,
}

/// Settings of a library configuration.
pub fn library_settings(
    solver: SolverChoice,
    tolerance_relative: f64,
    max_passes: usize,
) -> Settings {
    let mut settings = Settings::default();
    settings.solver.choice = solver;
    // The target margin stays at its default: a looser tolerance stops
    // earlier, it does not aim for a wider gap.
    settings.tolerance_relative = tolerance_relative;
    settings.max_passes = max_passes;
    settings
}

/// One run of `config` on a copy of `scene`.
pub fn run(scene: &Scene, config: &Config, checkpoints: &[usize]) -> Result<Vec<RunPoint>, String> {
    match config.kind {
        Kind::Library {
            solver,
            tolerance_relative,
            max_passes,
        } => stabilize(
            scene,
            library_settings(solver, tolerance_relative, max_passes),
            &config.parameter,
        ),
        Kind::GaussSeidel { preset, iterations } => stabilize(
            scene,
            crate::gauss_seidel::settings(&preset, iterations),
            &config.parameter,
        ),
        Kind::Settle => crate::settle::run(scene, checkpoints),
    }
}

fn stabilize(scene: &Scene, settings: Settings, parameter: &str) -> Result<Vec<RunPoint>, String> {
    let mut work = scene.clone();
    let mut stabilizer = Stabilizer::new(settings).map_err(|e| e.to_string())?;
    let start = Instant::now();
    let report = stabilizer.stabilize(&mut work).map_err(|e| e.to_string())?;
    let seconds = start.elapsed().as_secs_f64();
    Ok(vec![RunPoint {
        parameter: parameter.to_string(),
        seconds,
        scene: work,
        iterations: report.passes,
        status: report.status.name().to_string(),
        largest_island_rows: report
            .pass_reports
            .iter()
            .flat_map(|p| &p.solved)
            .map(|island| island.constraints)
            .max()
            .unwrap_or(0),
        rows_solved: report
            .pass_reports
            .iter()
            .flat_map(|p| &p.solved)
            .map(|island| island.constraints)
            .sum(),
    }])
}
