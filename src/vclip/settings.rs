//! Settings of a V-Clip query and the errors of bad input.
//!
//! The walk needs no tolerance: its only divisions are in edge clipping,
//! `l = dt / (dt - dh)` with `dt` and `dh` of opposite signs, and it
//! decides with exact sign tests as Mirtich (1998) does. Termination in
//! floating point is guarded by an iteration cap proportional to the
//! feature counts; hitting it triggers the exhaustive fallback.

use thiserror::Error;

use crate::geometry::Feature;

/// Default of [`VClipSettings::iterations_per_feature`].
///
/// Mirtich's walk visits each feature pair at most once in exact
/// arithmetic and in practice only a handful; a cap of a few transitions
/// per feature (of both bodies together) is never reached by a correct walk
/// and bounds a rounding cycle to linear cost.
pub const DEFAULT_ITERATIONS_PER_FEATURE: usize = 4;

/// Default of [`VClipSettings::min_iterations`]: transitions always allowed,
/// whatever the feature counts (a tetrahedron pair has only 28 features).
pub const DEFAULT_MIN_ITERATIONS: usize = 64;

/// Default of [`VClipSettings::tie_tolerance`]: a pair is accepted after a
/// cycle if its closest points are inside each other's Voronoi regions up
/// to this fraction of the pair's length scale (the bodies' scales plus the
/// distance between their centres). Rounding in the plane tests is about
/// 1e-16 of that scale; 1e-10 leaves a wide margin and still pins the
/// distance far below the 1e-9 relative accuracy the tests demand.
pub const DEFAULT_TIE_TOLERANCE: f64 = 1e-10;

/// Default of [`VClipSettings::touch_tolerance`]: a done state whose
/// closest points are closer than this fraction of the pair's length scale
/// is checked for overlap (touching or penetrating, see the `touching`
/// module); rounding of the distance itself is about 1e-16 of that scale.
pub const DEFAULT_TOUCH_TOLERANCE: f64 = 1e-10;

/// Settings of a query.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VClipSettings {
    /// Iteration cap = `min_iterations + iterations_per_feature * (features
    /// of A + features of B)`.
    pub iterations_per_feature: usize,
    /// See [`Self::iterations_per_feature`].
    pub min_iterations: usize,
    /// Overrides the cap when `Some` (tests force the fallback with it).
    pub max_iterations: Option<usize>,
    /// Relative tolerance of the closest-pair test after a cycle.
    pub tie_tolerance: f64,
    /// Relative distance below which a separated answer is checked for
    /// overlap, and within which a separating plane counts as touching.
    pub touch_tolerance: f64,
    /// After the deepest-vertex walk, search the neighbouring faces for a
    /// less deep vertex–face pair (see the `deepest` module). `false` gives
    /// exactly the witness face of docs/design.md section 4.
    pub refine_face: bool,
    /// Pairs with a cylinder or cone part: `true` (the default) computes
    /// them on the true solids by support functions (GJK/EPA and a
    /// refinement, `contact::round::support_pair`, measured within 2e-8 of
    /// the pair's size against the oracle, `docs/round-shapes.md`);
    /// `false` on the circumscribed polyhedra by V-Clip and the exact depth
    /// walk, whose depths exceed the true ones by at most the stated
    /// deviation `geometry::curved::CURVED_DEVIATION_RELATIVE` of the
    /// radius (`Shape::surface_deviation`).
    pub curved_support_functions: bool,
    /// Detection skips a pair whose last exact answer certifies that it is
    /// still separated beyond the contact margin, by a bound on how far its
    /// two parts moved since, and reuses an earlier call's answer of a pair
    /// whose parts have not moved at all (`contact::certificate`); `false`
    /// queries every candidate pair whose parts moved since its last answer
    /// in the call. The poses of a call are the same either way (a
    /// certified pair gives no row; an answer is a function of the solids
    /// and their poses).
    pub motion_certificates: bool,
}

impl Default for VClipSettings {
    fn default() -> Self {
        VClipSettings {
            iterations_per_feature: DEFAULT_ITERATIONS_PER_FEATURE,
            min_iterations: DEFAULT_MIN_ITERATIONS,
            max_iterations: None,
            tie_tolerance: DEFAULT_TIE_TOLERANCE,
            touch_tolerance: DEFAULT_TOUCH_TOLERANCE,
            refine_face: true,
            curved_support_functions: true,
            motion_certificates: true,
        }
    }
}

impl VClipSettings {
    /// The iteration cap for two bodies with these feature counts.
    pub fn iteration_cap(&self, features_a: usize, features_b: usize) -> usize {
        self.max_iterations.unwrap_or_else(|| {
            self.min_iterations.saturating_add(
                self.iterations_per_feature
                    .saturating_mul(features_a + features_b),
            )
        })
    }
}

/// Bad input to a query.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum VClipError {
    /// A pose has a NaN or infinite component.
    #[error("the pose of body {body:?} is not finite")]
    NonFinitePose {
        /// The body whose pose is bad.
        body: super::BodyRole,
    },
    /// A pose's rotation quaternion is not of unit norm (within
    /// [`ROTATION_NORM_TOLERANCE`](super::ROTATION_NORM_TOLERANCE)).
    #[error("the rotation of body {body:?} has quaternion norm {norm}, not 1")]
    NonUnitRotation {
        /// The body whose pose is bad.
        body: super::BodyRole,
        /// The norm found.
        norm: f64,
    },
    /// A warm-start feature index is out of range for its body (a stale
    /// cache from another shape).
    #[error("warm-start feature {feature:?} does not exist on body {body:?}")]
    InvalidWarmStart {
        /// The body.
        body: super::BodyRole,
        /// The feature given.
        feature: Feature,
    },
}
