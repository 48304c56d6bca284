//! `solve_projection`: validation, the per-island choice of solver, the
//! fallback chain, the residual check and the optional cross-check.
//!
//! Order of solvers tried: under [`SolverChoice::Auto`], nothing when every
//! row already holds ([`SolverKind::Trivial`]), the closed form for one
//! row, for islands of at most
//! [`SolverSettings::auto_dual_active_set_max_dofs`] entries of `dq`
//! without equality rows the dual active-set method (up to
//! [`SolverSettings::auto_dual_active_set_violated_max_dofs`] entries when
//! the rows violated at `dq = 0` are at most the entries), otherwise Lemke up to
//! [`SolverSettings::auto_lemke_max_rows`] rows (not counting equality
//! rows) and clarabel above, or the augmented Lagrangian from
//! [`SolverSettings::auto_augmented_lagrangian_min_rows`] rows (default
//! never: faster, but less exact, which keeps settled bridge scenes
//! awake; `benchmarks/results/solvers.md`, `coupling.md`). A named choice runs that solver
//! first. Whatever failed is followed by the remaining ones in an order
//! that depends on the size, like the first choice: up to
//! `auto_lemke_max_rows` rows clarabel -> Lemke -> PGS; above, clarabel ->
//! PGS -> Lemke, so that the dense tableau of Lemke, `O(n^2)` per pivot
//! and about `n` pivots on hundreds of rows, is the last resort, after the
//! sparse interior point and the `O(n^2)` sweeps.
//!
//! **Sizes.** The dense solvers (Lemke, PGS and clarabel's dual form, all on
//! the assembled `A = J M^-1 J^T`) never run on more rows than
//! [`SolverSettings::dense_max_rows`]: not as a first choice, not as a
//! fallback, not in the cross-check (which then reports
//! [`FailureReason::AboveDenseLimit`]). The rows counted are those the
//! solver would solve: for a problem with friction cones, its pyramid's
//! (`K` facets per cone besides the rows); for Lemke on a problem with
//! equality rows, the others (it eliminates the equalities through a
//! sparse factor, [`super::equality_elimination`]). Above the limit the chain is
//! clarabel alone (after the augmented Lagrangian when it is chosen).
//!
//! **Deadline** ([`SolverSettings::deadline`], the call's time budget):
//! clarabel gets the time left as its own time limit, Lemke checks it
//! before every pivot, PGS before every sweep, the augmented Lagrangian
//! before every Newton step; a solver asked to run after it does not start
//! (the closed form and the trivial answer, `O(1)`, still run). A solver
//! stopped by it fails with [`FailureReason::DeadlinePassed`] and ends the
//! chain: the caller keeps its configuration (the stabilizer's island does
//! not move).
//!
//! **The augmented Lagrangian** ([`SolverKind::AugmentedLagrangian`],
//! [`super::augmented_lagrangian`]) runs first when named, or under
//! `Auto` from [`SolverSettings::auto_augmented_lagrangian_min_rows`] rows
//! (default 161: in clarabel's place above Lemke's range, measured
//! faster than clarabel there); clarabel and the others follow it on
//! failure. It alone uses the multipliers of
//! [`solve_projection_warm`], and stops at [`SolverSettings::deadline`].
//!
//! **The interior point** ([`SolverKind::InteriorPoint`],
//! [`super::interior_point`]) runs first when named, or under `Auto` from
//! [`SolverSettings::auto_interior_point_min_rows`] rows (default
//! [`DEFAULT_AUTO_INTERIOR_POINT_MIN_ROWS`])
//! for problems without cones and equality rows; clarabel and the others
//! follow it on failure. It uses the multipliers of
//! [`solve_projection_warm`] (checked as they are, then its warm finish)
//! and stops at [`SolverSettings::deadline`].
//!
//! **Lemke's own residual test** ([`LemkeSettings::tol_residual`], 1e-9 on
//! the scaled LCP) is that of a standalone LCP solver. Here every candidate
//! passes the projection's acceptance check below, so Lemke's test only has
//! to reject a wrong basis; it is loosened to [`LEMKE_RESIDUAL_OF_ACCEPTANCE`]
//! times [`SolverSettings::tol_residual`] (1e-6 by default), and the
//! acceptance check decides. At high mass ratios (a pyramid under a cube
//! 1e5 to 1e6 times heavier) rounding keeps Lemke's complementary bases
//! just above 1e-9: at the standalone tolerance each would be thrown away,
//! the runs of the regularization ladder would fail the same way, and
//! clarabel would solve the island after them all. At the acceptance
//! tolerance Lemke's answer is kept and passes the check, while a basis
//! far off still goes up the ladder (chosen by measurement: `CHANGELOG.md`,
//! 2026-12-02, "Lemke inside the projection").
//!
//! **Friction cones** ([`ProjectionQp::cones`]): only clarabel's primal
//! form solves a second-order cone program. Under `Auto` a problem with
//! cones (and some violated row or cone) goes to clarabel whatever its
//! size; every other solver (a named choice, a fallback) solves the
//! problem's pyramid ([`ProjectionQp::pyramid`]), is checked on it, and
//! returns its facet multipliers as cone multipliers (the same forces,
//! [`super::friction_cone::cone_multipliers_of_facets`]), with
//! [`ProjectionSolution::pyramid_of_cones`] set. The cross-check of a
//! problem with cones compares clarabel and Lemke on the pyramid, one
//! problem for both ([`CrossCheck::on_pyramid`]).
//!
//! **Equality rows** ([`ProjectionQp::num_equalities`], joints) change
//! neither the order nor the choice: every solver takes them (clarabel's
//! primal form as a zero cone, the LCP solvers as free multipliers of a
//! mixed LCP, Lemke after eliminating them, the closed form with a
//! multiplier of either sign), and the debug log names their number. The
//! problem is trivial only when every equality row already holds within the
//! acceptance feasibility measure (`|phi_i - target_i| <= tol_residual L`);
//! a zero equality row that does not is rejected as
//! [`SolverError::InfeasibleRow`].
//!
//! Every candidate, from any solver, passes the same check before it is
//! returned: [`ProjectionResiduals::acceptance`] at most
//! [`SolverSettings::tol_residual`], i.e. the linearized rows hold to that
//! fraction of the acceptance length and `dq` is certified optimal to that
//! relative error by the duality gap (see [`super::residuals`] for the
//! measures and why they, and not the KKT measures of `lambda`, are what
//! the projection needs). Each solver that failed is listed in
//! [`ProjectionSolution::fallbacks`].

use std::cell::OnceCell;

use nalgebra::DVector;

use std::time::Instant;

use super::augmented_lagrangian::{self, AugmentedLagrangianSettings, Start};
use super::clarabel_qp::{self, ClarabelSettings};
use super::closed_form::solve_single_row;
use super::cross_check::{CrossCheck, CrossCheckOutcome, differences};
use super::dual_active_set;
use super::equality_elimination;
use super::error::SolverError;
use super::friction_cone::{CONE_DIM, cone_multipliers_of_facets};
use super::interior_point::{self, InteriorPointSettings};
use super::kept_analyses::KeptAnalyses;
use super::lcp::Lcp;
use super::lemke::{self, LemkeSettings, LemkeStatus};
use super::metric::BlockMetric;
use super::outcome::{Candidate, FailureReason, Fallback, SolverKind};
use super::pgs::{self, PgsSettings};
use super::projection::{JacobianRow, ProjectionQp};
use super::projection_lcp::{dq_from_lambda, projection_to_lcp};
use super::residuals::{
    ProjectionResiduals, acceptance_length, projection_residuals, row_violation,
};

/// Which solver to use for a projection QP.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum SolverChoice {
    /// Trivial / closed form / Lemke / clarabel by problem size.
    #[default]
    Auto,
    /// The augmented Lagrangian method with semismooth Newton
    /// ([`super::augmented_lagrangian`]).
    AugmentedLagrangian,
    /// The primal-dual interior point on the body-space matrix
    /// ([`super::interior_point`]).
    InteriorPoint,
    /// clarabel on the primal QP.
    Clarabel,
    /// clarabel on the dual QP (the LCP as a QP).
    ClarabelDual,
    /// Lemke's method on the LCP.
    Lemke,
    /// Projected Gauss-Seidel on the LCP.
    Pgs,
    /// Goldfarb and Idnani's dual active-set method
    /// ([`super::dual_active_set`]).
    DualActiveSet,
}

impl SolverChoice {
    /// All choices, with [`SolverChoice::name`] as in scene files and on
    /// the command line.
    pub const ALL: [SolverChoice; 8] = [
        SolverChoice::Auto,
        SolverChoice::AugmentedLagrangian,
        SolverChoice::InteriorPoint,
        SolverChoice::Clarabel,
        SolverChoice::ClarabelDual,
        SolverChoice::Lemke,
        SolverChoice::Pgs,
        SolverChoice::DualActiveSet,
    ];

    /// The name in files: `auto`, `augmented_lagrangian`, `clarabel`,
    /// `clarabel_dual`, `lemke`, `pgs`, `dual_active_set`.
    pub fn name(self) -> &'static str {
        match self {
            SolverChoice::Auto => "auto",
            SolverChoice::AugmentedLagrangian => "augmented_lagrangian",
            SolverChoice::InteriorPoint => "interior_point",
            SolverChoice::Clarabel => "clarabel",
            SolverChoice::ClarabelDual => "clarabel_dual",
            SolverChoice::Lemke => "lemke",
            SolverChoice::Pgs => "pgs",
            SolverChoice::DualActiveSet => "dual_active_set",
        }
    }

    /// The choice with the given name, if any.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|c| c.name() == name)
    }
}

/// Default of [`SolverSettings::auto_dual_active_set_max_dofs`]: 22
/// bodies.
pub const DEFAULT_AUTO_DUAL_ACTIVE_SET_MAX_DOFS: usize = 132;

/// Default of [`SolverSettings::auto_dual_active_set_violated_max_dofs`]:
/// the method's own limit ([`super::dual_active_set::MAX_DOFS`], 100
/// bodies).
pub const DEFAULT_AUTO_DUAL_ACTIVE_SET_VIOLATED_MAX_DOFS: usize = super::dual_active_set::MAX_DOFS;

/// Default of [`SolverSettings::auto_interior_point_min_rows`]: from this
/// many rows the interior point answers under `Auto` (Lemke below).
pub const DEFAULT_AUTO_INTERIOR_POINT_MIN_ROWS: usize = 41;

/// The most the interior point's stop target is raised to by
/// [`SolverSettings::precision_length`], as a fraction of
/// [`SolverSettings::tol_residual`]: a thousandth, the rounding floor the
/// interior point already accepts at its iteration limit, far inside the
/// acceptance test.
pub const PRECISION_STOP_CAP: f64 = 1e-3;

/// The factor `m` of the stop relaxation (`stop_relaxation`): a later pass's
/// acceptance target is `m (precision_length / v)^2` times its own, so its
/// bound on the distance to the minimizer, `sqrt(2 acceptance) v`, is
/// `sqrt(m)` (a tenth) of the first pass's: the passes' errors add up in
/// the call's displacement, and an interior point's bound is loose at its
/// first stop (it stops past its target) but tight at a raised one.
const PRECISION_MARGIN: f64 = 1e-2;

/// Settings of [`solve_projection`].
#[derive(Debug, Clone, PartialEq)]
pub struct SolverSettings {
    /// Solver choice.
    pub choice: SolverChoice,
    /// Also solve with a second solver (Lemke, or clarabel when Lemke was
    /// the first) and report the differences.
    pub cross_check: bool,
    /// Acceptance tolerance: every returned solution has
    /// [`ProjectionResiduals::acceptance`] at most this, i.e. each
    /// linearized row is at most `tol_residual * L` below its target
    /// (`L = ||phi - target||_inf`) and the duality gap
    /// certifies `||dq - dq*||_M <= tol_residual * sqrt(2 E)` (`E` about
    /// `1/2 dq^T M dq`; [`super::residuals`]). Default 1e-6: a correction
    /// right to one part in a million, far below what the linearization
    /// itself gets wrong (second order in `dq`), and above the rounding
    /// floor of the gap measure (about `sqrt(n u)`, 1e-7 at 500 rows).
    pub tol_residual: f64,
    /// Under `Auto`, Lemke for up to this many rows, clarabel (primal)
    /// above. Default 160, chosen by measurement on random stacks
    /// (`benchmarks/solvers.rs`: `benchmarks/results/solvers.md`, where the
    /// crossover lies between 150 and 200 rows). Lemke's dense tableau
    /// grows as `n^3`, clarabel's sparse factorization about linearly. A
    /// problem with equality rows counts its inequality rows: Lemke
    /// eliminates the equalities through a sparse factor
    /// ([`super::equality_elimination`]) and pivots on the rest.
    pub auto_lemke_max_rows: usize,
    /// Under `Auto`, the augmented Lagrangian for problems without cones
    /// of at least this many rows (before Lemke and clarabel). Default
    /// never (`usize::MAX`). At 161 (clarabel's place above Lemke's range)
    /// it is faster than clarabel on every engine state with such an
    /// island (the box bins, pyramids and the pile of 200: 0.55-0.8x,
    /// `benchmarks/results/solvers.md`), but its answers are further from
    /// the exact minimizer (2.9e-4 relative in `dq` against clarabel's, both
    /// accepted), and under the Rapier bridge that kept a settled compound
    /// pile awake and drifting (25.7 mm; with clarabel it sleeps and does
    /// not move: `benchmarks/results/coupling.md`).
    pub auto_augmented_lagrangian_min_rows: usize,
    /// The dense solvers (Lemke's tableau, PGS and clarabel's dual form on
    /// the assembled `A = J M^-1 J^T`) are never run on more rows than
    /// this (the pyramid's rows for a problem with cones), not even as a
    /// fallback or in the cross-check: their time grows as `n^3` and `n^2`
    /// per sweep (3,630 pyramid rows kept Lemke running for minutes).
    /// Default 1,000: one Lemke run there took 0.44-1.2 s against
    /// clarabel's 20-64 ms, at 300 rows 19-24 ms against 7-8 ms
    /// (`benchmarks/results/solvers.csv`), so a dense fallback costs at
    /// most about a second per run.
    pub dense_max_rows: usize,
    /// When the first solver fails, try the others (in the order of the
    /// module docs). Default true. The stabilizer turns it off for the
    /// trial regions of an island, whose failure only means that the
    /// region must grow (`stabilizer/region.rs`).
    pub fall_back: bool,
    /// Stop trying solvers when one certifies that the problem has no
    /// solution (clarabel's primal infeasibility certificate, or Lemke
    /// ending on a ray, which for the positive semidefinite matrices of
    /// these problems means that the LCP is infeasible). Default false (the
    /// full fallback chain); the stabilizer sets it for problems with a
    /// friction pyramid, which wedged bodies can make infeasible and which
    /// are then solved again without friction.
    pub stop_on_infeasible: bool,
    /// Every solver gives up at this instant (the caller's time budget;
    /// module docs, "Deadline"); `None`: no limit. Default `None`.
    pub deadline: Option<Instant>,
    /// The length, in the units of the rows' `b`, that the caller's answer
    /// needs its precision relative to; `None` (the default): each problem
    /// to its own length. The stabilizer sets it, from its second pass on,
    /// to the first pass's deepest penetration (or largest joint error,
    /// when that is larger): a later pass's problem is
    /// a correction of the linearization's error (often a thousandth of
    /// the first pass's depth), and the call's
    /// displacement is the sum of the passes' corrections. The interior
    /// point's stop target is raised by `(precision_length / v)^2 / 100`
    /// (`v` the problem's largest violation), at most to
    /// [`PRECISION_STOP_CAP`] times [`SolverSettings::tol_residual`]: its
    /// certified distance to the minimizer in `dq` is `sqrt(2 acceptance)`
    /// times the correction (`super::residuals`), so the later pass is
    /// answered to a tenth of the first pass's absolute precision
    /// (`benchmarks/results/call_cost.md`, "Later passes to the first
    /// pass's precision"). The acceptance test is unchanged.
    pub precision_length: Option<f64>,
    /// Under `Auto`, the interior point on the body-space matrix
    /// ([`super::interior_point`]) for problems without cones and equality
    /// rows of at least this many rows (before Lemke and clarabel; the
    /// augmented Lagrangian's threshold is checked first). Default
    /// [`DEFAULT_AUTO_INTERIOR_POINT_MIN_ROWS`], by measurement: from 41
    /// rows (Lemke below; friction pyramids included) it answers the worst
    /// calls of the Rapier loop at 0.15-0.39x Lemke's time (the thrown
    /// box's 120 rows) and 0.16-0.21x clarabel's (the pyramid's 2,900), the
    /// pile of 200's settling calls at 0.4x, and the large islands of the
    /// engine states at 0.17-0.47x clarabel's time, closer to the exact
    /// minimizer than clarabel's default answers (`benchmarks/results/
    /// solvers.md`, "The interior point" and "The worst calls of the
    /// Rapier loop"). Under the Rapier bridge the settling pile of 200
    /// follows any change of the answers; over sixteen drops perturbed by
    /// up to 2e-5 m it met issue 22's limits against Rapier alone on the
    /// same drop as often as clarabel did (8 and 6 of 16;
    /// `benchmarks/results/coupling.md`, "The settle over perturbed
    /// drops"). `usize::MAX`: never.
    pub auto_interior_point_min_rows: usize,
    /// Under `Auto`, for problems without cones and equality rows of at
    /// most this many entries of `dq`: the dual active-set method
    /// ([`super::dual_active_set`], dense in the active rows), whatever
    /// the rows. Default [`DEFAULT_AUTO_DUAL_ACTIVE_SET_MAX_DOFS`], by
    /// measurement on every QP of the engine states' calls, frictionless
    /// and with their engines' friction, each solver in alternation: up to
    /// 132 entries the method answered every QP in 0.03-0.71x the interior
    /// point's time and never more than 1.1x Lemke's (12.8 ms against
    /// 48.5 ms over the 488 QPs; `benchmarks/results/solvers.md`, "The
    /// dual active-set method"). 0: never (with
    /// [`SolverSettings::auto_dual_active_set_violated_max_dofs`] 0 too).
    pub auto_dual_active_set_max_dofs: usize,
    /// Under `Auto`, for problems without cones and equality rows above
    /// [`SolverSettings::auto_dual_active_set_max_dofs`] and up to this many
    /// entries of `dq`: the dual active-set method when the rows violated
    /// at `dq = 0` are at most the entries of `dq` (the method's steps grow
    /// with the rows it adds, each `O(|A|^2)`; the interior point's cost
    /// does not). Default [`DEFAULT_AUTO_DUAL_ACTIVE_SET_VIOLATED_MAX_DOFS`]:
    /// on the engine states' QPs of 133-600 entries the rule chose the
    /// method where it took 0.06-0.85x the interior point's time, and the
    /// interior point for the pyramids' first passes and the frictional
    /// piles, where the method took 1.1-10x (`solvers.md`). 0: never.
    pub auto_dual_active_set_violated_max_dofs: usize,
    /// Start the warm-startable solvers (the dual active-set method, the
    /// interior point, the augmented Lagrangian) from the multipliers they
    /// are given (the stabilizer's: the last answers of the same pairs, in
    /// earlier passes and calls). Default true. A warm start changes
    /// where a solver starts, never what it accepts (the minimizer in
    /// `dq` is unique): false makes every solve independent of history,
    /// as when comparing warm and cold (`probes warm`).
    pub warm_starts: bool,
    /// Augmented Lagrangian settings.
    pub augmented_lagrangian: AugmentedLagrangianSettings,
    /// Interior-point settings.
    pub interior_point: InteriorPointSettings,
    /// clarabel settings (both forms).
    pub clarabel: ClarabelSettings,
    /// Lemke settings.
    pub lemke: LemkeSettings,
    /// PGS settings.
    pub pgs: PgsSettings,
}

impl Default for SolverSettings {
    fn default() -> Self {
        Self {
            choice: SolverChoice::Auto,
            cross_check: false,
            tol_residual: 1e-6,
            auto_lemke_max_rows: 160,
            auto_augmented_lagrangian_min_rows: usize::MAX,
            dense_max_rows: 1000,
            fall_back: true,
            stop_on_infeasible: false,
            deadline: None,
            precision_length: None,
            auto_interior_point_min_rows: DEFAULT_AUTO_INTERIOR_POINT_MIN_ROWS,
            auto_dual_active_set_max_dofs: DEFAULT_AUTO_DUAL_ACTIVE_SET_MAX_DOFS,
            auto_dual_active_set_violated_max_dofs: DEFAULT_AUTO_DUAL_ACTIVE_SET_VIOLATED_MAX_DOFS,
            warm_starts: true,
            augmented_lagrangian: AugmentedLagrangianSettings::default(),
            interior_point: InteriorPointSettings::default(),
            clarabel: ClarabelSettings::default(),
            lemke: LemkeSettings::default(),
            pgs: PgsSettings::default(),
        }
    }
}

/// A checked solution of a projection QP.
#[derive(Debug, Clone, PartialEq)]
pub struct ProjectionSolution {
    /// The correction, six entries per body: `[dx; dtheta]`, world frame.
    pub dq: DVector<f64>,
    /// Multipliers, one per row (not unique with redundant rows; of either
    /// sign for equality rows).
    pub lambda: DVector<f64>,
    /// The solver that produced it.
    pub solver: SolverKind,
    /// Solvers that failed before it, in order.
    pub fallbacks: Vec<Fallback>,
    /// Residuals of `(dq, lambda)`.
    pub residuals: ProjectionResiduals,
    /// The cross-check, when asked for.
    pub cross_check: Option<CrossCheck>,
    /// Interior-point iterations, pivots, sweeps or Newton steps of the
    /// solver that succeeded.
    pub iterations: usize,
    /// Numeric factorizations made by the library's own sparse or dense
    /// Cholesky: of the body-space matrix `H` (interior point, augmented
    /// Lagrangian) or of the equality block (Lemke's sparse elimination,
    /// one); 0 for clarabel (its factorizations are its own), PGS and the
    /// dense Lemke path.
    pub factorizations: usize,
    /// The solver that answered started from given multipliers
    /// ([`solve_projection_warm`]): the augmented Lagrangian and the
    /// interior point whenever they are given (they measure them first),
    /// the dual active-set method when it took them (it refuses a warm
    /// set whose rows mostly hold at `dq = 0`).
    pub warm_started: bool,
    /// The problem had friction cones and the solver that answered takes
    /// linear rows only: `dq` is the answer of the cones' pyramid, and the
    /// residuals are checked on it (module docs).
    pub pyramid_of_cones: bool,
}

/// Lemke's own residual tolerance inside the projection, as a multiple of
/// the acceptance tolerance [`SolverSettings::tol_residual`] (module docs).
pub const LEMKE_RESIDUAL_OF_ACCEPTANCE: f64 = 1.0;

/// The fallback order after the first choice, up to
/// [`SolverSettings::auto_lemke_max_rows`] rows.
const FALLBACK_ORDER_SMALL: [SolverKind; 3] =
    [SolverKind::Clarabel, SolverKind::Lemke, SolverKind::Pgs];

/// The fallback order above [`SolverSettings::auto_lemke_max_rows`] rows:
/// dense Lemke last (module docs).
const FALLBACK_ORDER_LARGE: [SolverKind; 3] =
    [SolverKind::Clarabel, SolverKind::Pgs, SolverKind::Lemke];

/// Solves the projection QP (see the module docs).
pub fn solve_projection(
    qp: &ProjectionQp,
    settings: &SolverSettings,
) -> Result<ProjectionSolution, SolverError> {
    solve_projection_warm(qp, settings, None)
}

/// [`solve_projection`] with multipliers to start from (`warm`, one per
/// row of `qp.rows`, e.g. those of the previous pass): the augmented
/// Lagrangian starts from them and returns them with zero iterations when
/// they already pass the acceptance test; the other solvers ignore them.
pub fn solve_projection_warm(
    qp: &ProjectionQp,
    settings: &SolverSettings,
    warm: Option<&DVector<f64>>,
) -> Result<ProjectionSolution, SolverError> {
    solve_projection_kept(qp, settings, warm, None)
}

/// [`solve_projection_warm`] with a store of sparse symbolic analyses
/// (`kept`, [`KeptAnalyses`]): a solve whose sparse pattern is kept there
/// skips its analysis, and a new pattern's analysis is kept for the next
/// solves. The answer is the same with or without a store.
pub fn solve_projection_kept(
    qp: &ProjectionQp,
    settings: &SolverSettings,
    warm: Option<&DVector<f64>>,
    kept: Option<&KeptAnalyses>,
) -> Result<ProjectionSolution, SolverError> {
    if !super::recorder::is_on() {
        return solve_validated(qp, settings, warm, kept);
    }
    let start = Instant::now();
    let result = solve_validated(qp, settings, warm, kept);
    let solver = result.as_ref().ok().map(|s| s.solver);
    super::recorder::record(qp, warm, start.elapsed().as_secs_f64(), solver);
    result
}

/// [`solve_projection_warm`] without the recorder.
fn solve_validated(
    qp: &ProjectionQp,
    settings: &SolverSettings,
    warm: Option<&DVector<f64>>,
    kept: Option<&KeptAnalyses>,
) -> Result<ProjectionSolution, SolverError> {
    let metric = qp.validate()?;
    check_zero_rows(qp, settings.tol_residual)?;
    let warm = warm.filter(|_| settings.warm_starts);
    let pyramid_qp = (!qp.cones.is_empty()).then(|| qp.pyramid().0);
    let pyramid = pyramid_qp.as_ref().map(|pyramid_qp| Problem {
        qp: pyramid_qp,
        metric: &metric,
        lcp: OnceCell::new(),
        settings,
        pyramid: None,
        warm,
        kept,
    });
    let problem = Problem {
        qp,
        metric: &metric,
        lcp: OnceCell::new(),
        settings,
        pyramid: pyramid.as_ref(),
        warm,
        kept,
    };
    let mut fallbacks = Vec::new();
    let order = solver_order(qp, settings);
    log::debug!(
        "solver for {} rows ({} of them equalities) and {} cones: {:?} ({}), then {:?}",
        qp.num_rows(),
        qp.num_equalities,
        qp.cones.len(),
        order[0],
        choice_reason(qp, settings),
        &order[1..]
    );
    for kind in order {
        match problem.run_checked(kind) {
            Ok((candidate, residuals)) => {
                // The dual active-set method builds its one factor only
                // from a warm start it takes (`dual_active_set::warm`).
                let warm_started = warm.is_some()
                    && match kind {
                        SolverKind::AugmentedLagrangian | SolverKind::InteriorPoint => true,
                        SolverKind::DualActiveSet => candidate.factorizations > 0,
                        _ => false,
                    };
                log::debug!(
                    "  answered by {kind:?} ({}): {} iterations, {} factorizations",
                    if warm_started { "warm" } else { "cold" },
                    candidate.iterations,
                    candidate.factorizations
                );
                let cross_check = settings
                    .cross_check
                    .then(|| problem.cross_check(kind, &candidate));
                return Ok(ProjectionSolution {
                    dq: candidate.dq,
                    lambda: candidate.lambda,
                    solver: kind,
                    fallbacks,
                    residuals,
                    cross_check,
                    iterations: candidate.iterations,
                    factorizations: candidate.factorizations,
                    warm_started,
                    pyramid_of_cones: problem.on_pyramid(kind),
                });
            }
            Err(reason) => {
                log::debug!("solver {kind:?} failed: {reason}");
                let certified = reason.certifies_infeasibility();
                let out_of_time = reason == FailureReason::DeadlinePassed;
                fallbacks.push(Fallback {
                    solver: kind,
                    reason,
                });
                if (certified && settings.stop_on_infeasible) || out_of_time {
                    break;
                }
            }
        }
    }
    Err(SolverError::AllSolversFailed(fallbacks))
}

/// A violated row with no nonzero Jacobian cannot be satisfied; nor can a
/// violated cone whose normal row no body moves (its `w_0` stays below 0).
/// A cone is reported as row `num_rows + c`. An equality row with a zero
/// Jacobian is violated when `|phi - target|` exceeds what the acceptance
/// check lets pass, `tol_residual L` (module docs).
fn check_zero_rows(qp: &ProjectionQp, tol_residual: f64) -> Result<(), SolverError> {
    let zero = |j: &JacobianRow| j.blocks.iter().all(|(_, g)| g.iter().all(|&x| x == 0.0));
    let equality_slack = tol_residual * acceptance_length(qp);
    for (row, j) in qp.rows.iter().enumerate() {
        let violated = if qp.is_equality(row) {
            (qp.phi[row] - qp.target[row]).abs() > equality_slack
        } else {
            qp.phi[row] < qp.target[row]
        };
        if zero(j) && violated {
            return Err(SolverError::InfeasibleRow { row });
        }
    }
    for (c, cone) in qp.cones.iter().enumerate() {
        if zero(&cone.normal) && cone.b() < 0.0 {
            return Err(SolverError::InfeasibleRow {
                row: qp.num_rows() + c,
            });
        }
    }
    Ok(())
}

/// Whether `dq = 0` satisfies every row and cone: every inequality row
/// and cone exactly, every equality row within the acceptance feasibility
/// measure, `|b_i| <= tol_residual L` (module docs).
fn nothing_violated(qp: &ProjectionQp, tol_residual: f64) -> bool {
    let equality_slack = tol_residual * acceptance_length(qp);
    let rows_hold = qp.b().iter().enumerate().all(|(i, &b)| {
        let violation = row_violation(qp.is_equality(i), b);
        if qp.is_equality(i) {
            violation <= equality_slack
        } else {
            violation == 0.0
        }
    });
    rows_hold && qp.cones.iter().all(|c| c.b() >= 0.0)
}

/// The solvers to try, in order.
fn solver_order(qp: &ProjectionQp, settings: &SolverSettings) -> Vec<SolverKind> {
    let first = match settings.choice {
        SolverChoice::Auto => auto_choice(qp, settings),
        SolverChoice::AugmentedLagrangian => SolverKind::AugmentedLagrangian,
        SolverChoice::InteriorPoint => SolverKind::InteriorPoint,
        SolverChoice::Clarabel => SolverKind::Clarabel,
        SolverChoice::ClarabelDual => SolverKind::ClarabelDual,
        SolverChoice::Lemke => SolverKind::Lemke,
        SolverChoice::Pgs => SolverKind::Pgs,
        SolverChoice::DualActiveSet => SolverKind::DualActiveSet,
    };
    if first == SolverKind::Trivial || !settings.fall_back {
        return vec![first];
    }
    let fallbacks = if qp.num_rows() <= settings.auto_lemke_max_rows {
        FALLBACK_ORDER_SMALL
    } else {
        FALLBACK_ORDER_LARGE
    };
    let mut order = vec![first];
    // The dual active-set method answers in the interior point's place
    // (`auto_choice`): the interior point follows it.
    if first == SolverKind::DualActiveSet && qp.num_equalities == 0 {
        order.push(SolverKind::InteriorPoint);
    }
    order.extend(fallbacks.iter().copied().filter(|&k| k != first));
    if dense_rows(qp) > settings.dense_max_rows {
        order.retain(|&k| !is_dense(k) || dense_rows_of(k, qp) <= settings.dense_max_rows);
        if order.is_empty() {
            order.push(SolverKind::Clarabel);
        }
    }
    order
}

/// Whether `kind` solves the assembled `A = J M^-1 J^T` (module docs,
/// "Sizes").
fn is_dense(kind: SolverKind) -> bool {
    matches!(
        kind,
        SolverKind::Lemke | SolverKind::Pgs | SolverKind::ClarabelDual
    )
}

/// The rows a dense solver solves for `qp`: its rows, and its pyramid's
/// facets when it has cones.
fn dense_rows(qp: &ProjectionQp) -> usize {
    qp.num_rows() + qp.cones.len() * qp.cone_facets
}

/// The rows `kind` holds densely: Lemke eliminates equality rows through a
/// sparse factor (`super::equality_elimination`) and pivots on the rest;
/// the other dense solvers hold every row.
fn dense_rows_of(kind: SolverKind, qp: &ProjectionQp) -> usize {
    match kind {
        SolverKind::Lemke => dense_rows(qp) - qp.num_equalities,
        _ => dense_rows(qp),
    }
}

/// Why the first solver was chosen, for the log.
fn choice_reason(qp: &ProjectionQp, settings: &SolverSettings) -> String {
    let n = qp.num_rows();
    match (settings.choice, auto_choice(qp, settings)) {
        (SolverChoice::Auto, SolverKind::Trivial) => "auto: no row violated".into(),
        (SolverChoice::Auto, SolverKind::ClosedForm) if qp.num_equalities > 0 => {
            "auto: one (equality) row".into()
        }
        (SolverChoice::Auto, SolverKind::ClosedForm) => "auto: one row".into(),
        (SolverChoice::Auto, SolverKind::Clarabel) if !qp.cones.is_empty() => {
            "auto: friction cones, which only clarabel solves".into()
        }
        (SolverChoice::Auto, SolverKind::DualActiveSet)
            if qp.num_dofs() <= settings.auto_dual_active_set_max_dofs =>
        {
            format!(
                "auto: the dual active-set method, at most {} entries of dq",
                settings.auto_dual_active_set_max_dofs
            )
        }
        (SolverChoice::Auto, SolverKind::DualActiveSet) => format!(
            "auto: the dual active-set method, at most {} entries of dq and no more rows violated",
            settings.auto_dual_active_set_violated_max_dofs
        ),
        (SolverChoice::Auto, SolverKind::InteriorPoint) => format!(
            "auto: the interior point on the body-space matrix from {} rows",
            settings.auto_interior_point_min_rows
        ),
        (SolverChoice::Auto, SolverKind::AugmentedLagrangian) => format!(
            "auto: the warm-startable Newton method from {} rows",
            settings.auto_augmented_lagrangian_min_rows
        ),
        (SolverChoice::Auto, SolverKind::Lemke) => format!(
            "auto: dense pivoting is fastest up to {} rows",
            settings.auto_lemke_max_rows
        ),
        (SolverChoice::Auto, _) => format!(
            "auto: above {} rows the sparse interior point is fastest",
            settings.auto_lemke_max_rows
        ),
        (choice, _) => format!("{choice:?} asked for in the settings ({n} rows)"),
    }
}

fn auto_choice(qp: &ProjectionQp, settings: &SolverSettings) -> SolverKind {
    let n = qp.num_rows();
    if nothing_violated(qp, settings.tol_residual) {
        SolverKind::Trivial
    } else if !qp.cones.is_empty() {
        SolverKind::Clarabel
    } else if n == 1 {
        SolverKind::ClosedForm
    } else if n >= settings.auto_augmented_lagrangian_min_rows {
        SolverKind::AugmentedLagrangian
    } else if dual_active_set_chosen(qp, settings) {
        SolverKind::DualActiveSet
    } else if n >= settings.auto_interior_point_min_rows && qp.num_equalities == 0 {
        SolverKind::InteriorPoint
    } else if n - qp.num_equalities <= settings.auto_lemke_max_rows {
        SolverKind::Lemke
    } else {
        SolverKind::Clarabel
    }
}

/// Whether `Auto` takes the dual active-set method (no cones, checked by
/// the caller; [`SolverSettings::auto_dual_active_set_max_dofs`] and
/// [`SolverSettings::auto_dual_active_set_violated_max_dofs`]).
fn dual_active_set_chosen(qp: &ProjectionQp, settings: &SolverSettings) -> bool {
    let dofs = qp.num_dofs();
    if qp.num_equalities > 0 {
        false
    } else if dofs <= settings.auto_dual_active_set_max_dofs {
        true
    } else if dofs <= settings.auto_dual_active_set_violated_max_dofs {
        qp.b().iter().filter(|&&b| b < 0.0).count() <= dofs
    } else {
        false
    }
}

/// A validated problem with its dual LCP built on first use, and the
/// problem of its cones' pyramid when it has cones.
struct Problem<'a> {
    qp: &'a ProjectionQp,
    metric: &'a [BlockMetric],
    lcp: OnceCell<Option<Lcp>>,
    settings: &'a SolverSettings,
    pyramid: Option<&'a Problem<'a>>,
    /// Multipliers to start from (rows of the original problem first).
    warm: Option<&'a DVector<f64>>,
    /// The caller's kept sparse analyses.
    kept: Option<&'a KeptAnalyses>,
}

impl Problem<'_> {
    /// The pyramid, when `kind` cannot solve this problem's cones.
    fn pyramid_for(&self, kind: SolverKind) -> Option<&Problem<'_>> {
        self.pyramid
            .filter(|_| !matches!(kind, SolverKind::Clarabel | SolverKind::Trivial))
    }

    /// Whether `kind` answers this problem on its pyramid.
    fn on_pyramid(&self, kind: SolverKind) -> bool {
        self.pyramid_for(kind).is_some()
    }

    /// A candidate of the pyramid with cone multipliers (module docs).
    fn cone_candidate(&self, pyramid: Candidate) -> Candidate {
        let n = self.qp.num_rows();
        let facets = self.qp.cone_facets;
        let mut lambda = DVector::zeros(self.qp.num_multipliers());
        lambda.rows_mut(0, n).copy_from(&pyramid.lambda.rows(0, n));
        for c in 0..self.qp.cones.len() {
            let beta: Vec<f64> = pyramid
                .lambda
                .rows(n + c * facets, facets)
                .iter()
                .copied()
                .collect();
            let z = cone_multipliers_of_facets(&beta);
            lambda
                .fixed_rows_mut::<CONE_DIM>(n + CONE_DIM * c)
                .copy_from(&z);
        }
        Candidate { lambda, ..pyramid }
    }

    fn lcp(&self) -> Result<&Lcp, FailureReason> {
        self.lcp
            .get_or_init(|| projection_to_lcp(self.qp, self.metric).ok())
            .as_ref()
            // A = J M^-1 J^T overflowed (extreme masses): only the primal
            // clarabel form applies.
            .ok_or(FailureReason::NotApplicable)
    }

    /// Runs one solver and checks its candidate.
    fn run_checked(
        &self,
        kind: SolverKind,
    ) -> Result<(Candidate, ProjectionResiduals), FailureReason> {
        if let Some(pyramid) = self.pyramid_for(kind) {
            let (candidate, residuals) = pyramid.run_checked(kind)?;
            return Ok((self.cone_candidate(candidate), residuals));
        }
        let candidate = self.run(kind)?;
        let residuals =
            projection_residuals(self.qp, self.metric, &candidate.dq, &candidate.lambda);
        let tolerance = self.settings.tol_residual;
        let residual = residuals.acceptance();
        log::debug!(
            "  {kind:?} answered {} rows: feasibility {:.2e}, optimality {:.2e} \
             (natural map {:.2e}, complementarity {:.2e}, stationarity {:.2e})",
            self.qp.num_rows(),
            residuals.feasibility,
            residuals.optimality,
            residuals.natural_map,
            residuals.complementarity,
            residuals.stationarity
        );
        // A NaN residual fails too.
        if residual.is_nan() || residual > tolerance {
            return Err(FailureReason::ResidualTooLarge {
                residual,
                tolerance,
            });
        }
        Ok((candidate, residuals))
    }

    /// Runs one solver within the size and time limits (module docs).
    fn run(&self, kind: SolverKind) -> Result<Candidate, FailureReason> {
        let s = self.settings;
        let rows = dense_rows_of(kind, self.qp);
        if is_dense(kind) && rows > s.dense_max_rows {
            return Err(FailureReason::AboveDenseLimit {
                rows,
                limit: s.dense_max_rows,
            });
        }
        let constant_time = matches!(kind, SolverKind::Trivial | SolverKind::ClosedForm);
        if !constant_time && self.out_of_time() {
            return Err(FailureReason::DeadlinePassed);
        }
        // A failure once the deadline has passed is the deadline's.
        self.run_unlimited(kind)
            .map_err(|reason| match self.out_of_time() {
                true => FailureReason::DeadlinePassed,
                false => reason,
            })
    }

    /// Whether the deadline has passed.
    fn out_of_time(&self) -> bool {
        self.settings
            .deadline
            .is_some_and(|deadline| Instant::now() >= deadline)
    }

    /// clarabel's settings with the time left before the deadline as its
    /// time limit, when that is shorter.
    fn clarabel_settings(&self) -> ClarabelSettings {
        let mut clarabel = self.settings.clarabel.clone();
        if let Some(deadline) = self.settings.deadline {
            let left = deadline.saturating_duration_since(Instant::now());
            clarabel.time_limit = clarabel.time_limit.min(left.as_secs_f64());
        }
        clarabel
    }

    fn run_unlimited(&self, kind: SolverKind) -> Result<Candidate, FailureReason> {
        let s = self.settings;
        // The start of the two warm-startable solvers.
        let start = Start {
            warm: self.warm,
            tolerance: s.tol_residual,
            // Only the interior point reads it (`Start::relaxation`).
            relaxation: match kind {
                SolverKind::InteriorPoint => stop_relaxation(s, self.qp),
                _ => 1.0,
            },
            deadline: s.deadline,
            kept: self.kept,
        };
        match kind {
            SolverKind::Trivial => Ok(Candidate {
                dq: DVector::zeros(self.qp.num_dofs()),
                lambda: DVector::zeros(self.qp.num_multipliers()),
                iterations: 0,
                factorizations: 0,
            }),
            SolverKind::ClosedForm => solve_single_row(self.qp, self.metric),
            SolverKind::AugmentedLagrangian => {
                augmented_lagrangian::solve(self.qp, self.metric, &s.augmented_lagrangian, &start)
                    .map_err(FailureReason::AugmentedLagrangian)
            }
            SolverKind::InteriorPoint => {
                interior_point::solve(self.qp, self.metric, &s.interior_point, &start)
                    .map_err(FailureReason::InteriorPoint)
            }
            SolverKind::DualActiveSet => {
                dual_active_set::solve(self.qp, self.metric, s.tol_residual, s.deadline, self.warm)
                    .map_err(FailureReason::DualActiveSet)
            }
            SolverKind::Clarabel => {
                clarabel_qp::primal::solve(self.qp, self.metric, &self.clarabel_settings())
            }
            SolverKind::ClarabelDual => {
                let clarabel = self.clarabel_settings();
                let sol = clarabel_qp::dual::solve_lcp_unchecked(self.lcp()?, &clarabel)?;
                Ok(self.candidate_from_lambda(sol.z, sol.iterations))
            }
            SolverKind::Lemke if self.qp.num_equalities > 0 => self.lemke_eliminated(),
            SolverKind::Lemke => {
                let sol = lemke::solve(self.lcp()?, &self.lemke_settings())
                    .map_err(|f| FailureReason::Lemke(f.status))?;
                Ok(self.candidate_from_lambda(sol.z, sol.pivots))
            }
            SolverKind::Pgs => {
                let pgs_settings = PgsSettings {
                    deadline: s.deadline,
                    ..s.pgs.clone()
                };
                let sol = pgs::solve(self.lcp()?, &pgs_settings).map_err(FailureReason::Pgs)?;
                Ok(self.candidate_from_lambda(sol.z, sol.sweeps))
            }
        }
    }

    /// Lemke on a problem with equality rows: the equality block eliminated
    /// through a sparse factor (`super::equality_elimination`); when that
    /// answer misses Lemke's test and the whole problem fits
    /// `auto_lemke_max_rows`, the dense elimination by a pivoted factor
    /// (rank-revealing in its own order) answers instead.
    fn lemke_eliminated(&self) -> Result<Candidate, FailureReason> {
        let settings = self.lemke_settings();
        match equality_elimination::solve(self.qp, self.metric, &settings, self.kept) {
            // The correction the elimination computed for its own check.
            Ok(sol) => Ok(Candidate {
                dq: sol.dq,
                lambda: sol.z,
                iterations: sol.pivots,
                factorizations: sol.factorizations,
            }),
            Err(failure) => match failure.status {
                LemkeStatus::Inaccurate { .. }
                    if dense_rows(self.qp) <= self.settings.auto_lemke_max_rows =>
                {
                    log::debug!(
                        "  lemke: the sparse elimination missed ({:?}), the dense one follows",
                        failure.status
                    );
                    let sol = lemke::solve(self.lcp()?, &settings)
                        .map_err(|f| FailureReason::Lemke(f.status))?;
                    Ok(self.candidate_from_lambda(sol.z, sol.pivots))
                }
                status => Err(FailureReason::Lemke(status)),
            },
        }
    }

    /// Lemke's settings for this problem: its own residual test loosened to
    /// [`LEMKE_RESIDUAL_OF_ACCEPTANCE`] times the acceptance tolerance
    /// (module docs),
    /// and the call's deadline.
    fn lemke_settings(&self) -> LemkeSettings {
        let s = self.settings;
        let loosened = LEMKE_RESIDUAL_OF_ACCEPTANCE * s.tol_residual;
        LemkeSettings {
            tol_residual: s.lemke.tol_residual.max(loosened),
            deadline: s.deadline,
            ..s.lemke.clone()
        }
    }

    fn candidate_from_lambda(&self, lambda: DVector<f64>, iterations: usize) -> Candidate {
        let dq = dq_from_lambda(self.qp, self.metric, &lambda);
        Candidate {
            dq,
            lambda,
            iterations,
            factorizations: 0,
        }
    }

    /// The cross-check of `candidate` from `kind`; with cones, of
    /// clarabel and Lemke on the pyramid (module docs).
    fn cross_check(&self, kind: SolverKind, candidate: &Candidate) -> CrossCheck {
        let Some(pyramid) = self.pyramid else {
            return self.compare(kind, candidate);
        };
        let first = if self.on_pyramid(kind) {
            kind
        } else {
            SolverKind::Clarabel
        };
        let mut check = match pyramid.run_checked(first) {
            Ok((candidate, _)) => pyramid.compare(first, &candidate),
            Err(reason) => CrossCheck {
                reference: first,
                outcome: CrossCheckOutcome::ReferenceFailed(reason),
                on_pyramid: true,
            },
        };
        check.on_pyramid = true;
        check
    }

    /// Solves again with Lemke (clarabel when `kind` is Lemke) and compares.
    fn compare(&self, kind: SolverKind, candidate: &Candidate) -> CrossCheck {
        let reference = if kind == SolverKind::Lemke {
            SolverKind::Clarabel
        } else {
            SolverKind::Lemke
        };
        let outcome = match self.run_checked(reference) {
            Ok((other, reference_residuals)) => CrossCheckOutcome::Compared {
                differences: differences(self.qp, self.metric, &candidate.dq, &other.dq),
                reference_residuals,
            },
            Err(reason) => CrossCheckOutcome::ReferenceFailed(reason),
        };
        CrossCheck {
            reference,
            outcome,
            on_pyramid: false,
        }
    }
}

/// Solves one problem with clarabel (primal) and with Lemke and reports
/// their differences (the cross-check of docs/design.md section 5). The
/// first element is clarabel's solution; `outcome` holds Lemke's.
pub fn cross_check_projection(
    qp: &ProjectionQp,
    settings: &SolverSettings,
) -> Result<(ProjectionSolution, CrossCheck), SolverError> {
    let settings = SolverSettings {
        choice: SolverChoice::Clarabel,
        cross_check: true,
        ..settings.clone()
    };
    let solution = solve_projection(qp, &settings)?;
    // `cross_check: true` above: every solution solve_projection returns
    // then carries a cross-check (see the loop in solve_projection).
    let check = solution.cross_check.clone().expect("cross-check requested");
    Ok((solution, check))
}

/// The factor by which [`SolverSettings::precision_length`] raises the
/// interior point's stop target on `qp`: `m (precision_length / v)^2`
/// ([`PRECISION_MARGIN`] `m`) with
/// `v` the problem's largest violation (`max_i max(0, -b_i)`, `|b_i|` on an
/// equality row, the violated normal rows of cones), the length its
/// correction is of, so that the answer's distance to the minimizer, about
/// `sqrt(2 acceptance)` times the correction, stays a tenth of the first
/// pass's absolute precision; at least 1 (never tighter than the problem's own
/// length), unbounded without a violated row (the caller caps it); 1
/// without a precision length.
fn stop_relaxation(settings: &SolverSettings, qp: &ProjectionQp) -> f64 {
    let Some(length) = settings.precision_length else {
        return 1.0;
    };
    let b = qp.b();
    let violation = (0..b.len())
        .map(|i| crate::solver::residuals::row_violation(qp.is_equality(i), b[i]))
        .chain(qp.cones.iter().map(|cone| (-cone.b()).max(0.0)))
        .fold(0.0, f64::max);
    let ratio = length / violation;
    let relaxation = PRECISION_MARGIN * ratio * ratio;
    match relaxation > 1.0 {
        true => relaxation,
        // Also NaN (no violation and no length): the problem's own.
        false => 1.0,
    }
}
