//! Poses of the dynamic bodies of a projection and their metric.
//!
//! A body's state is its centre-of-mass position `x` and rotation `R`
//! (world frame). The metric block of body `i` is `blockdiag(m_i I3, I_i)`
//! with the world-frame inertia `I_i = R_i I_body R_i^T`.
//! A correction `dq` is applied as `x += dx`, `R = exp(dtheta) R`: the
//! rotation vector `dtheta` acts in the world frame, and the exponential
//! keeps `R` a rotation whatever the step.

use nalgebra::DVector;

pub use crate::body::{BodyInertia, BodyState};

/// The states of the dynamic bodies of one projection, in a fixed order:
/// body `i` owns entries `6 i .. 6 i + 6` of a correction.
pub type Configuration = Vec<BodyState>;

/// `configuration` moved by `alpha dq`.
pub fn moved_configuration(
    configuration: &[BodyState],
    dq: &DVector<f64>,
    alpha: f64,
) -> Configuration {
    configuration
        .iter()
        .enumerate()
        .map(|(i, state)| {
            let dx = dq.fixed_rows::<3>(6 * i).into_owned();
            let dtheta = dq.fixed_rows::<3>(6 * i + 3).into_owned();
            state.moved(&dx, &dtheta, alpha)
        })
        .collect()
}
