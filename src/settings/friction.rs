//! How rows with friction bound their sliding: the friction pyramid of `K`
//! facets or the exact Coulomb cone (the math is in
//! [`crate::projector::friction`]).

/// Default number of pyramid directions `K`.
pub const DEFAULT_FRICTION_DIRECTIONS: usize = 4;

/// How the projection treats the friction cone (1) of a row with friction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum FrictionModel {
    /// The pyramid (2) of `K` facets for every solver: a QP with linear
    /// rows, which clarabel, Lemke and PGS solve alike. It allows up to
    /// `1 / cos(pi / K)` times the cone's sliding in its corners.
    #[default]
    Pyramid,
    /// The exact cone (1) as a second-order cone of clarabel's primal form
    /// ([`crate::solver::friction_cone`]). Lemke, PGS and clarabel's dual
    /// form, which take linear rows only, solve the pyramid (2) instead
    /// when they run (a named choice, a fallback, the cross-check); under
    /// `SolverChoice::Auto` a problem with cones goes to clarabel.
    Cone,
}

impl FrictionModel {
    /// Both models, with [`FrictionModel::name`] as in files.
    pub const ALL: [FrictionModel; 2] = [FrictionModel::Pyramid, FrictionModel::Cone];

    /// `pyramid` or `cone`.
    pub fn name(self) -> &'static str {
        match self {
            FrictionModel::Pyramid => "pyramid",
            FrictionModel::Cone => "cone",
        }
    }

    /// The model with the given name, if any.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.name() == name)
    }
}

/// How the friction of a projection's rows enters the problem that is
/// solved (the math is in [`crate::projector::friction_rows`]). The same
/// minimizer every way; they differ in the problems the solvers see.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum FrictionRows {
    /// Every row with its friction: under the pyramid the row and its `K`
    /// facets, under the cone model the row and its cone. The Rapier
    /// bridge's default (`BridgeSettings::default()`, feature `rapier`):
    /// over 64 perturbed drops of its pile of 200, 15 settled within issue
    /// 22's limits with it and 11 with [`FrictionRows::Implied`]
    /// (`benchmarks/results/engine_friction.md`): the same minimizer, but
    /// the settle follows the solvers' answers within their tolerance.
    All,
    /// Every row's friction, with the pyramid's facets in place of their
    /// row (they imply it): `K` rows per row with friction, not `K + 1`.
    /// The default: 10-40 % faster than [`FrictionRows::All`] on the
    /// engine states, and as fast as [`FrictionRows::Generated`] there,
    /// where nearly every contact's friction is needed
    /// (`benchmarks/results/engine_friction.md`). The cone model is the
    /// same either way (clarabel's primal form leaves a cone's row out).
    #[default]
    Implied,
    /// Generated as needed: the rows whose friction held in the previous
    /// answer (all of them when they are most rows), or none, first; then
    /// the friction of every row whose friction the answer violates, until
    /// none is. Facets replace their row as under [`FrictionRows::Implied`].
    /// Fewer rows where few contacts slide, one more solve per round where
    /// many do.
    Generated,
}

impl FrictionRows {
    /// Every way, with [`FrictionRows::name`] as in the Python keyword.
    pub const ALL: [FrictionRows; 3] = [
        FrictionRows::All,
        FrictionRows::Implied,
        FrictionRows::Generated,
    ];

    /// `all`, `implied` or `generated`.
    pub fn name(self) -> &'static str {
        match self {
            FrictionRows::All => "all",
            FrictionRows::Implied => "implied",
            FrictionRows::Generated => "generated",
        }
    }

    /// The way with the given name, if any.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|rows| rows.name() == name)
    }
}
