//! The settings of a call: one [`Settings`] with nested groups
//! (`line_search`, `solver`, `vclip`, `gauss_seidel`), built and validated
//! by [`Settings::builder`] (every field has a documented default), and
//! one resolved view of its lengths for a scene, [`ResolvedLengths`],
//! which the stages of a call read.
//!
//! Every invalid value is a [`SettingsError`] naming the field by its path.
//!
//! Lengths are relative to the scene's length scale `L`, the circumradius
//! (largest distance of a vertex from the centre of mass) of the smallest
//! dynamic body: scaling a scene by `s` scales `L`, hence every tolerance,
//! by `s`, so the corrected poses scale by `s` and the number of passes is
//! unchanged. Each relative length has an absolute override.
//!
//! An engine that keeps its contacts slightly penetrating on purpose
//! (Rapier's allowed linear error, Box2D's linear slop) can be respected
//! with [`Settings::allowed_penetration`] `a` (absolute): the call accepts
//! any depth up to `a + tolerance`, and its linearized rows aim at the gap
//! `target_margin - a` (a negative gap: a depth of `a - target_margin`), so
//! a corrected contact is left at about the engine's own depth rather than
//! separated. With `a = 0` both lengths are the plain ones, bit for bit.
//!
//! [`Settings::time_budget`] bounds the wall time of a call: it is the
//! deadline of every solver inside every pass (clarabel's time limit,
//! Lemke's pivots, PGS's sweeps; `crate::solver`'s "Deadline"), and it is
//! checked after each pass's detection (never before the first, so a call
//! always detects and tries one pass).
//!
//! [`Settings::method`] chooses the correction: the projection (the
//! default; every setting but `gauss_seidel` is its) or the nonlinear
//! Gauss–Seidel baseline (`stabilizer/gauss_seidel/`), which reads
//! `gauss_seidel`, the lengths (`tolerance_*`, `contact_margin_*`,
//! `allowed_penetration`), `contact_manifold`, `time_budget` and `vclip`,
//! and ignores the rest (`max_passes` included: its sweeps are
//! `gauss_seidel.iterations`).

use std::time::Duration;

mod builder;
mod error;
mod friction;
mod gauss_seidel;
mod lengths;
mod line_search;
mod scene;

pub use builder::SettingsBuilder;
pub use error::SettingsError;
pub use friction::{DEFAULT_FRICTION_DIRECTIONS, FrictionModel, FrictionRows};
pub use gauss_seidel::GaussSeidelSettings;
pub use lengths::ResolvedLengths;
pub use line_search::LineSearchSettings;
pub use scene::SceneSettings;

use crate::solver::SolverSettings;
use crate::vclip::VClipSettings;
use error::{at_least, non_negative, positive, positive_or_infinite};

/// How a call corrects the poses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Method {
    /// The smallest mass-weighted correction: linearized contact rows, a QP
    /// per island, line search, passes until resolved (docs/design.md
    /// section 1).
    #[default]
    Projection,
    /// The game-engine baseline: nonlinear Gauss–Seidel position correction
    /// (Box2D v2.4's position solver), with [`Settings::gauss_seidel`].
    GaussSeidel,
}

impl Method {
    /// Every method, in declaration order.
    pub const ALL: [Method; 2] = [Method::Projection, Method::GaussSeidel];

    /// Lowercase name, as in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Method::Projection => "projection",
            Method::GaussSeidel => "gauss_seidel",
        }
    }

    /// The method of a [`Method::name`].
    pub fn from_name(name: &str) -> Option<Method> {
        Method::ALL.into_iter().find(|m| m.name() == name)
    }
}

/// Settings of [`crate::Stabilizer`]. Build them with
/// [`Settings::builder`], or change fields of [`Settings::default`]; the
/// stabilizer validates them when it is made.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Settings {
    /// The correction method. Default [`Method::Projection`].
    pub method: Method,
    /// Parameters of [`Method::GaussSeidel`] (unused by the projection).
    /// Default Box2D's.
    pub gauss_seidel: GaussSeidelSettings,
    /// Penetration depth accepted as resolved, relative to `L`. Default 1e-6.
    pub tolerance_relative: f64,
    /// Absolute tolerance (length); overrides `tolerance_relative`. Default none.
    pub tolerance_absolute: Option<f64>,
    /// Separated pairs closer than this (relative to `L`) join islands and
    /// the constraints, so that a correction cannot push a body into a
    /// neighbour; the broad phase enlarges AABBs by it. Default 1e-2.
    pub contact_margin_relative: f64,
    /// Absolute contact margin; overrides the relative one. Default none.
    pub contact_margin_absolute: Option<f64>,
    /// Gap that the linearized constraints aim for, relative to `L`, so that
    /// the second-order error of the linearization (rotations) rarely leaves
    /// a penetration above the tolerance. Default
    /// [`DEFAULT_TARGET_MARGIN_RELATIVE`] (1e-5, ten tolerances).
    pub target_margin_relative: f64,
    /// Absolute target margin; overrides the relative one. Default none.
    pub target_margin_absolute: Option<f64>,
    /// Penetration accepted as the engine's own (length, absolute, >= 0):
    /// depths up to `allowed_penetration + tolerance` are resolved, and the
    /// linearized rows aim at the gap `target_margin - allowed_penetration`
    /// (see the module docs). Default 0 (every penetration beyond the
    /// tolerance is removed).
    pub allowed_penetration: f64,
    /// Wall-time budget of one call: when it is spent, the call stops at
    /// the configuration reached ([`crate::Status::TimeLimit`]; never worse
    /// than the input, as any call). Inside a pass every solver stops at it
    /// and its island keeps its poses (only the `O(1)` closed form of a
    /// one-row island and the trivial answer still run), so a zero budget
    /// does one pass that moves at most such islands. Default none (no
    /// limit).
    pub time_budget: Option<Duration>,
    /// Largest number of passes (detect, solve every penetrating island,
    /// apply). Default 100.
    pub max_passes: usize,
    /// One constraint row per penetrating vertex of a pair's witness body
    /// below (or within the contact margin of) the witness face plane, rather
    /// than the deepest vertex alone. Default true, chosen by measurement
    /// (`benchmarks/results/manifold.md`).
    pub contact_manifold: bool,
    /// Build a near (separated) pair's manifold on a face axis nearly as
    /// wide as its widest separating edge–edge axis, by the ratios of gaps
    /// that a penetrating pair's uses for depths
    /// ([`crate::contact::penetration::FACE_PREFERENCE_RELATIVE`]). Default
    /// true: without it two level boxes a hair apart get the single row of
    /// an edge–edge axis, and a step tilts one into the other (stacks then
    /// take extra passes of short line-search steps; `CHANGELOG.md`,
    /// 2026-12-02). `false` judges gaps by the penetrating ratios, under
    /// which a near pair's manifold stays on its widest separating axis,
    /// an edge–edge one included (`tests/it/stabilize/seed.rs`).
    pub near_pair_faces: bool,
    /// When an island's problem cannot be solved with every contact row
    /// asking for the target margin, solve it again with the rows within
    /// the tolerance of contact (touching, or open by less than the
    /// margin) holding their value (`held_rows` in `projector/step.rs`).
    /// Default true: with every row asking for the margin, a box between
    /// two walls that touch it (an exactly fitting slot) is infeasible,
    /// both walls asking it to move away. Only a retry: holding every such
    /// row from the start lets the second-order error of a step push held
    /// contacts past the tolerance (measured in the engine loop of
    /// `examples/with_and_without.rs`, `CHANGELOG.md`, 2026-12-02). `false`:
    /// no retry, such an island is left unsolved.
    pub hold_open_gaps: bool,
    /// Coulomb friction coefficient of a body that has none of its own
    /// ([`crate::body::Body::set_friction`]); a pair's coefficient is the
    /// mean of its two bodies'. Every contact row (penetrating, resting,
    /// or open within the contact margin) gets the friction pyramid of
    /// [`crate::projector::friction`]: a contact slides at most `1 / mu`
    /// times its normal opening beyond its target. Default 0: frictionless
    /// (no friction row is added, so the projection is exactly the one
    /// without friction; the Rapier bridge reads each collider's friction
    /// instead).
    pub friction: f64,
    /// Directions `K` of the friction pyramid (at least 3). Default 4
    /// (the pyramid exceeds the cone by at most 41 % in its corners; 8
    /// gives 8 % for twice the rows). Under [`FrictionModel::Cone`] the
    /// pyramid of the solvers that take linear rows only (Lemke, PGS) and
    /// of the cross-check.
    pub friction_directions: usize,
    /// The friction pyramid or the exact cone ([`FrictionModel`]). Default
    /// [`FrictionModel::Pyramid`], chosen by measurement
    /// (`benchmarks/results/friction_models.md`): the pyramid of 4 facets
    /// is faster than the cone and differs from it by a small fraction of
    /// the body size; 8 facets cost more than the cone.
    pub friction_model: FrictionModel,
    /// How the friction rows enter the problem solved: all of them, all
    /// with the pyramid's facets in place of their row, or generated as
    /// they are needed ([`FrictionRows`]); the same minimizer every way.
    /// Default [`FrictionRows::Implied`] (the Rapier bridge's default
    /// settings keep [`FrictionRows::All`]).
    pub friction_rows: FrictionRows,
    /// clarabel's iteration limit on a problem with friction (its
    /// pyramid's rows or cones), in place of
    /// [`crate::solver::clarabel_qp::ClarabelSettings::max_iter`] when lower. Default
    /// [`DEFAULT_FRICTION_MAX_ITERATIONS`]: over every engine state of
    /// `tests/data/engine` with its engine's friction, both models, the
    /// solved frictional problems took at most 28 iterations, while a
    /// nearly infeasible pyramid (bodies wedged with `mu = 1`) ran to 200
    /// without an answer, about a second on 3,625 rows, before the island
    /// was solved without friction (`benchmarks/results/engine_friction.md`).
    pub friction_max_iterations: usize,
    /// Friction is given up on an island (which is then solved without
    /// it, the report counting the island as dropped) when the interior
    /// point proves that every correction honouring it is longer, in the
    /// mass metric, than this many times the island's largest violation
    /// (the Farkas radius of its multipliers,
    /// [`crate::solver::interior_point::InteriorPointSettings::infeasible_radius`]).
    /// Such a correction could not be taken anyway: the trust region holds
    /// a pass to about a body's size. Default
    /// [`DEFAULT_FRICTION_MAX_CORRECTION`]: over 5,036 frictional solves
    /// that converged in the Rapier loop the radius never passed 191; the
    /// MuJoCo bin of 160 boxes with `mu = 1` (wedged) reaches 1e4 at its
    /// 32nd iteration, where the certificate at 1e6 needed more than 60
    /// and then clarabel on 3,860 rows (206 -> 92-110 ms over three
    /// runs, `benchmarks/results/engine_friction.md`).
    pub friction_max_correction: f64,
    /// Solve every body of a penetrating island in every pass. Default
    /// false: a pass solves the bodies of the pairs that still penetrate,
    /// grown while the answer pushes bodies held still (see
    /// `stabilizer/region.rs`), which gives the whole island's answer to
    /// within the tolerance at the cost of the part that moves.
    pub solve_whole_islands: bool,
    /// Keep every pair that penetrated beyond the tolerance in a pass of a
    /// call active in the call's later passes, whatever its distance then:
    /// it is queried and gives rows even when separated beyond the contact
    /// margin. A body wedged between two others (or a body and the ground)
    /// whose contacts are never both within the margin at once is
    /// otherwise pushed out of one into the other and back, each pass
    /// seeing one contact; with the pair kept, the pass after the push
    /// sees both contacts and solves them together. On the inputs of the
    /// Rapier pile of 200's loop the longest call goes from 61 passes to 6
    /// (`examples/probes/passes_probe.rs`, `CHANGELOG.md`). Default false,
    /// by measurement: with it on, the interior point's and clarabel's
    /// calls on the mixed pile `rp08` end 6.4e-6 apart relative to the
    /// largest motion (2.4e-6 without: the kept rows make the passes
    /// follow the solvers' differences), and the bridge's settling pile of
    /// 200 takes another trajectory (it follows any change of answers,
    /// `benchmarks/results/solvers.md`).
    pub keep_penetrated_pairs: bool,
    /// In islands with joints, each body's rotational metric is
    /// `I + w (tr I / 2) Id` with this `w`, instead of the inertia `I`
    /// alone: a rotation costs at least `w` times what turning the body
    /// about an axis of its mean inertia costs. The mass metric makes a
    /// light link's rotation cheap, and where a joint error can be removed
    /// to first order only by turning links with a tiny lever (a nearly
    /// straight chain held between a fixed anchor and a heavy body), the
    /// minimum-norm step turns them far and its second-order error undoes
    /// the step; weighted, the step translates instead. Default
    /// [`DEFAULT_JOINT_ROTATION_WEIGHT`], chosen by measurement on Rapier
    /// chains (`docs/joints.md`); 0 is the mass metric. Islands without
    /// joints always use the mass metric.
    pub joint_rotation_weight: f64,
    /// Trust region: the largest rotation of a body in one step, radians.
    /// The island's whole correction is scaled down (its direction kept) so
    /// that no body turns further, before the line search; the next pass
    /// linearizes again. Default 0.2 (11 degrees: the second-order error of
    /// a contact point at lever `r`, `theta^2 r / 2`, stays within 2% of `r`).
    /// `f64::INFINITY` turns the limit off.
    pub step_max_rotation: f64,
    /// Trust region: the largest translation of a body's centre of mass in
    /// one step, relative to the body's radius of gyration
    /// (`sqrt(tr(I) / 2m)`, the half-edge for a cube), applied as
    /// `step_max_rotation`; a body may always translate by its island's
    /// deepest penetration. Default 1 (one half-edge per pass beyond that).
    /// `f64::INFINITY` turns the limit off.
    pub step_max_translation_relative: f64,
    /// Backtracking line search.
    pub line_search: LineSearchSettings,
    /// Solver choice, cross-check and solver tolerances. The default is
    /// the solvers' own, clarabel's polish included on every answer
    /// ([`crate::solver::clarabel_qp::ClarabelSettings::polish_above`] 0): polishing only
    /// the answers the acceptance test would reject saves 13-27 % of a call
    /// (`benchmarks/results/polish.md`), but a settled Rapier compound pile
    /// under the bridge then fell asleep at step 148 instead of 120 (Rapier
    /// alone: 117; `benchmarks/results/coupling.md`).
    pub solver: SolverSettings,
    /// V-Clip iteration cap and tie tolerance.
    pub vclip: VClipSettings,
}

/// Default of [`Settings::target_margin_relative`]: the rows aim at a gap
/// of `1e-5 L`, ten default tolerances. A pass's step turns bodies, and a
/// row linearized at the start of the pass misses the second-order part of
/// that motion (about `r theta^2 / 2` at a lever `r`): with the gap of one
/// tolerance (`1e-6 L`) the MuJoCo and Rapier pyramids of the engine
/// states ended their first pass 4-7 tolerances deep and needed a second
/// pass for it, and the last passes of the Bullet thrown box and jumble
/// and of the Rapier pile of 200 were such residuals too. At `1e-5 L`
/// those passes are gone and no engine state needs one more; at `2e-5 L`
/// and above the MuJoCo bin took one pass fewer but the Bullet bin and
/// the MuJoCo hull pile one more (`benchmarks/results/call_cost.md`,
/// twenty-third session). The cost is a gap of `1e-5 L` on the contacts a
/// call corrects.
pub const DEFAULT_TARGET_MARGIN_RELATIVE: f64 = 1e-5;

/// Default of [`Settings::joint_rotation_weight`].
pub const DEFAULT_JOINT_ROTATION_WEIGHT: f64 = 300.0;

/// Default of [`Settings::step_max_rotation`], radians.
pub const DEFAULT_STEP_MAX_ROTATION: f64 = 0.2;

/// Default of [`Settings::step_max_translation_relative`].
pub const DEFAULT_STEP_MAX_TRANSLATION_RELATIVE: f64 = 1.0;

impl Default for Settings {
    fn default() -> Self {
        Settings {
            method: Method::default(),
            gauss_seidel: GaussSeidelSettings::default(),
            tolerance_relative: 1e-6,
            tolerance_absolute: None,
            contact_margin_relative: 1e-2,
            contact_margin_absolute: None,
            target_margin_relative: DEFAULT_TARGET_MARGIN_RELATIVE,
            target_margin_absolute: None,
            allowed_penetration: 0.0,
            time_budget: None,
            max_passes: 100,
            keep_penetrated_pairs: false,
            contact_manifold: true,
            near_pair_faces: true,
            hold_open_gaps: true,
            friction: 0.0,
            friction_directions: DEFAULT_FRICTION_DIRECTIONS,
            friction_model: FrictionModel::default(),
            friction_rows: FrictionRows::default(),
            friction_max_iterations: DEFAULT_FRICTION_MAX_ITERATIONS,
            friction_max_correction: DEFAULT_FRICTION_MAX_CORRECTION,
            solve_whole_islands: false,
            joint_rotation_weight: DEFAULT_JOINT_ROTATION_WEIGHT,
            step_max_rotation: DEFAULT_STEP_MAX_ROTATION,
            step_max_translation_relative: DEFAULT_STEP_MAX_TRANSLATION_RELATIVE,
            line_search: LineSearchSettings::default(),
            solver: SolverSettings::default(),
            vclip: VClipSettings::default(),
        }
    }
}

/// Default [`Settings::friction_max_iterations`]: about twice the most
/// iterations a solved frictional problem of the engine states took (28).
pub const DEFAULT_FRICTION_MAX_ITERATIONS: usize = 60;

/// Default [`Settings::friction_max_correction`]: fifty times the largest
/// Farkas radius of a converged frictional solve in the Rapier loop (191).
pub const DEFAULT_FRICTION_MAX_CORRECTION: f64 = 1e4;

/// The fewest directions of a friction pyramid (a triangle).
pub const MIN_FRICTION_DIRECTIONS: usize = 3;

impl Settings {
    /// A builder starting from the defaults.
    pub fn builder() -> SettingsBuilder {
        SettingsBuilder::default()
    }

    /// Checks every field; the error names the first invalid one by its
    /// path.
    pub fn validate(&self) -> Result<(), SettingsError> {
        self.gauss_seidel.validate()?;
        positive("tolerance_relative", self.tolerance_relative)?;
        non_negative("contact_margin_relative", self.contact_margin_relative)?;
        non_negative("target_margin_relative", self.target_margin_relative)?;
        if let Some(value) = self.tolerance_absolute {
            positive("tolerance_absolute", value)?;
        }
        if let Some(value) = self.contact_margin_absolute {
            non_negative("contact_margin_absolute", value)?;
        }
        if let Some(value) = self.target_margin_absolute {
            non_negative("target_margin_absolute", value)?;
        }
        non_negative("allowed_penetration", self.allowed_penetration)?;
        non_negative("joint_rotation_weight", self.joint_rotation_weight)?;
        positive_or_infinite("step_max_rotation", self.step_max_rotation)?;
        positive_or_infinite(
            "step_max_translation_relative",
            self.step_max_translation_relative,
        )?;
        at_least("max_passes", self.max_passes, 1)?;
        non_negative("friction", self.friction)?;
        at_least(
            "friction_directions",
            self.friction_directions,
            MIN_FRICTION_DIRECTIONS,
        )?;
        at_least("friction_max_iterations", self.friction_max_iterations, 1)?;
        positive("friction_max_correction", self.friction_max_correction)?;
        // The solvers' residual check `residual > tol` never fails for a
        // NaN tolerance: any candidate would be accepted.
        positive("solver.tol_residual", self.solver.tol_residual)?;
        // A radius of zero or NaN would stop the interior point at once or
        // never.
        positive(
            "solver.interior_point.infeasible_radius",
            self.solver.interior_point.infeasible_radius,
        )?;
        self.line_search.validate()
    }
}
