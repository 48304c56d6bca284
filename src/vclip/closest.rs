//! Closest points between primitive features: point–segment and
//! segment–segment, both in one frame.
//!
//! Segment–segment (`p(s) = p0 + s d1`, `q(t) = q0 + t d2`, `s, t ∈ [0, 1]`):
//! the minimum of the convex function `|p(s) - q(t)|²` over the unit square
//! is either interior (the stationary point of the two lines, computed with
//! the common normal `d1 × d2`, see `interior_stationary_point`) or on
//! the square's boundary, i.e.
//! an endpoint of one segment against the other segment. We take the best of
//! the four endpoint projections (well conditioned, exact up to rounding) and
//! the interior point when it exists. Every candidate is a pair of points of
//! the segments, so the result never underestimates the distance, and
//! parallel segments (`a e - b² = 0`) need no division: they are always
//! solved by an endpoint.

use nalgebra::Point3;

/// A pair of closest points with their parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SegmentPair {
    /// Parameter on the first segment.
    pub s: f64,
    /// Parameter on the second segment.
    pub t: f64,
    /// Squared distance.
    pub distance_squared: f64,
}

/// Parameter of the point of segment `a -> b` closest to `p`.
pub(crate) fn project_on_segment(p: &Point3<f64>, a: &Point3<f64>, b: &Point3<f64>) -> f64 {
    let d = b - a;
    let length_squared = d.norm_squared();
    if length_squared > 0.0 {
        ((p - a).dot(&d) / length_squared).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// Closest points of segments `p0 -> p1` and `q0 -> q1`.
pub fn segment_segment(
    p0: &Point3<f64>,
    p1: &Point3<f64>,
    q0: &Point3<f64>,
    q1: &Point3<f64>,
) -> SegmentPair {
    let evaluate = |s: f64, t: f64| SegmentPair {
        s,
        t,
        distance_squared: ((p0 + (p1 - p0) * s) - (q0 + (q1 - q0) * t)).norm_squared(),
    };
    let candidates = [
        evaluate(0.0, project_on_segment(p0, q0, q1)),
        evaluate(1.0, project_on_segment(p1, q0, q1)),
        evaluate(project_on_segment(q0, p0, p1), 0.0),
        evaluate(project_on_segment(q1, p0, p1), 1.0),
    ];
    let mut best = candidates
        .into_iter()
        .min_by(|x, y| x.distance_squared.total_cmp(&y.distance_squared))
        .unwrap_or_else(|| evaluate(0.0, 0.0));
    if let Some((s, t)) = interior_stationary_point(p0, p1, q0, q1) {
        let interior = evaluate(s, t);
        if interior.distance_squared < best.distance_squared {
            best = interior;
        }
    }
    best
}

/// The stationary point of `|p(s) - q(t)|²` if it lies strictly inside the
/// unit square and the lines are not parallel.
///
/// With `n = d1 × d2` and `w = q0 - p0`, the lines' closest points are at
/// `s = ((w × d2) . n) / |n|²`. The cross product keeps a relative accuracy
/// of `ε / sin θ` for an angle `θ` between the segments, where the textbook
/// denominator `|d1|²|d2|² - (d1 . d2)²` loses `ε / sin² θ` to cancellation,
/// which for nearly parallel edges (Mirtich's degeneracy test) is the whole
/// answer. `t` is then the projection of `p(s)` on the other line, so that
/// the pair's distance is off only to second order in the error of `s`.
fn interior_stationary_point(
    p0: &Point3<f64>,
    p1: &Point3<f64>,
    q0: &Point3<f64>,
    q1: &Point3<f64>,
) -> Option<(f64, f64)> {
    let (d1, d2, w) = (p1 - p0, q1 - q0, q0 - p0);
    let n = d1.cross(&d2);
    let nn = n.norm_squared();
    if nn <= 0.0 {
        return None;
    }
    let s = w.cross(&d2).dot(&n) / nn;
    if !(s > 0.0 && s < 1.0) {
        return None;
    }
    let t = ((p0 + d1 * s) - q0).dot(&d2) / d2.norm_squared();
    (t > 0.0 && t < 1.0).then_some((s, t))
}
