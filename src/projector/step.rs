//! One projection step (linearize, solve, line search, apply) and the loop
//! of steps for a single provider.
//!
//! A step at configuration `q`:
//! 1. measure the true constraints; if the deepest penetration is within
//!    `tolerance`, stop (nothing is touched);
//! 2. linearize: rows `phi_k + J_k dq >= target`;
//! 3. solve the projection QP for `dq` (see [`crate::solver`]) and scale it
//!    into the trust region ([`super::trust_region`]);
//! 4. line search along `dq` ([`super::line_search`]) and apply the accepted
//!    step, or leave `q` unchanged and report a stall.

use std::time::Instant;

use nalgebra::{DVector, Matrix3};

use super::consistent_equalities::consistent_equalities;
use super::friction::friction_cones;
use super::friction_rows::{FrictionalQp, seed, solve_generating_rows};
use super::line_search::{LineSearchOutcome, line_search};
use super::trust_region::TrustRegion;
use crate::settings::{FrictionModel, FrictionRows, ResolvedLengths, Settings};

use crate::rows::{
    BodyInertia, BodyState, ConstraintProvider, ConstraintRow, Measurement, RowKind,
};
use crate::solver::friction_cone::CONE_DIM;
use crate::solver::{
    BodyMetric, JacobianRow, KeptAnalyses, ProjectionQp, ProjectionSolution, SolverError,
    solve_projection_kept,
};

/// What a step did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepOutcome {
    /// No penetration beyond the tolerance: nothing was done.
    AlreadySatisfied,
    /// A step was accepted and applied.
    Moved,
    /// The line search found no acceptable step; nothing was applied.
    Stalled,
}

/// The record of one projection step.
#[derive(Debug, Clone)]
pub struct StepReport {
    /// What happened.
    pub outcome: StepOutcome,
    /// Number of linearized constraints.
    pub constraints: usize,
    /// The solver's result (`None` when nothing was solved).
    pub solution: Option<ProjectionSolution>,
    /// Factor in (0, 1] by which the trust region scaled the solver's
    /// correction (1 when nothing was solved or no limit was reached).
    pub trust_scale: f64,
    /// Accepted step length along the scaled correction (`None` when
    /// nothing was applied).
    pub alpha: Option<f64>,
    /// Trial configurations measured by the line search.
    pub line_search_trials: usize,
    /// Deepest penetration before the step.
    pub depth_before: f64,
    /// Deepest penetration after the step (equal to before if not moved).
    pub depth_after: f64,
    /// Largest equality error (a joint's) before the step.
    pub equality_error_before: f64,
    /// Largest equality error after the step (equal to before if not moved).
    pub equality_error_after: f64,
    /// Mass-weighted length of the applied correction,
    /// `alpha trust_scale sqrt(dq^T M dq)`.
    pub displacement: f64,
    /// Wall time of linearization and solver, seconds.
    pub solve_seconds: f64,
    /// Wall time of the line search, seconds.
    pub line_search_seconds: f64,
}

/// Final status of [`project`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProjectionStatus {
    /// No penetration beyond the tolerance remains.
    Converged,
    /// `max_passes` steps were taken and a penetration remains.
    StepLimit,
    /// A line search found no acceptable step.
    Stalled,
}

/// The record of [`project`].
#[derive(Debug, Clone)]
pub struct ProjectionSummary {
    /// How the loop ended.
    pub status: ProjectionStatus,
    /// One report per step taken (including the final check).
    pub steps: Vec<StepReport>,
}

/// A step solved but not yet taken: the correction and what the line search
/// needs. [`plan_step`] makes it, [`take_step`] searches along it; in between
/// the caller may look at the multipliers (the stabilizer checks whether
/// bodies held still would be pushed).
#[derive(Debug, Clone)]
pub struct PlannedStep {
    /// The constraints measured at the configuration.
    pub before: Measurement,
    /// The solver's result.
    pub solution: ProjectionSolution,
    /// The linearized constraints.
    pub rows: Vec<ConstraintRow>,
    /// The problem solved: the rows, then the friction pyramid's rows
    /// (or the friction cones).
    pub qp: ProjectionQp,
    /// For each multiplier of `qp` (a row, or one of the three of a cone),
    /// the index in `rows` of its contact row.
    pub qp_parents: Vec<usize>,
    /// Factor by which the trust region scaled the solver's correction.
    pub trust_scale: f64,
    /// The scaled correction.
    pub dq: DVector<f64>,
    /// Wall time of linearization and solver, seconds.
    pub solve_seconds: f64,
}

/// What [`plan_step`] found.
#[derive(Debug, Clone)]
pub enum Plan {
    /// No penetration or equality error beyond the tolerance: nothing to
    /// do. Holds the measurement.
    Satisfied(Measurement),
    /// A correction to search along.
    Step(Box<PlannedStep>),
}

/// Measures, linearizes and solves at `configuration` (not moved). With
/// `hold_rows`, the rows within the tolerance of contact but short of the
/// target margin hold their value (`held_rows`) instead of asking for
/// the margin.
pub fn plan_step<P: ConstraintProvider + ?Sized>(
    provider: &mut P,
    configuration: &[BodyState],
    inertias: &[BodyInertia],
    settings: &Settings,
    lengths: &ResolvedLengths,
    hold_rows: bool,
) -> Result<Plan, SolverError> {
    plan_step_warm(
        provider,
        configuration,
        inertias,
        settings,
        lengths,
        hold_rows,
        &|_, _, _| None,
        None,
    )
}

/// The solver's warm start of a planned problem: given the provider after
/// its linearization, the problem and, for each multiplier, the index of
/// its row ([`PlannedStep::qp_parents`]), multipliers to start from.
pub type WarmStartOf<'a, P> = dyn Fn(&P, &ProjectionQp, &[usize]) -> Option<DVector<f64>> + 'a;

/// [`plan_step`] with the solver started from the multipliers `warm`
/// gives for the problem, and the sparse analyses kept in `kept`
/// (`crate::solver::solve_projection_kept`).
#[allow(clippy::too_many_arguments)]
pub fn plan_step_warm<P: ConstraintProvider + ?Sized>(
    provider: &mut P,
    configuration: &[BodyState],
    inertias: &[BodyInertia],
    settings: &Settings,
    lengths: &ResolvedLengths,
    hold_rows: bool,
    warm: &WarmStartOf<'_, P>,
    kept: Option<&KeptAnalyses>,
) -> Result<Plan, SolverError> {
    let before = provider.measure(configuration);
    let worst_before = before.worst_violation();
    if worst_before <= lengths.tolerance {
        return Ok(Plan::Satisfied(before));
    }
    let solve_start = Instant::now();
    let rows = provider.linearize(configuration);
    log::debug!(
        "  linearized: {} rows ({} equalities, {} with friction), deepest penetration {:.3e}, largest equality error {:.3e}",
        rows.len(),
        rows.iter()
            .filter(|row| row.kind == RowKind::Equality)
            .count(),
        rows.iter().filter(|row| row.friction.is_some()).count(),
        before.deepest_penetration(),
        before.largest_equality_error()
    );
    let held = hold_rows
        .then(|| held_rows(&rows, lengths.tolerance, lengths.target_margin))
        .flatten();
    let jointed = rows.iter().any(|row| row.kind == RowKind::Equality);
    let (with_cones, order, cone_parents) = projection_qp_with_cones(
        configuration,
        inertias,
        held.as_deref().unwrap_or(&rows),
        lengths.target_margin,
        settings.friction_directions,
        if jointed {
            settings.joint_rotation_weight
        } else {
            0.0
        },
    );
    let with_cones = match provider.equalities_may_be_redundant() {
        true => match consistent_equalities(&with_cones)? {
            Some((consistent, removed)) => {
                log::debug!(
                    "  a loop of joints: equality rows made consistent before solving (a change of {removed:.3e})"
                );
                consistent
            }
            None => with_cones,
        },
        false => with_cones,
    };
    let cone_rows = cone_rows(&order, &cone_parents);
    let model = settings.friction_model;
    // Without cones the problem is its own pyramid: no copy.
    let (qp, qp_parents, with_cones) = if with_cones.cones.is_empty() {
        (with_cones, order, None)
    } else {
        let (qp, qp_parents) = model_qp(&with_cones, order, &cone_parents, model);
        (qp, qp_parents, Some(with_cones))
    };
    let warm = warm(provider, &qp, &qp_parents);
    let problem = FrictionalQp {
        with_cones: with_cones.as_ref().unwrap_or(&qp),
        cone_rows: &cone_rows,
        full: &qp,
        model,
    };
    let solution = solve_or_make_consistent(&problem, settings, warm.as_ref(), kept)?;
    let qp = match solution.1 {
        Some(consistent) => consistent,
        None => qp,
    };
    let solution = solution.0;
    let trust_scale = TrustRegion::of(settings).scale(&solution.dq, inertias, worst_before);
    let dq = &solution.dq * trust_scale;
    Ok(Plan::Step(Box::new(PlannedStep {
        before,
        rows,
        qp,
        qp_parents,
        trust_scale,
        dq,
        solve_seconds: solve_start.elapsed().as_secs_f64(),
        solution,
    })))
}

/// Solves the frictional problem ([`solve_frictional`]); when every solver
/// fails on a problem with equality rows, solves it again with its
/// equalities made consistent ([`consistent_equalities`]), and returns
/// that problem (in the layout of `problem.full`) with the answer.
fn solve_or_make_consistent(
    problem: &FrictionalQp<'_>,
    settings: &Settings,
    warm: Option<&DVector<f64>>,
    kept: Option<&KeptAnalyses>,
) -> Result<(ProjectionSolution, Option<ProjectionQp>), SolverError> {
    match solve_frictional(problem, settings, warm, kept) {
        Ok(solution) => Ok((solution, None)),
        Err(error) => match consistent_equalities(problem.with_cones)? {
            Some((consistent, removed)) => {
                log::debug!(
                    "  not solved ({error}); equality rows made consistent (a change of {removed:.3e} that no first-order motion reaches) and solved again"
                );
                let order: Vec<usize> = (0..consistent.num_rows()).collect();
                let (full, _) = model_qp(&consistent, order, &[], problem.model);
                let retry = FrictionalQp {
                    with_cones: &consistent,
                    full: &full,
                    ..*problem
                };
                let solution = solve_frictional(&retry, settings, None, kept)?;
                Ok((solution, Some(full)))
            }
            None => Err(error),
        },
    }
}

/// Solves the full problem `problem.full` as it is
/// ([`FrictionRows::All`]), or by generating its friction rows
/// ([`super::friction_rows`]), from all of them ([`FrictionRows::Implied`])
/// or from the rows whose friction held in `warm`
/// ([`FrictionRows::Generated`]).
fn solve_frictional(
    problem: &FrictionalQp<'_>,
    settings: &Settings,
    warm: Option<&DVector<f64>>,
    kept: Option<&KeptAnalyses>,
) -> Result<ProjectionSolution, SolverError> {
    match settings.friction_rows {
        FrictionRows::All => {
            // Multipliers of linear rows only start a solver (module docs of
            // `super::friction_rows`).
            let warm = warm.filter(|_| problem.full.cones.is_empty());
            solve_projection_kept(problem.full, &settings.solver, warm, kept)
        }
        FrictionRows::Implied | FrictionRows::Generated => {
            let working = match settings.friction_rows {
                FrictionRows::Implied => vec![true; problem.with_cones.cones.len()],
                _ => seed(problem, warm, settings.solver.auto_lemke_max_rows),
            };
            let (solution, generation) =
                solve_generating_rows(problem, &settings.solver, warm, working, kept)?;
            if generation.cones > 0 {
                log::debug!(
                    "  friction rows generated: {} of {} rows with friction in {} rounds{}",
                    generation.generated,
                    generation.cones,
                    generation.rounds,
                    if generation.full_solve {
                        ", the last on the full problem"
                    } else {
                        ""
                    }
                );
            }
            Ok(solution)
        }
    }
}

impl StepReport {
    /// The report of a step that found nothing to do at `measurement`.
    pub fn satisfied(measurement: &Measurement) -> Self {
        let depth = measurement.deepest_penetration();
        let equality_error = measurement.largest_equality_error();
        StepReport {
            outcome: StepOutcome::AlreadySatisfied,
            constraints: 0,
            solution: None,
            trust_scale: 1.0,
            alpha: None,
            line_search_trials: 0,
            depth_before: depth,
            depth_after: depth,
            equality_error_before: equality_error,
            equality_error_after: equality_error,
            displacement: 0.0,
            solve_seconds: 0.0,
            line_search_seconds: 0.0,
        }
    }
}

/// Line search along a planned step; moves `configuration` in place if a
/// step is accepted.
pub fn take_step<P: ConstraintProvider + ?Sized>(
    provider: &mut P,
    configuration: &mut Vec<BodyState>,
    plan: PlannedStep,
    settings: &Settings,
    lengths: &ResolvedLengths,
) -> StepReport {
    let PlannedStep {
        before,
        solution,
        rows,
        trust_scale,
        dq,
        solve_seconds,
        ..
    } = plan;
    let constraints = rows.len();
    let mut report = StepReport {
        outcome: StepOutcome::Stalled,
        constraints,
        trust_scale,
        solve_seconds,
        ..StepReport::satisfied(&before)
    };
    let line_search_start = Instant::now();
    let search = line_search(
        provider,
        configuration,
        &dq,
        &before,
        lengths.tolerance,
        lengths.allowed_penetration,
        &settings.line_search,
    );
    match search {
        LineSearchOutcome::Accepted {
            alpha,
            trials,
            configuration: moved,
            measurement,
        } => {
            report.outcome = StepOutcome::Moved;
            report.alpha = Some(alpha);
            report.line_search_trials = trials;
            report.depth_after = measurement.deepest_penetration();
            report.equality_error_after = measurement.largest_equality_error();
            report.displacement = alpha * trust_scale * solution.residuals.displacement;
            *configuration = moved;
        }
        LineSearchOutcome::Rejected { trials } => {
            report.line_search_trials = trials;
        }
    }
    report.line_search_seconds = line_search_start.elapsed().as_secs_f64();
    let (largest_dx, largest_dtheta) = largest_motions(&dq);

    log::debug!(
        "  step: {} rows, {:?}, trust scale {:.3e}, largest |dx| {:.3e} |dtheta| {:.3e}, alpha {:?} after {} trials, depth {:.3e} -> {:.3e}, equality error {:.3e} -> {:.3e}",
        report.constraints,
        solution.solver,
        report.trust_scale,
        largest_dx,
        largest_dtheta,
        report.alpha,
        report.line_search_trials,
        report.depth_before,
        report.depth_after,
        report.equality_error_before,
        report.equality_error_after
    );
    report.solution = Some(solution);
    report
}

/// The largest translation and rotation of one body in a correction.
fn largest_motions(dq: &DVector<f64>) -> (f64, f64) {
    (0..dq.len() / 6).fold((0.0, 0.0), |(dx, dtheta): (f64, f64), i| {
        (
            dx.max(dq.fixed_rows::<3>(6 * i).norm()),
            dtheta.max(dq.fixed_rows::<3>(6 * i + 3).norm()),
        )
    })
}

/// One projection step on `configuration` (moved in place only if a step is
/// accepted): [`plan_step`], then [`take_step`], the rows in contact held
/// when `settings.hold_open_gaps` is set. On a solver error the
/// configuration is unchanged.
pub fn projection_step<P: ConstraintProvider + ?Sized>(
    provider: &mut P,
    configuration: &mut Vec<BodyState>,
    inertias: &[BodyInertia],
    settings: &Settings,
    lengths: &ResolvedLengths,
) -> Result<StepReport, SolverError> {
    let hold_rows = settings.hold_open_gaps;
    Ok(
        match plan_step(
            provider,
            configuration,
            inertias,
            settings,
            lengths,
            hold_rows,
        )? {
            Plan::Satisfied(measurement) => StepReport::satisfied(&measurement),
            Plan::Step(plan) => take_step(provider, configuration, *plan, settings, lengths),
        },
    )
}

/// Projection steps ([`projection_step`]) until no penetration beyond the
/// tolerance remains, a step stalls, or `settings.max_passes` steps moved.
pub fn project<P: ConstraintProvider + ?Sized>(
    provider: &mut P,
    configuration: &mut Vec<BodyState>,
    inertias: &[BodyInertia],
    settings: &Settings,
    lengths: &ResolvedLengths,
) -> Result<ProjectionSummary, SolverError> {
    let max_steps = settings.max_passes;
    let mut steps = Vec::new();
    for _ in 0..=max_steps {
        let report = projection_step(provider, configuration, inertias, settings, lengths)?;
        let outcome = report.outcome;
        steps.push(report);
        let status = match outcome {
            StepOutcome::AlreadySatisfied => ProjectionStatus::Converged,
            StepOutcome::Stalled => ProjectionStatus::Stalled,
            StepOutcome::Moved if steps.len() > max_steps => ProjectionStatus::StepLimit,
            StepOutcome::Moved => continue,
        };
        return Ok(ProjectionSummary { status, steps });
    }
    Ok(ProjectionSummary {
        status: ProjectionStatus::StepLimit,
        steps,
    })
}

/// The rows with a value `phi` within the tolerance of contact but short of
/// the target margin (`-tolerance <= phi < target`) made to hold it: their
/// `phi` raised to the target, so that the linearized row reads
/// `J dq >= 0` (the contact may open, not close), and their friction apex
/// where they are (`r = 0`: no sliding without opening). `None` when no row
/// is such. Asking every row for the target margin makes a box pressed
/// between two walls that touch it (an exactly fitting slot) infeasible:
/// both walls ask the box to move away from them (Lemke's ray, clarabel's
/// infeasibility certificate), and the box stays sunk in the floor. Rows
/// deeper than the tolerance still aim at the
/// target margin, which covers the linearization's second-order error.
pub fn held_rows(
    rows: &[ConstraintRow],
    tolerance: f64,
    target: f64,
) -> Option<Vec<ConstraintRow>> {
    let holds = |row: &ConstraintRow| {
        row.kind == RowKind::Inequality && row.phi >= -tolerance && row.phi < target
    };
    rows.iter().any(holds).then(|| {
        rows.iter()
            .map(|row| {
                let mut row = row.clone();
                if holds(&row) {
                    row.phi = target;
                }
                row
            })
            .collect()
    })
}

/// The projection QP of `rows` at `configuration`: the rows with target
/// `target_margin` (equality rows, which come first, with target 0), then
/// the friction pyramid of the rows with friction (target 0;
/// [`super::friction`]) or their cones; and for each of its multipliers
/// the index of its row in `rows`. Equality rows after an inequality row
/// are a provider's error: they are moved first, keeping their order, and
/// the parents follow.
pub fn projection_qp(
    configuration: &[BodyState],
    inertias: &[BodyInertia],
    rows: &[ConstraintRow],
    target_margin: f64,
    friction_directions: usize,
    friction_model: FrictionModel,
) -> (ProjectionQp, Vec<usize>) {
    projection_qp_weighted(
        configuration,
        inertias,
        rows,
        target_margin,
        friction_directions,
        friction_model,
        0.0,
    )
}

/// [`projection_qp`] with each body's rotational metric `I + w (tr I / 2)
/// Id` (`w = rotation_weight`: [`Settings::joint_rotation_weight`] in
/// islands with joints, 0 elsewhere).
pub fn projection_qp_weighted(
    configuration: &[BodyState],
    inertias: &[BodyInertia],
    rows: &[ConstraintRow],
    target_margin: f64,
    friction_directions: usize,
    friction_model: FrictionModel,
    rotation_weight: f64,
) -> (ProjectionQp, Vec<usize>) {
    let (qp, order, cone_parents) = projection_qp_with_cones(
        configuration,
        inertias,
        rows,
        target_margin,
        friction_directions,
        rotation_weight,
    );
    model_qp(&qp, order, &cone_parents, friction_model)
}

/// The projection QP of `rows` with a friction cone per row with friction
/// (the rows in the order of [`projection_qp`], the cones in the order of
/// their rows), the index in `rows` of each of its rows, and the index in
/// `rows` of each cone's row.
fn projection_qp_with_cones(
    configuration: &[BodyState],
    inertias: &[BodyInertia],
    rows: &[ConstraintRow],
    target_margin: f64,
    friction_directions: usize,
    rotation_weight: f64,
) -> (ProjectionQp, Vec<usize>, Vec<usize>) {
    let bodies = configuration
        .iter()
        .zip(inertias)
        .map(|(state, inertia)| {
            let world = inertia.inertia_world(&state.rotation);
            let floor = rotation_weight * 0.5 * world.trace();
            BodyMetric {
                mass: inertia.mass,
                inertia_world: world + Matrix3::identity() * floor,
            }
        })
        .collect();
    let mut order: Vec<usize> = (0..rows.len()).collect();
    order.sort_by_key(|&i| rows[i].kind != RowKind::Equality);
    let num_equalities = rows
        .iter()
        .filter(|row| row.kind == RowKind::Equality)
        .count();
    let (cones, cone_parents) = friction_cones(rows, target_margin);
    let target = |row: &ConstraintRow| match row.kind {
        RowKind::Equality => 0.0,
        RowKind::Inequality => target_margin,
    };
    let qp = ProjectionQp {
        bodies,
        rows: order
            .iter()
            .map(|&i| JacobianRow {
                blocks: rows[i].blocks.clone(),
            })
            .collect(),
        phi: order.iter().map(|&i| rows[i].phi).collect(),
        target: order.iter().map(|&i| target(&rows[i])).collect(),
        num_equalities,
        cones,
        cone_facets: friction_directions,
    };
    (qp, order, cone_parents)
}

/// The problem of `friction_model` from a problem with cones (`qp`, its
/// rows from `rows[order[i]]`, its cones from `rows[cone_parents[c]]`):
/// `qp` itself for the cone, its pyramid for the pyramid; and for each of
/// its multipliers the index of its row in `rows`.
fn model_qp(
    qp: &ProjectionQp,
    order: Vec<usize>,
    cone_parents: &[usize],
    friction_model: FrictionModel,
) -> (ProjectionQp, Vec<usize>) {
    let n = qp.num_rows();
    let mut parents = order;
    let cone_parent = |c: usize| cone_parents.get(c).copied().unwrap_or(n + c);
    match friction_model {
        FrictionModel::Cone => {
            parents.extend((0..qp.cones.len()).flat_map(|c| [cone_parent(c); CONE_DIM]));
            (qp.clone(), parents)
        }
        FrictionModel::Pyramid => {
            let (pyramid, origins) = qp.pyramid();
            parents.extend(origins[n..].iter().map(|&c| cone_parent(c - n)));
            (pyramid, parents)
        }
    }
}

/// The index in the problem's rows of each cone's row: the position of
/// `cone_parents[c]` in `order`.
fn cone_rows(order: &[usize], cone_parents: &[usize]) -> Vec<usize> {
    let mut position = vec![usize::MAX; order.len()];
    for (i, &row) in order.iter().enumerate() {
        position[row] = i;
    }
    cone_parents.iter().map(|&row| position[row]).collect()
}
