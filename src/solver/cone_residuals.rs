//! The residual measures of [`super::residuals`] on the friction cones of a
//! problem ([`super::friction_cone`]), in the cone's own sense.
//!
//! For a cone with value `w` and multiplier `z` (both in `R^3`) and the
//! scale `a = J_n M^-1 J_n^T` of its normal row (the `a_i` of a row; one
//! factor for the three components, since `K` is invariant only under a
//! common positive scaling), with `K` the second-order cone:
//! - infeasibility: `max(0, |w_t| - w_0)`, the smallest lift of `w_0` that
//!   puts `w` in `K` (for a row: `max(0, -w_i)`);
//! - natural map: `|a z - P_K(a z - w)|`, zero exactly when `z in K`,
//!   `w in K`, `z^T w = 0` (for a row, `a_i lambda_i - max(0, a_i lambda_i
//!   - w_i) = min(a_i lambda_i, w_i)`, the row's natural map);
//! - complementarity: `a |z^T w|`;
//! - the gap term `P_K(z)^T lift(w) >= 0` (both in `K`, self-dual), which
//!   replaces `lambda_i^+ w_i^+` in the duality gap: with `z` projected onto
//!   `K` the dual objective is a lower bound (weak duality holds for any
//!   `z in K*  = K`), and `dq` is feasible for the problem whose cone apex
//!   is lifted by the infeasibility.

use nalgebra::{DVector, Vector3};

use super::friction_cone::{CONE_DIM, cone_violation, lift_into_cone, project_onto_cone};
use super::metric::BlockMetric;
use super::projection::ProjectionQp;

/// One cone at a candidate.
pub struct ConeAtCandidate {
    /// `w`.
    pub w: Vector3<f64>,
    /// `z`.
    pub z: Vector3<f64>,
    /// `a`, the scale of the normal row (or `a_fallback` when it is 0).
    pub a: f64,
    /// `b = phi - target`.
    pub b: f64,
}

impl ConeAtCandidate {
    /// `max(0, |w_t| - w_0)`.
    pub fn infeasibility(&self) -> f64 {
        cone_violation(&self.w)
    }

    /// `|a z - P_K(a z - w)|`.
    pub fn natural_map(&self) -> f64 {
        let force = self.z * self.a;
        (force - project_onto_cone(&(force - self.w))).norm()
    }

    /// `a |z^T w|`.
    pub fn complementarity(&self) -> f64 {
        self.a * self.z.dot(&self.w).abs()
    }

    /// `|a z|`: the force as a length.
    pub fn force(&self) -> f64 {
        self.a * self.z.norm()
    }

    /// `P_K(z)^T lift(w)`.
    pub fn gap(&self) -> f64 {
        project_onto_cone(&self.z).dot(&lift_into_cone(&self.w))
    }
}

/// Every cone of `qp` at `(dq, lambda)`; `a_fallback` stands for a normal
/// row that no body moves.
pub fn cones_at(
    qp: &ProjectionQp,
    metric: &[BlockMetric],
    dq: &DVector<f64>,
    lambda: &DVector<f64>,
    a_fallback: f64,
) -> Vec<ConeAtCandidate> {
    let n = qp.num_rows();
    qp.cones
        .iter()
        .enumerate()
        .map(|(c, cone)| {
            let start = n + CONE_DIM * c;
            let z = if lambda.len() >= start + CONE_DIM {
                lambda.fixed_rows::<CONE_DIM>(start).into_owned()
            } else {
                Vector3::zeros()
            };
            let a: f64 = cone
                .normal
                .blocks
                .iter()
                .map(|(k, g)| g.dot(&metric[*k].apply_inv(g)))
                .sum();
            ConeAtCandidate {
                w: cone.value(dq),
                z,
                a: if a > 0.0 { a } else { a_fallback },
                b: cone.b(),
            }
        })
        .collect()
}

/// The multipliers projected onto their cones: inequality rows' clamped
/// at 0, equality rows' left as they are (free), cones' projected onto `K`.
pub fn projected_multipliers(qp: &ProjectionQp, lambda: &DVector<f64>) -> DVector<f64> {
    let n = qp.num_rows();
    let mut out = DVector::from_iterator(
        lambda.len(),
        lambda
            .iter()
            .enumerate()
            .map(|(i, &x)| if qp.is_equality(i) { x } else { x.max(0.0) }),
    );
    for c in 0..qp.cones.len() {
        let start = n + CONE_DIM * c;
        if out.len() >= start + CONE_DIM {
            let z = lambda.fixed_rows::<CONE_DIM>(start).into_owned();
            out.fixed_rows_mut::<CONE_DIM>(start)
                .copy_from(&project_onto_cone(&z));
        }
    }
    out
}
