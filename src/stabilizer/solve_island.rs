//! One projection step for one island, computed without touching the
//! scene; the caller applies the results in island order.
//!
//! The step moves the island's [`Region`]: the bodies that still penetrate,
//! grown while the answer pushes bodies held still (see [`super::region`]),
//! up to the whole island.
//!
//! **Friction.** An island whose problem with friction cannot be solved
//! (its pyramid or cones leave wedged bodies no way out: a box pressed into
//! a right-angled corner with `mu >= 1`) is solved without friction
//! ([`IslandReport::friction_dropped`]), and so is, for the rest of the
//! call, every island holding one of its bodies: the passes after the
//! first only remove what the linearization left, and each frictional
//! attempt on a wedged island is the pass's largest problem and, near
//! infeasibility, its slowest (on the MuJoCo bin of 160 boxes with
//! `mu = 1` the attempts of the later passes cost more than the whole
//! frictionless call: `benchmarks/results/engine_friction.md`).
//!
//! An island that cannot be solved (every solver failed, or its problem is
//! invalid) is not an error of the call: its solution moves nothing and
//! says why ([`IslandOutcome::Failed`]), so that the other islands and the
//! passes already made keep their progress.

use std::cell::RefCell;
use std::sync::Arc;

use crate::Error;
use crate::broad_phase::BodyPair;
use crate::contact::{Island, IslandError};
use crate::contact::{
    IslandContacts, PairQuery, PosedQuery, SceneGeometry, WarmStartCache, shape_pair,
};
use crate::geometry::ConvexPolyhedron;
use crate::projector::{Plan, PlannedStep, StepReport, plan_step_warm, take_step};
use crate::rows::{BodyInertia, BodyState};
use crate::scene::Scene;
use crate::solver::{KeptAnalyses, ProjectionQp, SolverSettings};
use crate::vclip::FeaturePair;

use super::island_constraints::IslandConstraints;
use super::joint_state::island_joints;
use super::region::{Region, pushed_bodies};
use super::report::{IslandOutcome, IslandReport};
use super::solver_warm::{MultiplierPairs, SolverWarmCache, WarmLayers};
use crate::settings::{ResolvedLengths, Settings};

/// The outcome of one island's step, to apply to the scene.
pub struct IslandSolution {
    /// What happened, for the report.
    pub report: IslandReport,
    /// New centre-of-mass states of the moved bodies (empty unless moved).
    pub states: Vec<(usize, BodyState)>,
    /// V-Clip warm starts of the solved pairs after the step (part pairs
    /// and their last feature pairs).
    pub warm_starts: Vec<(BodyPair, FeaturePair)>,
    /// The multipliers of the island's answer, for the next pass and call.
    pub solver_warm: SolverWarmCache,
    /// Narrow-phase answers at the accepted configuration (empty unless
    /// moved), for the next detection.
    pub answers: Vec<(BodyPair, PosedQuery)>,
    /// Linearization and solver time, seconds.
    pub solve_seconds: f64,
    /// Line-search time apart from its queries, seconds.
    pub line_search_seconds: f64,
    /// Time of the island's own narrow-phase queries, seconds.
    pub query_seconds: f64,
    /// Number of those queries.
    pub queries: usize,
}

impl IslandSolution {
    /// Moves the island's bodies and records the warm starts.
    /// `shapes`: the polyhedron of every part (`SceneParts::shapes`).
    pub fn apply(
        &self,
        scene: &mut Scene,
        shapes: &[Arc<ConvexPolyhedron>],
        cache: &mut WarmStartCache,
    ) -> Result<(), Error> {
        for (body, state) in &self.states {
            scene.body_mut(*body)?.set_com_pose(state.isometry())?;
        }
        for &(pair, features) in &self.warm_starts {
            cache.insert(pair, shape_pair(shapes, pair), features);
        }
        Ok(())
    }
}

/// The shared input of every island's step in one pass.
#[derive(Clone, Copy)]
pub struct PassInput<'a> {
    /// The scene at the pass's poses.
    pub scene: &'a Scene,
    /// Shapes and poses of every body.
    pub geometry: SceneGeometry<'a>,
    /// The pass's active part pairs (islands index them).
    pub active_pairs: &'a [BodyPair],
    /// The body pair of each active pair.
    pub active_bodies: &'a [BodyPair],
    /// Signed value (distance, or minus the exact depth) of each active pair.
    pub active_values: &'a [f64],
    /// Narrow-phase answer of each active pair at the pass's poses.
    pub active_queries: &'a [PairQuery],
    /// The call's settings.
    pub settings: &'a Settings,
    /// The call's lengths.
    pub lengths: &'a ResolvedLengths,
    /// Whether the rows in contact hold their value
    /// ([`crate::projector::plan_step`]'s `hold_rows`): the retry of an
    /// island that cannot be solved without it.
    pub hold_rows: bool,
    /// Whether pairs get their friction coefficients (else frictionless).
    pub frictional: bool,
    /// Per scene body: it was in an island solved without friction earlier
    /// in the call; an island holding such a body is solved without
    /// friction (module docs, "Friction").
    pub without_friction: &'a [bool],
    /// The solver's warm starts (the multipliers of the last pass, or of
    /// the last call's first pass).
    pub solver_warm: WarmLayers<'a>,
    /// The stabilizer's kept sparse analyses.
    pub kept_analyses: &'a KeptAnalyses,
}

/// One projection step on `island`; a failure moves nothing and is
/// reported in the solution.
pub fn solve_island(input: PassInput, island: &Island) -> IslandSolution {
    let dropped_before = island
        .bodies
        .iter()
        .any(|&body| input.without_friction.get(body) == Some(&true));
    let input = PassInput {
        frictional: input.frictional && !dropped_before,
        ..input
    };
    let solution = solve_island_or_fail(input, island).map(|mut solution| {
        solution.report.friction_dropped |= dropped_before;
        solution
    });
    solution.unwrap_or_else(|error| {
        log::debug!(
            "island of {} bodies (first {}) not solved: {error}",
            island.bodies.len(),
            island.bodies[0]
        );
        let depth = island
            .pairs
            .iter()
            .map(|&k| -input.active_values[k])
            .fold(0.0, f64::max);
        IslandSolution::failed(island, depth, error)
    })
}

impl IslandSolution {
    /// The solution of an island that could not be solved: nothing moves.
    fn failed(island: &Island, depth: f64, error: Error) -> Self {
        IslandSolution {
            report: IslandReport {
                bodies: island.bodies.clone(),
                joints: island.joints.clone(),
                pairs: island.pairs.len(),
                region_bodies: 0,
                region_rounds: 0,
                friction_dropped: false,
                rows_held: false,
                constraints: 0,
                solver: None,
                fallbacks: Vec::new(),
                solver_iterations: 0,
                factorizations: 0,
                warm_started: false,
                cross_check: None,
                outcome: IslandOutcome::Failed(error),
                trust_scale: 1.0,
                alpha: None,
                line_search_trials: 0,
                depth_before: depth,
                depth_after: depth,
                joint_error_before: 0.0,
                joint_error_after: 0.0,
                displacement: 0.0,
            },
            states: Vec::new(),
            warm_starts: Vec::new(),
            solver_warm: SolverWarmCache::default(),
            answers: Vec::new(),
            solve_seconds: 0.0,
            line_search_seconds: 0.0,
            query_seconds: 0.0,
            queries: 0,
        }
    }
}

/// One round of an island's step: the region's contacts and joints, its
/// configuration at the pass's poses and its plan.
struct Round<'a> {
    constraints: IslandConstraints<'a>,
    configuration: Vec<BodyState>,
    plan: Result<Plan, Error>,
    /// The keys of the last problem whose warm start was read, with its
    /// rows' parents: the step's answer is recorded under them when its
    /// problem is that one.
    warm_keys: Option<(Vec<usize>, MultiplierPairs<'a>)>,
}

/// The region's problem: its contacts (every island pair with a body in
/// the region) and the plan at the pass's poses.
fn plan_region<'a>(
    input: PassInput<'a>,
    island: &Island,
    bodies: Vec<usize>,
) -> Result<Round<'a>, Error> {
    let moving = |body: usize| bodies.binary_search(&body).is_ok();
    let region_pairs: Vec<usize> = island
        .pairs
        .iter()
        .copied()
        .filter(|&k| {
            let bodies = input.active_bodies[k];
            moving(bodies.body_a) || moving(bodies.body_b)
        })
        .collect();
    let pairs: Vec<BodyPair> = region_pairs
        .iter()
        .map(|&k| input.active_pairs[k])
        .collect();
    let answers: Vec<PairQuery> = region_pairs
        .iter()
        .map(|&k| input.active_queries[k].clone())
        .collect();
    let friction: Vec<f64> = region_pairs
        .iter()
        .map(|&k| match input.frictional {
            true => pair_friction(input.scene, input.settings, input.active_bodies[k]),
            false => 0.0,
        })
        .collect();
    let has_friction = friction.iter().any(|&mu| mu > 0.0);
    let (configuration, inertias) = island_state(input.scene, &bodies)?;
    let joints = island_joints(
        input.scene,
        &island.joints,
        &bodies,
        input.lengths.scale,
        input.lengths.contact_margin,
    )?;
    let contacts = IslandContacts::new(
        input.geometry,
        bodies,
        pairs,
        friction,
        answers,
        configuration.clone(),
        input.settings,
        input.lengths.contact_margin,
    );
    let mut constraints = IslandConstraints::new(contacts, joints);
    // A region short of the whole island has one solver and no fallback:
    // its failure only means that it must grow. A whole island with
    // friction tries the fallbacks but stops at a certificate of
    // infeasibility (a friction pyramid that leaves wedged bodies no way
    // out): the island is then solved again without friction
    // (`solve_island_or_fail`).
    let whole = contacts_cover_island(island, constraints.contacts.bodies());
    let trial_settings;
    let settings = if whole && !has_friction {
        input.settings
    } else {
        let mut solver = SolverSettings {
            fall_back: whole,
            stop_on_infeasible: true,
            ..input.settings.solver.clone()
        };
        if has_friction {
            let limit = u32::try_from(input.settings.friction_max_iterations).unwrap_or(u32::MAX);
            solver.clarabel.max_iter = solver.clarabel.max_iter.min(limit);
            let radius = &mut solver.interior_point.infeasible_radius;
            *radius = radius.min(input.settings.friction_max_correction);
        }
        trial_settings = Settings {
            solver,
            ..input.settings.clone()
        };
        &trial_settings
    };
    let shapes = input.geometry.shapes();
    let warm_keys = RefCell::new(None);
    let warm = |constraints: &IslandConstraints, _: &ProjectionQp, parents: &[usize]| {
        let keys = multiplier_pairs(constraints, parents, shapes)?;
        let lambda = input.solver_warm.warm_start(&keys);
        *warm_keys.borrow_mut() = Some((parents.to_vec(), keys));
        lambda
    };
    let plan = plan_step_warm(
        &mut constraints,
        &configuration,
        &inertias,
        settings,
        input.lengths,
        input.hold_rows,
        &warm,
        Some(input.kept_analyses),
    )
    .map_err(Error::from);
    Ok(Round {
        constraints,
        configuration,
        plan,
        warm_keys: warm_keys.into_inner(),
    })
}

/// The friction coefficient of a pair: the mean of its bodies' own
/// coefficients or, for a body without one, the settings'.
pub(super) fn pair_friction(scene: &Scene, settings: &Settings, pair: BodyPair) -> f64 {
    let of = |body: usize| {
        scene
            .body(body)
            .ok()
            .and_then(|b| b.friction())
            .unwrap_or(settings.friction)
    };
    0.5 * (of(pair.body_a) + of(pair.body_b))
}

/// Whether `bodies` are all the island's dynamic bodies.
fn contacts_cover_island(island: &Island, bodies: &[usize]) -> bool {
    bodies.len() == island.bodies.len()
}

/// The region of the first round: the penetrating pairs' bodies, or the
/// whole island when the settings ask for it or the island has joints (a
/// joint's rows move both its bodies, held or not).
fn first_region(input: PassInput, island: &Island) -> Region {
    if input.settings.solve_whole_islands || !island.joints.is_empty() {
        return Region::whole(&island.bodies);
    }
    let island_pairs: Vec<BodyPair> = island
        .pairs
        .iter()
        .map(|&k| input.active_bodies[k])
        .collect();
    let penetrating: Vec<BodyPair> = island
        .pairs
        .iter()
        .filter(|&&k| -input.active_values[k] > input.lengths.tolerance)
        .map(|&k| input.active_bodies[k])
        .collect();
    Region::new(&island.bodies, &island_pairs, &penetrating)
}

/// Plans rounds on a growing region until its answer pushes no held body
/// (or the region is the whole island).
fn plan_island<'a>(
    input: PassInput<'a>,
    island: &Island,
) -> Result<(Round<'a>, usize, f64), Error> {
    let mut region = first_region(input, island);
    let mut rounds = 0;
    let mut solve_seconds = 0.0;
    loop {
        rounds += 1;
        let round = plan_region(input, island, region.bodies())?;
        if let Ok(Plan::Step(step)) = &round.plan {
            solve_seconds += step.solve_seconds;
        }
        let pushed = match &round.plan {
            _ if region.is_whole() => return Ok((round, rounds, solve_seconds)),
            Ok(Plan::Satisfied(_)) => return Ok((round, rounds, solve_seconds)),
            Ok(Plan::Step(step)) => {
                let pushed = pushed_by(input, &region, &round.constraints.contacts, step);
                if pushed.is_empty() {
                    return Ok((round, rounds, solve_seconds));
                }
                pushed
            }
            Err(error) => {
                log::debug!(
                    "island (first body {}): region of {} bodies not solved ({error}); growing",
                    island.bodies[0],
                    round.constraints.contacts.bodies().len()
                );
                Vec::new()
            }
        };
        log::debug!(
            "island (first body {}): region of {} bodies pushes {} held bodies; growing",
            island.bodies[0],
            round.constraints.contacts.bodies().len(),
            pushed.len()
        );
        region.grow(&pushed);
    }
}

/// The held bodies that a region's planned step pushes beyond the
/// tolerance.
fn pushed_by(
    input: PassInput,
    region: &Region,
    contacts: &IslandContacts,
    step: &PlannedStep,
) -> Vec<usize> {
    let mass = |body: usize| {
        input
            .scene
            .body(body)
            .ok()
            .and_then(|b| b.mass())
            .map_or(f64::INFINITY, |m| m.mass)
    };
    let row_pairs = contacts.row_pairs();
    let qp_row_pairs: Vec<usize> = step.qp_parents.iter().map(|&row| row_pairs[row]).collect();
    pushed_bodies(
        region,
        &contacts.body_pairs(),
        &step.qp.multiplier_rows(),
        &qp_row_pairs,
        step.solution.lambda.as_slice(),
        mass,
        input.lengths.tolerance,
    )
}

/// The part pair of every multiplier of a planned problem (a friction
/// cone's three multipliers belong to its row's pair: they seed the next
/// problem's friction rows, `crate::projector::friction_rows::seed`, and
/// are no solver's start).
fn multiplier_pairs<'a>(
    constraints: &IslandConstraints,
    parents: &[usize],
    shapes: &'a [Arc<ConvexPolyhedron>],
) -> Option<MultiplierPairs<'a>> {
    let contacts = &constraints.contacts;
    let row_pairs = contacts.row_pairs();
    // The joints' rows come first and the contacts' last, and every row
    // has a multiplier: the rows are one more than the largest parent.
    let rows = parents.iter().max().map_or(0, |&last| last + 1);
    let joint_rows = rows.saturating_sub(row_pairs.len());
    let pairs: Vec<Option<BodyPair>> = parents
        .iter()
        .map(|&row| {
            let contact_row = row.checked_sub(joint_rows)?;
            let pair = row_pairs.get(contact_row)?;
            contacts.pairs().get(*pair).copied()
        })
        .collect();
    Some(MultiplierPairs::new(&pairs, shapes))
}

/// One projection step on `island`, whose pairs index the pass's active
/// pairs.
///
/// When the problem cannot be solved, it is tried again in this order,
/// until one succeeds: without friction (`friction_dropped`: a friction
/// pyramid or cone that wedged bodies cannot satisfy, e.g. a box pressed
/// into a right-angled corner with `mu >= 1`), then with the rows in
/// contact held (`rows_held`: walls touching a body on opposite sides),
/// with friction and then without. Dropping friction before holding rows
/// spends one failed solve, not two, on a wedged island (the frictional
/// problems are the largest and, near infeasibility, the slowest:
/// `benchmarks/results/engine_friction.md`). No retry once the solvers'
/// deadline has passed.
fn solve_island_or_fail(input: PassInput, island: &Island) -> Result<IslandSolution, Error> {
    log::debug!(
        "island {}: {} bodies, {} pairs",
        island_label(input.scene, &island.bodies),
        island.bodies.len(),
        island.pairs.len()
    );
    let retry_held = input.settings.hold_open_gaps && !input.hold_rows;
    let mut retries = Vec::new();
    if input.frictional {
        retries.push((input.hold_rows, false));
    }
    if retry_held {
        retries.push((true, input.frictional));
        if input.frictional {
            retries.push((true, false));
        }
    }
    let mut result = solve_island_once(input, island);
    for (hold_rows, frictional) in retries {
        let error = match &result {
            Err(error) if !out_of_time(input.settings) => error,
            _ => break,
        };
        log::debug!(
            "island {}: not solved ({error}); solved again {} friction{}",
            island_label(input.scene, &island.bodies),
            if frictional { "with" } else { "without" },
            if hold_rows {
                ", the rows in contact held"
            } else {
                ""
            }
        );
        let attempt = PassInput {
            hold_rows,
            frictional,
            ..input
        };
        result = solve_island_once(attempt, island).map(|mut solution| {
            solution.report.rows_held = hold_rows;
            solution.report.friction_dropped = input.frictional && !frictional;
            solution
        });
    }
    result
}

/// Whether the solvers' deadline (the call's time budget) has passed.
fn out_of_time(settings: &Settings) -> bool {
    settings
        .solver
        .deadline
        .is_some_and(|deadline| std::time::Instant::now() >= deadline)
}

/// [`solve_island_or_fail`] with or without friction (`input.frictional`).
fn solve_island_once(input: PassInput, island: &Island) -> Result<IslandSolution, Error> {
    let (round, rounds, solve_seconds) = plan_island(input, island)?;
    let Round {
        mut constraints,
        mut configuration,
        plan,
        warm_keys,
    } = round;
    let mut solver_warm = SolverWarmCache::default();
    let step = match plan? {
        Plan::Satisfied(measurement) => StepReport::satisfied(&measurement),
        Plan::Step(step) => {
            let keys = match warm_keys {
                Some((parents, keys)) if parents == step.qp_parents => Some(keys),
                _ => multiplier_pairs(&constraints, &step.qp_parents, input.geometry.shapes()),
            };
            if let Some(keys) = keys {
                solver_warm.record(&keys, &step.solution.lambda);
            }
            take_step(
                &mut constraints,
                &mut configuration,
                *step,
                input.settings,
                input.lengths,
            )
        }
    };
    let mut solution = finish(
        island,
        input.scene,
        rounds,
        constraints.contacts,
        configuration,
        step,
        solve_seconds,
    );
    solution.solver_warm = solver_warm;
    Ok(solution)
}

/// The solution of an island from its last round's step.
fn finish(
    island: &Island,
    scene: &Scene,
    rounds: usize,
    contacts: IslandContacts,
    configuration: Vec<BodyState>,
    step: StepReport,
    solve_seconds: f64,
) -> IslandSolution {
    let warm_starts = contacts.warm_starts();
    let moved = step.outcome == crate::projector::StepOutcome::Moved;
    let bodies = contacts.bodies();
    let (states, answers) = if moved {
        let states = bodies.iter().copied().zip(configuration).collect();
        (states, contacts.answers())
    } else {
        (Vec::new(), Vec::new())
    };
    let solution = step.solution.as_ref();
    log::debug!(
        "island {}: {} bodies, moved {} of them ({} rounds), {} pairs, joints {:?}, {} rows, {:?}, alpha {:?}, depth {:.3e} -> {:.3e}, joint error {:.3e} -> {:.3e}",
        island_label(scene, &island.bodies),
        island.bodies.len(),
        bodies.len(),
        rounds,
        contacts.pairs().len(),
        island.joints,
        step.constraints,
        solution.map(|s| s.solver),
        step.alpha,
        step.depth_before,
        step.depth_after,
        step.equality_error_before,
        step.equality_error_after
    );
    let query_seconds = contacts.query_seconds();
    IslandSolution {
        report: IslandReport {
            bodies: island.bodies.clone(),
            joints: island.joints.clone(),
            pairs: contacts.pairs().len(),
            region_bodies: bodies.len(),
            region_rounds: rounds,
            friction_dropped: false,
            rows_held: false,
            constraints: step.constraints,
            solver: solution.map(|s| s.solver),
            fallbacks: solution.map(|s| s.fallbacks.clone()).unwrap_or_default(),
            solver_iterations: solution.map_or(0, |s| s.iterations),
            factorizations: solution.map_or(0, |s| s.factorizations),
            warm_started: solution.is_some_and(|s| s.warm_started),
            cross_check: solution.and_then(|s| s.cross_check.clone()),
            outcome: step.outcome.into(),
            trust_scale: step.trust_scale,
            alpha: step.alpha,
            line_search_trials: step.line_search_trials,
            depth_before: step.depth_before,
            depth_after: step.depth_after,
            joint_error_before: step.equality_error_before,
            joint_error_after: step.equality_error_after,
            displacement: step.displacement,
        },
        states,
        solver_warm: SolverWarmCache::default(),
        warm_starts,
        answers,
        solve_seconds,
        line_search_seconds: (step.line_search_seconds - query_seconds).max(0.0),
        query_seconds,
        queries: contacts.queries(),
    }
}

/// The names of an island's first bodies, for the log.
fn island_label(scene: &Scene, bodies: &[usize]) -> String {
    const SHOWN: usize = 3;
    let names: Vec<String> = bodies
        .iter()
        .take(SHOWN)
        .map(|&i| format!("{i} {}", scene.bodies().get(i).map_or("?", |b| b.name())))
        .collect();
    let more = bodies.len().saturating_sub(SHOWN);
    match more {
        0 => format!("[{}]", names.join(", ")),
        _ => format!("[{}, and {more} more]", names.join(", ")),
    }
}

/// States and inertias of the island's dynamic bodies.
pub fn island_state(
    scene: &Scene,
    bodies: &[usize],
) -> Result<(Vec<BodyState>, Vec<BodyInertia>), Error> {
    let mut states = Vec::with_capacity(bodies.len());
    let mut inertias = Vec::with_capacity(bodies.len());
    for &index in bodies {
        let body = scene.body(index)?;
        let pose = body.com_pose();
        states.push(BodyState {
            position: pose.translation.vector.into(),
            rotation: pose.rotation,
        });
        let Some(mass) = body.mass() else {
            return Err(IslandError::MasslessBody { body: index }.into());
        };
        inertias.push(BodyInertia {
            mass: mass.mass,
            inertia_body: mass.inertia_body,
        });
    }
    Ok((states, inertias))
}
