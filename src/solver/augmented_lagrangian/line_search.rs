//! Exact line search on the augmented Lagrangian along a Newton direction.
//!
//! Along `dq + t d` the row values are `w_i + t s_i` (`s = J d`) and the
//! derivative of the augmented Lagrangian (module docs of [`super`]) is
//!
//! ```text
//! phi'(t) = d^T M dq + t d^T M d - sum_E s_i (lambda_i - rho_i (w_i + t s_i))
//!                                - sum_I s_i max(0, lambda_i - rho_i (w_i + t s_i))
//! ```
//!
//! a continuous, nondecreasing, piecewise linear function of `t` (the
//! function is convex, piecewise quadratic). Its breakpoints are the `t`
//! where an inequality row enters or leaves the active set,
//! `t_i = (lambda_i - rho_i w_i) / (rho_i s_i)`. The minimizer is its root,
//! found by walking the sorted breakpoints: `O(m log m)`, exact.

/// The values along the direction that the search needs.
pub(super) struct Direction<'a> {
    /// `d^T M dq`.
    pub m_dq: f64,
    /// `d^T M d > 0`.
    pub m_d: f64,
    /// `w_i` at `t = 0`.
    pub w: &'a [f64],
    /// `s_i = J_i d`.
    pub s: &'a [f64],
    /// Current multipliers `lambda_i`.
    pub lambda: &'a [f64],
    /// Penalties `rho_i`.
    pub rho: &'a [f64],
    /// The first `num_equalities` rows are equalities.
    pub num_equalities: usize,
}

/// The step `t >= 0` that minimizes the augmented Lagrangian along the
/// direction (the root of `phi'`), or `None` if `phi'` is not negative at
/// `t = 0` (not a descent direction: rounding at the minimizer).
pub(super) fn exact_step(dir: &Direction<'_>) -> Option<f64> {
    // phi'(t) = value + slope t on the current segment.
    let mut value = dir.m_dq;
    let mut slope = dir.m_d;
    let mut breakpoints: Vec<(f64, usize)> = Vec::new();
    for i in 0..dir.w.len() {
        let (s, r) = (dir.s[i], dir.rho[i]);
        if s == 0.0 || r == 0.0 {
            continue;
        }
        let p = dir.lambda[i] - r * dir.w[i];
        if i < dir.num_equalities {
            value -= s * p;
            slope += r * s * s;
            continue;
        }
        // Active at t = 0+ when p - t r s > 0 for small t > 0.
        let active_at_start = p > 0.0 || (p == 0.0 && s < 0.0);
        if active_at_start {
            value -= s * p;
            slope += r * s * s;
        }
        let t_i = p / (r * s);
        if t_i > 0.0 && t_i.is_finite() {
            breakpoints.push((t_i, i));
        }
    }
    if value.is_nan() || value >= 0.0 {
        return None;
    }
    breakpoints.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
    for (t_i, i) in breakpoints {
        // phi'(t_i) on the current segment.
        if value + slope * t_i >= 0.0 && slope > 0.0 {
            return Some(-value / slope);
        }
        // Row i changes state at t_i: its term -s (p - t r s) enters or
        // leaves; phi' is continuous there, so only (value, slope) of the
        // linear form change.
        let (s, r) = (dir.s[i], dir.rho[i]);
        let p = dir.lambda[i] - r * dir.w[i];
        let entering = s < 0.0;
        let sign = if entering { 1.0 } else { -1.0 };
        value -= sign * s * p;
        slope += sign * r * s * s;
    }
    // Past the last breakpoint the slope is at least d^T M d > 0.
    (slope > 0.0).then(|| -value / slope)
}
