//! Coulomb's friction cone as a constraint of the projection QP: a
//! three-dimensional second-order cone, its pyramid, and the cone algebra
//! that the residuals need.
//!
//! A cone of contact row `(J_n, phi, target)` with unit tangents `t_1, t_2`
//! and coefficient `mu` asks (`crate::projector::friction`, eq. (1))
//!
//! ```text
//! w = (phi - target + J_n dq,  mu J_t1 dq,  mu J_t2 dq)  in  K,
//! K = { (w_0, w_1, w_2) : w_0 >= |(w_1, w_2)| }          (SOC of dimension 3)
//! ```
//!
//! `K` is self-dual, so the multiplier of the cone is `z = (z_0, z_1, z_2)`
//! in `K` too, with stationarity `M dq = J_n^T z_0 + mu J_t1^T z_1 +
//! mu J_t2^T z_2`: a normal force `f_n = z_0` and a tangential force
//! `f_t = mu (z_1, z_2)`, and `|(z_1, z_2)| <= z_0` is `|f_t| <= mu f_n`,
//! Coulomb's law. Complementarity is `z^T w = 0` (then `z` and `w` lie on
//! opposite rays of the boundary of `K`, or one of them is zero).
//!
//! The pyramid with `K` directions `theta_k = 2 pi k / K` replaces the cone
//! by its `K` supporting half-spaces `w_0 - cos(theta_k) w_1 -
//! sin(theta_k) w_2 >= 0` ([`FrictionCone::facets`]); its polygon contains
//! the cone's disc and exceeds it by at most `1 / cos(pi / K)`. A facet's
//! multiplier `beta_k >= 0` is the cone multiplier
//! `beta_k (1, -cos(theta_k), -sin(theta_k))`, on the boundary of `K`
//! ([`cone_multipliers_of_facets`]).

use nalgebra::{DVector, Vector3, Vector6};

use super::projection::JacobianRow;

/// One friction cone: `mu |(J_t1 dq, J_t2 dq)| <= phi + J_n dq - target`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FrictionCone {
    /// `J_n`, the contact row's Jacobian (blocks as in [`JacobianRow`]).
    pub normal: JacobianRow,
    /// `J_t1, J_t2`: the relative tangential displacement along two unit
    /// tangents, with blocks in the same bodies and order as `normal`'s.
    pub tangents: [JacobianRow; 2],
    /// Friction coefficient, finite and `>= 0`.
    pub mu: f64,
    /// The contact row's value at the current configuration (length,
    /// negative = penetration).
    pub phi: f64,
    /// The value at which the row reaches its target: the cone's apex
    /// (length).
    pub target: f64,
}

/// Number of components of a friction cone (normal, two tangents).
pub const CONE_DIM: usize = 3;

impl FrictionCone {
    /// `b = phi - target`: the cone's first component at `dq = 0`.
    pub fn b(&self) -> f64 {
        self.phi - self.target
    }

    /// The three rows `(J_n, mu J_t1, mu J_t2)` whose values with `(b, 0, 0)`
    /// added are `w`, and whose transposes carry the multiplier `z`.
    pub fn rows(&self) -> [JacobianRow; CONE_DIM] {
        let scaled = |row: &JacobianRow| JacobianRow {
            blocks: row.blocks.iter().map(|(k, g)| (*k, g * self.mu)).collect(),
        };
        [
            self.normal.clone(),
            scaled(&self.tangents[0]),
            scaled(&self.tangents[1]),
        ]
    }

    /// `w = (b + J_n dq, mu J_t1 dq, mu J_t2 dq)` (module docs).
    pub fn value(&self, dq: &DVector<f64>) -> Vector3<f64> {
        let dot = |row: &JacobianRow| -> f64 {
            row.blocks
                .iter()
                .map(|(k, g)| g.dot(&dq.fixed_rows::<6>(6 * k)))
                .sum()
        };
        Vector3::new(
            self.b() + dot(&self.normal),
            self.mu * dot(&self.tangents[0]),
            self.mu * dot(&self.tangents[1]),
        )
    }

    /// Adds `J_n^T z_0 + mu (J_t1^T z_1 + J_t2^T z_2)` to `out`.
    pub fn add_force(&self, z: &Vector3<f64>, out: &mut DVector<f64>) {
        let rows = [&self.normal, &self.tangents[0], &self.tangents[1]];
        let weights = [z.x, self.mu * z.y, self.mu * z.z];
        for (row, weight) in rows.into_iter().zip(weights) {
            for (k, g) in &row.blocks {
                let mut block = out.fixed_rows_mut::<6>(6 * k);
                block += g * weight;
            }
        }
    }

    /// The `directions` facets of the cone's pyramid (module docs) as
    /// rows `(J_n - mu cos(theta_k) J_t1 - mu sin(theta_k) J_t2) dq >= r`
    /// with `phi = -r = phi - target` and target 0.
    pub fn facets(&self, directions: usize) -> Vec<(JacobianRow, f64)> {
        let required = self.target - self.phi;
        (0..directions)
            .map(|k| {
                let (sin, cos) = facet_angle(k, directions).sin_cos();
                let blocks = self
                    .normal
                    .blocks
                    .iter()
                    .zip(&self.tangents[0].blocks)
                    .zip(&self.tangents[1].blocks)
                    .map(|(((body, n), (_, t1)), (_, t2))| {
                        let facet: Vector6<f64> = n - (t1 * cos + t2 * sin) * self.mu;
                        (*body, facet)
                    })
                    .collect();
                (JacobianRow { blocks }, -required)
            })
            .collect()
    }
}

/// The values at `w` ([`FrictionCone::value`]) of the `directions`
/// facets of the cone's pyramid, `w_0 - cos(theta_k) w_1 - sin(theta_k)
/// w_2`: the facet rows of [`FrictionCone::facets`] at the same `dq`
/// (negative = violated).
pub fn facet_values(w: Vector3<f64>, directions: usize) -> impl Iterator<Item = f64> {
    (0..directions).map(move |k| {
        let (sin, cos) = facet_angle(k, directions).sin_cos();
        w.x - cos * w.y - sin * w.z
    })
}

/// `theta_k = 2 pi k / K`.
fn facet_angle(k: usize, directions: usize) -> f64 {
    std::f64::consts::TAU * k as f64 / directions as f64
}

/// The cone multiplier `sum_k beta_k (1, -cos(theta_k), -sin(theta_k))`
/// of facet multipliers `beta` (module docs): it exerts the same force.
pub fn cone_multipliers_of_facets(beta: &[f64]) -> Vector3<f64> {
    beta.iter()
        .enumerate()
        .map(|(k, &b)| {
            let (sin, cos) = facet_angle(k, beta.len()).sin_cos();
            Vector3::new(b, -b * cos, -b * sin)
        })
        .sum()
}

/// How far `w` lies outside `K`: `max(0, |(w_1, w_2)| - w_0)`.
pub fn cone_violation(w: &Vector3<f64>) -> f64 {
    (w.y.hypot(w.z) - w.x).max(0.0)
}

/// The Euclidean projection of `v` onto `K`: `v` inside, 0 inside the polar
/// cone `-K`, else `(v_0 + |v_t|) / 2 (1, v_t / |v_t|)`.
pub fn project_onto_cone(v: &Vector3<f64>) -> Vector3<f64> {
    let t = v.y.hypot(v.z);
    if t <= v.x {
        *v
    } else if t <= -v.x {
        Vector3::zeros()
    } else {
        let half = 0.5 * (v.x + t);
        Vector3::new(half, half * v.y / t, half * v.z / t)
    }
}

/// The smallest increase of `w_0` that puts `w` in `K`.
pub fn lift_into_cone(w: &Vector3<f64>) -> Vector3<f64> {
    Vector3::new(w.x.max(w.y.hypot(w.z)), w.y, w.z)
}
