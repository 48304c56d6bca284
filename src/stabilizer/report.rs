//! What a stabilization call did: status, passes, islands, solvers,
//! line-search steps, penetration before and after, displacement, times.

use crate::Error;
use crate::contact::Detection;
pub use crate::contact::PairPenetration;
use crate::joints::JointErrors;
use crate::projector::StepOutcome;
use crate::settings::ResolvedLengths;
use crate::solver::{CrossCheck, Fallback, SolverKind};

/// How a call ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// No penetration deeper than the tolerance was found: no pose was
    /// touched.
    NothingToDo,
    /// Penetrations were removed: none deeper than the tolerance remains.
    Converged,
    /// The pass limit was reached with a penetration left.
    PassLimit,
    /// The time budget ([`super::Settings::time_budget`]) was spent after a
    /// pass with a penetration left: the call stopped at the configuration
    /// that pass reached (never worse than the input).
    TimeLimit,
    /// Every island solved in the last pass stalled (the line search found
    /// no acceptable step); the stalled islands are in
    /// [`Report::islands_left`].
    Stalled,
    /// In the last pass no island moved and at least one could not be
    /// solved at all (every solver failed, or its problem was invalid). The
    /// other islands' progress and the passes before are kept; the islands
    /// left and why are in [`Report::islands_left`].
    Unsolved,
}

impl Status {
    /// Short lowercase name, as in the scene file report.
    pub fn name(self) -> &'static str {
        match self {
            Status::NothingToDo => "nothing_to_do",
            Status::Converged => "converged",
            Status::PassLimit => "pass_limit",
            Status::TimeLimit => "time_limit",
            Status::Stalled => "stalled",
            Status::Unsolved => "unsolved",
        }
    }

    /// Whether no penetration deeper than the tolerance remains.
    pub fn is_resolved(self) -> bool {
        matches!(self, Status::NothingToDo | Status::Converged)
    }

    /// The status that ends a call after a detection, if any, for either
    /// method: the deepest penetration within the tolerance
    /// ([`Status::NothingToDo`] before any pass, else
    /// [`Status::Converged`]), the pass limit reached, or the time budget
    /// spent after at least one pass (`out_of_time`, asked only then).
    pub(crate) fn after_detection(
        deepest: f64,
        tolerance: f64,
        passes: usize,
        pass_limit: usize,
        out_of_time: impl FnOnce() -> bool,
    ) -> Option<Status> {
        if deepest <= tolerance {
            Some(if passes == 0 {
                Status::NothingToDo
            } else {
                Status::Converged
            })
        } else if passes == pass_limit {
            Some(Status::PassLimit)
        } else if passes > 0 && out_of_time() {
            Some(Status::TimeLimit)
        } else {
            None
        }
    }
}

/// What one island's step did.
#[derive(Debug, Clone, PartialEq)]
pub enum IslandOutcome {
    /// No penetration beyond the tolerance: nothing was done.
    AlreadySatisfied,
    /// A step was accepted and applied.
    Moved,
    /// The line search found no acceptable step; the island's bodies kept
    /// their poses.
    Stalled,
    /// The island could not be solved (every solver failed, or its problem
    /// was invalid); its bodies kept their poses.
    Failed(Error),
}

impl From<StepOutcome> for IslandOutcome {
    fn from(outcome: StepOutcome) -> Self {
        match outcome {
            StepOutcome::AlreadySatisfied => IslandOutcome::AlreadySatisfied,
            StepOutcome::Moved => IslandOutcome::Moved,
            StepOutcome::Stalled => IslandOutcome::Stalled,
        }
    }
}

impl IslandOutcome {
    /// Whether the island's bodies were moved.
    pub fn moved(&self) -> bool {
        matches!(self, IslandOutcome::Moved)
    }

    /// Why an island was left, as in the scene file report: `stalled`, or
    /// the error of a failed island.
    pub fn reason(&self) -> String {
        match self {
            IslandOutcome::AlreadySatisfied => "already_satisfied".into(),
            IslandOutcome::Moved => "moved".into(),
            IslandOutcome::Stalled => "stalled".into(),
            IslandOutcome::Failed(error) => format!("failed: {error}"),
        }
    }
}

/// An island left with a penetration: its bodies kept the poses they had
/// before its step.
#[derive(Debug, Clone, PartialEq)]
pub struct IslandLeft {
    /// Dynamic bodies (scene indices, ascending).
    pub bodies: Vec<usize>,
    /// [`IslandOutcome::Stalled`] or [`IslandOutcome::Failed`].
    pub outcome: IslandOutcome,
}

/// One joint's errors before and after a call.
#[derive(Debug, Clone, PartialEq)]
pub struct JointReport {
    /// Index of the joint in the scene.
    pub index: usize,
    /// Its name.
    pub name: String,
    /// Its type ([`crate::JointKind::name`]).
    pub kind: &'static str,
    /// Body `a` (scene index).
    pub body_a: usize,
    /// Body `b` (scene index).
    pub body_b: usize,
    /// Errors at the poses before the call.
    pub before: JointErrors,
    /// Errors at the poses after the call.
    pub after: JointErrors,
}

/// One island solved in one pass.
#[derive(Debug, Clone)]
pub struct IslandReport {
    /// Dynamic bodies (scene indices, ascending).
    pub bodies: Vec<usize>,
    /// Joints of the island (scene indices, ascending).
    pub joints: Vec<usize>,
    /// Body pairs of the island (penetrating or within the contact margin).
    pub pairs: usize,
    /// Bodies moved by the step: the region that still penetrated, grown
    /// while the answer pushed bodies held still (all of `bodies` when
    /// [`super::Settings::solve_whole_islands`]); 0 if not solved.
    pub region_bodies: usize,
    /// Problems solved to find that region (1 when the first one pushed
    /// no held body).
    pub region_rounds: usize,
    /// The island was solved without friction: its problem with friction
    /// could not be solved (its friction pyramid or cones left wedged
    /// bodies no way out, certified or within the solvers' limits), here
    /// or in an earlier pass of the call for one of its bodies.
    pub friction_dropped: bool,
    /// The problem with every row at the target margin could not be solved
    /// (walls touching a body on opposite sides ask it to move away from
    /// both) and the island was solved again with the rows within the
    /// tolerance of contact holding their gap
    /// (`held_rows` in `projector/step.rs`, [`crate::Settings::hold_open_gaps`]).
    pub rows_held: bool,
    /// Linearized constraint rows.
    pub constraints: usize,
    /// The solver that produced the correction (`None` if nothing solved).
    pub solver: Option<SolverKind>,
    /// Solvers that failed first, in order.
    pub fallbacks: Vec<Fallback>,
    /// Iterations (interior-point iterations, pivots, sweeps or Newton
    /// steps) of the solver that answered.
    pub solver_iterations: usize,
    /// Numeric factorizations made by the library's own Cholesky: of the
    /// body-space matrix (interior point, augmented Lagrangian) or of the
    /// joints' equality block (Lemke's sparse elimination); 0 for clarabel,
    /// PGS and dense Lemke
    /// ([`crate::solver::ProjectionSolution::factorizations`]).
    pub factorizations: usize,
    /// The solver that answered started from given multipliers.
    pub warm_started: bool,
    /// The clarabel/Lemke comparison, when the cross-check is on.
    pub cross_check: Option<CrossCheck>,
    /// Moved, stalled, failed, or nothing to do.
    pub outcome: IslandOutcome,
    /// Factor by which the trust region scaled the solver's correction.
    pub trust_scale: f64,
    /// Accepted step length (along the scaled correction).
    pub alpha: Option<f64>,
    /// Trial configurations measured by the line search.
    pub line_search_trials: usize,
    /// Deepest penetration of the island before and after the step.
    pub depth_before: f64,
    /// See `depth_before`.
    pub depth_after: f64,
    /// Largest joint error of the island before the step (length units,
    /// angles times the scene's scale; joint limits count with the
    /// penetrations).
    pub joint_error_before: f64,
    /// See `joint_error_before`.
    pub joint_error_after: f64,
    /// Mass-weighted length of the applied correction.
    pub displacement: f64,
}

/// One pass: detection over the whole scene, then one projection step per
/// penetrating island.
#[derive(Debug, Clone, Default)]
pub struct PassReport {
    /// Candidate pairs from the broad phase.
    pub candidate_pairs: usize,
    /// Candidate pairs queried by the narrow phase (the others had not
    /// moved since their last answer, or were certified separated).
    pub queried_pairs: usize,
    /// Candidate pairs certified separated beyond the contact margin by a
    /// bound on their motion since their last exact answer, and not queried
    /// (`contact::certificate`).
    pub certified_pairs: usize,
    /// Candidate pairs answered by an earlier call's answer at the same
    /// poses of the same solids (`contact::certificate`), not queried.
    pub reused_pairs: usize,
    /// Pairs penetrating deeper than the tolerance.
    pub penetrating_pairs: usize,
    /// Pairs within the contact margin (penetrating or not).
    pub active_pairs: usize,
    /// Islands formed from the active pairs.
    pub islands: usize,
    /// Deepest penetration found by this pass's detection.
    pub deepest: f64,
    /// Largest joint error at this pass's poses (length units, angles
    /// times the scene's scale).
    pub joint_error: f64,
    /// The islands solved in this pass (those with a penetration deeper than
    /// the tolerance), in ascending order of their smallest body.
    pub solved: Vec<IslandReport>,
}

/// Wall time per stage, seconds, summed over passes (and over islands for
/// the per-island stages, so with several threads these may exceed `total`).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StageTimes {
    /// Broad phase (AABB tree).
    pub broad_phase: f64,
    /// Narrow phase (V-Clip over candidate pairs).
    pub narrow_phase: f64,
    /// Linearization and solvers.
    pub solve: f64,
    /// Line searches (V-Clip on trial configurations).
    pub line_search: f64,
    /// The whole call.
    pub total: f64,
}

/// The report of [`super::Stabilizer::stabilize`].
#[derive(Debug, Clone)]
pub struct Report {
    /// How the call ended.
    pub status: Status,
    /// Number of passes that solved at least one island.
    pub passes: usize,
    /// One entry per pass (detection and solves), the last being the final
    /// check when it found nothing to solve.
    pub pass_reports: Vec<PassReport>,
    /// The scene's length scale `L` (smallest dynamic body's circumradius).
    pub scale: f64,
    /// The absolute penetration tolerance used (including the allowed
    /// penetration).
    pub tolerance: f64,
    /// The allowed penetration ([`super::Settings::allowed_penetration`]),
    /// included in `tolerance`.
    pub allowed_penetration: f64,
    /// Deepest penetration before the call: the exact depth (the minimum
    /// translation, equal to the separating-axis depth) of the deepest pair.
    pub depth_before: f64,
    /// Deepest penetration after the call (exact, as `depth_before`).
    pub depth_after: f64,
    /// The pairs penetrating deeper than the tolerance before the call, by
    /// ascending body indices.
    pub penetrations_before: Vec<PairPenetration>,
    /// The pairs still penetrating deeper than the tolerance at the last
    /// detection of the call.
    pub penetrations_after: Vec<PairPenetration>,
    /// Largest joint error before the call (length units, angles times
    /// the scene's scale `L`, limits' excess included).
    pub joint_error_before: f64,
    /// Largest joint error after the call (as `joint_error_before`).
    pub joint_error_after: f64,
    /// Every joint's errors before and after the call, in joint order.
    pub joints: Vec<JointReport>,
    /// Mass-weighted displacement of the whole scene, `sqrt(sum_i m_i
    /// |dx_i|^2 + dtheta_i^T I_i dtheta_i)` between the poses before and
    /// after (`dtheta_i` the rotation vector of `R_after R_before^T`).
    pub displacement: f64,
    /// Number of bodies whose pose changed.
    pub bodies_moved: usize,
    /// Islands left in the last pass that solved anything: those whose
    /// line search stalled or that could not be solved, with the reason.
    /// Their bodies kept the poses they had before that pass's step.
    pub islands_left: Vec<IslandLeft>,
    /// The result was worse than the input (the exact deepest penetration
    /// or the merit, `sum (depth - tolerance)^2` over the penetrating pairs,
    /// rose: islands moved into each other) and every pose was put back as
    /// it was before the call; `depth_after` and `penetrations_after` are
    /// then the input's.
    pub restored_input: bool,
    /// Narrow-phase queries (V-Clip and, when penetrating, the exact
    /// depth) run by the call: detections and line-search trials. A pair is
    /// queried once per configuration of its two bodies.
    pub pair_queries: usize,
    /// Detections' candidate pairs not queried because a bound on their
    /// motion since their last exact answer (this call's or an earlier
    /// one's) certified them separated beyond the contact margin, summed
    /// over the passes.
    pub certified_pairs: usize,
    /// Detections' candidate pairs answered by an earlier call's answer at
    /// the same poses of the same solids, not queried, summed over the
    /// passes.
    pub reused_pairs: usize,
    /// Multipliers the stabilizer keeps after the call as the solver's warm
    /// starts of the next calls (one per contact row and friction row of
    /// the pairs last solved; freed when their bodies go).
    pub solver_warm_multipliers: usize,
    /// The sparse symbolic analyses the stabilizer keeps after the call for
    /// the next solves of the same patterns (the equality blocks of joints
    /// and the body-space matrices of the interior point,
    /// `crate::solver::kept_analyses`): their number and the bytes they
    /// hold (at most 16 patterns; freed when bodies are removed through
    /// the stabilizer).
    pub kept_analyses: (usize, usize),
    /// Wall time per stage.
    pub times: StageTimes,
}

impl Report {
    /// The report of a call that has not detected anything yet.
    pub fn new(lengths: &ResolvedLengths) -> Self {
        Report {
            status: Status::NothingToDo,
            passes: 0,
            pass_reports: Vec::new(),
            scale: lengths.scale,
            tolerance: lengths.tolerance,
            allowed_penetration: lengths.allowed_penetration,
            depth_before: 0.0,
            depth_after: 0.0,
            penetrations_before: Vec::new(),
            penetrations_after: Vec::new(),
            joint_error_before: 0.0,
            joint_error_after: 0.0,
            joints: Vec::new(),
            displacement: 0.0,
            bodies_moved: 0,
            islands_left: Vec::new(),
            restored_input: false,
            pair_queries: 0,
            certified_pairs: 0,
            reused_pairs: 0,
            solver_warm_multipliers: 0,
            kept_analyses: (0, 0),
            times: StageTimes::default(),
        }
    }

    /// Takes in a detection's times and depth (the first one is the depth
    /// before the call, the last one the depth after).
    pub(crate) fn record_detection(&mut self, detection: &Detection) {
        self.times.broad_phase += detection.broad_phase_seconds;
        self.times.narrow_phase += detection.narrow_phase_seconds;
        self.pair_queries += detection.queried;
        self.certified_pairs += detection.certified;
        self.reused_pairs += detection.reused;
        if self.pass_reports.is_empty() {
            self.depth_before = detection.deepest;
            self.penetrations_before = detection.penetrations.clone();
        }
        self.depth_after = detection.deepest;
        self.penetrations_after = detection.penetrations.clone();
    }

    /// The merit of the scene at a detection: `sum (depth - tolerance)^2`
    /// over the pairs penetrating deeper than the tolerance (the line
    /// search's merit, over the whole scene).
    pub fn merit(penetrations: &[PairPenetration], tolerance: f64) -> f64 {
        penetrations
            .iter()
            .map(|p| (p.depth - tolerance).max(0.0).powi(2))
            .sum()
    }

    /// Total number of islands solved over all passes.
    pub fn islands_solved(&self) -> usize {
        self.pass_reports.iter().map(|p| p.solved.len()).sum()
    }

    /// Total line-search trials over all passes.
    pub fn line_search_trials(&self) -> usize {
        self.pass_reports
            .iter()
            .flat_map(|p| &p.solved)
            .map(|island| island.line_search_trials)
            .sum()
    }
}
