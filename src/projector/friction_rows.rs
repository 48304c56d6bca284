//! The friction rows of a projection generated as they are needed (row
//! generation, lazy constraints): the frictional QP's exact minimizer from
//! a sequence of smaller problems.
//!
//! The frictional problem `F` is the projection QP with, for every row with
//! friction `c`, its pyramid's `K` facets (eq. (2) of [`super::friction`])
//! or its cone (eq. (1)). For a working set `W` of rows with friction, the
//! relaxation `F_W` keeps every row, and the friction of the rows in `W`
//! only (under the pyramid the facets of a row in `W` replace the row: they
//! imply it, since their sum is `K` times it). Every constraint of `F_W` is
//! one of `F`'s, so its feasible set contains `F`'s and its minimum is at
//! most `F`'s. Hence:
//!
//! - **Exactness.** If the minimizer `dq_W` of `F_W` satisfies the friction
//!   of every row outside `W`, it is feasible for `F` and no feasible point
//!   of `F` costs less: it is `F`'s minimizer (unique, `M` positive
//!   definite). Its multipliers, with zeros for the constraints left out
//!   (and for a pyramid row replaced by its facets), satisfy `F`'s KKT
//!   conditions: the forces are the same.
//! - **Infeasibility.** If `F_W` has no solution, neither has `F`: a
//!   certificate on the relaxation is one on the full problem, so the typed
//!   outcomes (a frictional island certified infeasible, then solved
//!   without friction by the stabilizer) are unchanged.
//! - **Termination.** Each round adds every row whose friction is violated
//!   at `dq_W` (by more than [`GENERATION_SLACK`] times the acceptance
//!   feasibility, `tol_residual L`), at least one, so at most `C + 1`
//!   rounds for `C` rows with friction; after [`MAX_ROUNDS`] the full
//!   problem is solved as it is.
//!
//! The answer is then checked on the full problem with the solvers' own
//! acceptance test ([`crate::solver::ProjectionResiduals::acceptance`] at
//! most `tol_residual`); should it fail, the full problem is solved as it
//! is. The left-out facets' violation bound `GENERATION_SLACK tol_residual
//! L` keeps the answer's feasibility on the full problem well inside that
//! test.
//!
//! **Why.** Wherever the frictionless answer slides nothing, it is the
//! answer with friction ([`super::friction`]), and the full problem, `K`
//! rows per contact under the pyramid, costs Lemke about `K^3` and
//! clarabel about `K` times the frictionless problem. Only the rows that
//! slide need friction; the first working set is [`seed`]'s. Measured on
//! the engine states, the frictionless answer slides nearly every contact,
//! and generating costs about what it saves: a setting
//! ([`crate::FrictionRows::Generated`]), not the default
//! (`benchmarks/results/engine_friction.md`).

use nalgebra::DVector;

use crate::settings::FrictionModel;
use crate::solver::friction_cone::{CONE_DIM, cone_violation, facet_values};
use crate::solver::residuals::{acceptance_length, projection_residuals};
use crate::solver::{
    FrictionCone, KeptAnalyses, ProjectionQp, ProjectionSolution, SolverError, SolverSettings,
    solve_projection_kept,
};

/// A left-out row's friction counts as violated when it is more than this
/// fraction of the acceptance feasibility (`tol_residual L`) from holding
/// (module docs): far enough above rounding not to add facets that hold,
/// far enough below the acceptance test that the answer passes it on the
/// full problem.
pub const GENERATION_SLACK: f64 = 1e-2;

/// Rounds of row generation before the full problem is solved as it is
/// (module docs, "Termination").
pub const MAX_ROUNDS: usize = 8;

/// When the first working set holds at least this fraction of the rows
/// with friction, or at least this fraction of the rows left out of the
/// working set have their friction violated, the round takes every row's
/// friction (the full problem, less the pyramid's redundant rows): the
/// rows that slide are then most of them, and a further round would cost
/// about as much as the full problem again.
pub const ADD_ALL_FRACTION: f64 = 0.5;

/// The frictional problem of one step: the rows with their cones, and the
/// row of each cone.
pub struct FrictionalQp<'a> {
    /// The rows and a cone per row with friction ([`ProjectionQp::cones`]).
    pub with_cones: &'a ProjectionQp,
    /// For each cone, the index of its contact row in `with_cones.rows`.
    pub cone_rows: &'a [usize],
    /// The full problem that is solved: `with_cones` (cone model) or its
    /// pyramid ([`ProjectionQp::pyramid`]): rows, then per cone its `K`
    /// facets or its three multipliers.
    pub full: &'a ProjectionQp,
    /// Which of the two `full` is.
    pub model: FrictionModel,
}

/// What [`solve_generating_rows`] did, for the log and the report.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Generation {
    /// Problems solved (1: the first working set was enough).
    pub rounds: usize,
    /// Rows whose friction entered the last problem solved, of
    /// [`Generation::cones`].
    pub generated: usize,
    /// Rows with friction.
    pub cones: usize,
    /// The full problem was solved as it is (after [`MAX_ROUNDS`], or
    /// because the answer failed the acceptance test on it).
    pub full_solve: bool,
}

/// The first working set: the rows with friction whose multipliers in
/// `warm` (in the layout of `problem.full`) are not all zero, the row's
/// own or its friction's (the rows that pressed or held by friction in the
/// previous answer, those whose friction is likely to be needed again).
/// Without such a row, none when the frictionless problem is Lemke's
/// (at most `lemke_max_rows` rows: a round on the rows alone costs about
/// `1 / (K + 1)^3` of one with every facet), every one when it is
/// clarabel's (whose time grows about linearly with the rows, so that a
/// first round without friction would cost about `1 / K` of the full
/// problem, and on the engine states most rows' friction is needed:
/// `benchmarks/results/engine_friction.md`).
pub fn seed(
    problem: &FrictionalQp<'_>,
    warm: Option<&DVector<f64>>,
    lemke_max_rows: usize,
) -> Vec<bool> {
    let cones = problem.with_cones.cones.len();
    let mut working = vec![false; cones];
    if let Some(warm) = warm.filter(|w| w.len() == problem.full.num_multipliers()) {
        let n = problem.with_cones.num_rows();
        let per_cone = multipliers_per_cone(problem);
        for (c, work) in working.iter_mut().enumerate() {
            let row = warm.get(problem.cone_rows[c]).is_some_and(|&x| x != 0.0);
            *work = row
                || warm
                    .rows(n + c * per_cone, per_cone)
                    .iter()
                    .any(|&x| x != 0.0);
        }
    }
    if !working.contains(&true) && problem.with_cones.num_rows() > lemke_max_rows {
        working.iter_mut().for_each(|w| *w = true);
    }
    working
}

/// The minimizer of `problem.full` by row generation (module docs), started
/// from the working set `working` (one flag per cone), with the
/// multipliers in `problem.full`'s layout. `warm` (that layout too) is
/// passed on to the solver, restricted to each round's problem, when that
/// problem has linear rows only; every round's solve uses the sparse
/// analyses kept in `kept`.
pub fn solve_generating_rows(
    problem: &FrictionalQp<'_>,
    settings: &SolverSettings,
    warm: Option<&DVector<f64>>,
    mut working: Vec<bool>,
    kept: Option<&KeptAnalyses>,
) -> Result<(ProjectionSolution, Generation), SolverError> {
    let cones = problem.with_cones.cones.len();
    // A working set of another problem's length: no row's friction first.
    working.resize(cones, false);
    // The solvers take multipliers of linear rows only (the augmented
    // Lagrangian's warm start): a problem with cones is given none (its
    // multipliers seed the working set, `seed`).
    let start = |qp: &ProjectionQp, origin: Option<&[usize]>| {
        let warm =
            warm.filter(|w| w.len() == problem.full.num_multipliers() && qp.cones.is_empty())?;
        Some(match origin {
            Some(origin) => DVector::from_iterator(origin.len(), origin.iter().map(|&i| warm[i])),
            None => warm.clone(),
        })
    };
    let mut generation = Generation {
        cones,
        ..Generation::default()
    };
    let full_solve = |mut generation: Generation| {
        generation.full_solve = true;
        generation.generated = cones;
        generation.rounds += 1;
        let warm = start(problem.full, None);
        solve_projection_kept(problem.full, settings, warm.as_ref(), kept).map(|s| (s, generation))
    };
    if cones == 0 || settings.cross_check {
        return full_solve(generation);
    }
    if most(working.iter().filter(|&&w| w).count(), cones) {
        working.iter_mut().for_each(|w| *w = true);
    }
    let slack = GENERATION_SLACK * settings.tol_residual * acceptance_length(problem.full);
    let mut iterations = 0;
    let mut fallbacks = Vec::new();
    while generation.rounds < MAX_ROUNDS {
        let relaxed = relaxation(problem, &working);
        let relaxed_warm = start(&relaxed.qp, Some(&relaxed.origin));
        generation.rounds += 1;
        generation.generated = working.iter().filter(|&&w| w).count();
        let solution = solve_projection_kept(&relaxed.qp, settings, relaxed_warm.as_ref(), kept)?;
        iterations += solution.iterations;
        fallbacks.extend(solution.fallbacks.iter().cloned());
        let violated = violated_cones(problem, &working, &solution.dq, slack);
        log::debug!(
            "  friction rows, round {}: {} of {} rows with friction in the problem ({} rows), {} more violated",
            generation.rounds,
            generation.generated,
            cones,
            relaxed.qp.num_rows(),
            violated.len()
        );
        if violated.is_empty() {
            let lambda = relaxed.scatter(&solution.lambda, problem.full.num_multipliers());
            let metric = problem.full.validate()?;
            let residuals = projection_residuals(problem.full, &metric, &solution.dq, &lambda);
            let residual = residuals.acceptance();
            if residual.is_nan() || residual > settings.tol_residual {
                log::debug!(
                    "  friction rows: the answer fails the full problem's acceptance ({residual:.2e}); solving it as it is"
                );
                return full_solve(generation);
            }
            let solution = ProjectionSolution {
                lambda,
                residuals,
                iterations,
                fallbacks,
                ..solution
            };
            return Ok((solution, generation));
        }
        let left_out = working.iter().filter(|&&w| !w).count();
        if most(violated.len(), left_out) {
            working.iter_mut().for_each(|w| *w = true);
        } else {
            for c in violated {
                working[c] = true;
            }
        }
    }
    log::debug!("  friction rows: {MAX_ROUNDS} rounds; solving the full problem as it is");
    full_solve(generation)
}

/// Whether `part` of `whole` rows is at least [`ADD_ALL_FRACTION`] of
/// them: then every row's friction is taken.
fn most(part: usize, whole: usize) -> bool {
    part as f64 >= ADD_ALL_FRACTION * whole as f64
}

/// Multipliers per cone in `problem.full`: `K` facets or the cone's three.
fn multipliers_per_cone(problem: &FrictionalQp<'_>) -> usize {
    match problem.model {
        FrictionModel::Pyramid => problem.with_cones.cone_facets,
        FrictionModel::Cone => CONE_DIM,
    }
}

/// A relaxation `F_W` and, for each of its multipliers, the index of the
/// same multiplier in the full problem.
struct Relaxation {
    qp: ProjectionQp,
    origin: Vec<usize>,
}

impl Relaxation {
    /// The relaxation's multipliers in the full problem's layout (zeros
    /// for the constraints left out).
    fn scatter(&self, lambda: &DVector<f64>, len: usize) -> DVector<f64> {
        let mut full = DVector::zeros(len);
        for (&i, &value) in self.origin.iter().zip(lambda.iter()) {
            full[i] = value;
        }
        full
    }
}

/// `F_W` (module docs): every row, except under the pyramid the rows of the
/// working cones, which their facets replace; the working cones or their
/// facets.
fn relaxation(problem: &FrictionalQp<'_>, working: &[bool]) -> Relaxation {
    let base = problem.with_cones;
    let n = base.num_rows();
    let working_cones = || base.cones.iter().enumerate().filter(|(c, _)| working[*c]);
    match problem.model {
        FrictionModel::Cone => {
            let mut origin: Vec<usize> = (0..n).collect();
            let mut cones = Vec::new();
            for (c, cone) in working_cones() {
                cones.push(cone.clone());
                origin.extend((0..CONE_DIM).map(|d| n + CONE_DIM * c + d));
            }
            Relaxation {
                qp: ProjectionQp {
                    bodies: base.bodies.clone(),
                    rows: base.rows.clone(),
                    phi: base.phi.clone(),
                    target: base.target.clone(),
                    cones,
                    cone_facets: base.cone_facets,
                    num_equalities: base.num_equalities,
                },
                origin,
            }
        }
        FrictionModel::Pyramid => {
            let k = base.cone_facets;
            let mut replaced = vec![false; n];
            for (c, _) in working_cones() {
                replaced[problem.cone_rows[c]] = true;
            }
            let mut qp = ProjectionQp {
                bodies: base.bodies.clone(),
                cone_facets: k,
                num_equalities: base.num_equalities,
                ..ProjectionQp::default()
            };
            let mut origin = Vec::new();
            for i in (0..n).filter(|&i| !replaced[i]) {
                qp.rows.push(base.rows[i].clone());
                qp.phi.push(base.phi[i]);
                qp.target.push(base.target[i]);
                origin.push(i);
            }
            for (c, cone) in working_cones() {
                for (f, (row, phi)) in cone.facets(k).into_iter().enumerate() {
                    qp.rows.push(row);
                    qp.phi.push(phi);
                    qp.target.push(0.0);
                    origin.push(n + c * k + f);
                }
            }
            Relaxation { qp, origin }
        }
    }
}

/// The cones outside the working set whose friction `dq` violates by more
/// than `slack` (a length): under the pyramid its most violated facet,
/// under the cone model the cone itself.
fn violated_cones(
    problem: &FrictionalQp<'_>,
    working: &[bool],
    dq: &DVector<f64>,
    slack: f64,
) -> Vec<usize> {
    let k = problem.with_cones.cone_facets;
    problem
        .with_cones
        .cones
        .iter()
        .enumerate()
        .filter(|(c, _)| !working[*c])
        .filter(|(_, cone)| friction_violation(cone, problem.model, k, dq) > slack)
        .map(|(c, _)| c)
        .collect()
}

/// How far `dq` is from satisfying `cone`'s friction under `model` (0 when
/// it does).
fn friction_violation(
    cone: &FrictionCone,
    model: FrictionModel,
    k: usize,
    dq: &DVector<f64>,
) -> f64 {
    let w = cone.value(dq);
    match model {
        FrictionModel::Cone => cone_violation(&w),
        FrictionModel::Pyramid => facet_values(w, k).map(|value| -value).fold(0.0, f64::max),
    }
}
