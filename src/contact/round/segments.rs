//! Closest points of two segments (a point is a segment of length 0).
//!
//! With `P(s) = p0 + s d1`, `Q(t) = q0 + t d2`, `s, t` in `[0, 1]`, the
//! squared distance `|P(s) - Q(t)|^2` is a convex quadratic. Its
//! unconstrained minimum solves
//!
//! ```text
//! [ a  -b ] [s]   [-c]      a = d1.d1, b = d1.d2, e = d2.d2,
//! [ b  -e ] [t] = [-f],     c = d1.r,  f = d2.r,  r = p0 - q0,
//! ```
//!
//! `s = (b f - c e) / (a e - b^2)`. Clamped to `[0, 1]`, the best `t` for
//! it is `(b s + f) / e`, and when that leaves `[0, 1]` the clamped `t`
//! fixes `s = clamp((b t - c) / a)`; for a convex quadratic over a box,
//! this sequence reaches the constrained minimum. Parallel segments
//! (`a e - b^2` zero) take `s = 0` and go on the same way: any minimizer
//! is a closest pair.

use nalgebra::Point3;

/// Relative size below which a segment counts as a point, and below which
/// `a e - b^2` counts as parallel (both against the squared lengths).
pub const DEGENERATE_RELATIVE: f64 = 1e-14;

/// The closest points `(on [p0, p1], on [q0, q1])`.
pub fn closest_points(
    p0: &Point3<f64>,
    p1: &Point3<f64>,
    q0: &Point3<f64>,
    q1: &Point3<f64>,
) -> (Point3<f64>, Point3<f64>) {
    let (d1, d2, r) = (p1 - p0, q1 - q0, p0 - q0);
    let (a, e, f) = (d1.norm_squared(), d2.norm_squared(), d2.dot(&r));
    let scale = (a + e + r.norm_squared()).max(f64::MIN_POSITIVE);
    let tiny = DEGENERATE_RELATIVE * scale;
    let (s, t) = if a <= tiny && e <= tiny {
        (0.0, 0.0)
    } else if a <= tiny {
        (0.0, (f / e).clamp(0.0, 1.0))
    } else {
        let c = d1.dot(&r);
        if e <= tiny {
            ((-c / a).clamp(0.0, 1.0), 0.0)
        } else {
            let b = d1.dot(&d2);
            let denominator = a * e - b * b;
            let s = if denominator > tiny * scale {
                ((b * f - c * e) / denominator).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let t = (b * s + f) / e;
            if t < 0.0 {
                ((-c / a).clamp(0.0, 1.0), 0.0)
            } else if t > 1.0 {
                (((b - c) / a).clamp(0.0, 1.0), 1.0)
            } else {
                (s, t)
            }
        }
    };
    (p0 + d1 * s, q0 + d2 * t)
}

/// The closest point of `[q0, q1]` to `p`.
pub fn closest_to_point(p: &Point3<f64>, q0: &Point3<f64>, q1: &Point3<f64>) -> Point3<f64> {
    closest_points(p, p, q0, q1).1
}
