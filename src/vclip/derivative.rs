//! The derivative checks after clipping (Mirtich 1998, section 4.3).
//!
//! After an edge `e(l) = t + l u` (`u = h - t`) has been clipped to
//! `[l_lo, l_hi]` against the region of a feature `X`, the distance
//! `D(l) = dist(e(l), X)` is convex, so its minimum over the edge lies
//! before `l_lo` iff `D'(l_lo) > 0` and after `l_hi` iff `D'(l_hi) < 0`; in
//! either case `X` moves to the neighbour whose plane cut the edge there.
//! Only signs are needed:
//! - to a point `v`: `sign D'(l) = sign(u . (e(l) - v))`;
//! - to a face with plane `P`, unit normal `n`: `sign D'(l) = sign(u . n)`
//!   if `D_P(e(l)) > 0`, `-sign(u . n)` if `D_P(e(l)) < 0`. With the
//!   heights `d_t = D_P(t)`, `d_h = D_P(h)`, `u . n = d_h - d_t` and
//!   `D_P(e(l)) = d_t + l (d_h - d_t)`: the check needs only the two
//!   heights. They are computed once per state, with `P` pulled back into
//!   the edge's own frame, by every state that compares an edge with a face
//!   (E-E, E-F, V-F), so that all of them take the same decision for an
//!   edge (nearly) parallel to the face; otherwise rounding differences
//!   between frames can make two states send the walk back and forth.
//!
//! When `X` is an edge, the distance is measured to the neighbour (vertex or
//! face) whose plane was crossed: at the crossing point both give the same
//! closest point. A zero sign (the edge touches the reference, or the
//! reference is perpendicular) asks for no update: the distance is at a
//! stationary point, and the walk ends there with distance 0 when touching.

use nalgebra::Point3;

use super::clip::{Clip, lerp};
use crate::geometry::Feature;

/// What the distance is measured to.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Reference {
    /// A vertex position.
    Point(Point3<f64>),
    /// A face plane, by the heights `(D_P(t), D_P(h))` of the edge's ends.
    Heights(f64, f64),
}

/// `D'(l)` in length units up to a positive factor: the point form is
/// divided by `|u|` so that it compares with a length slack.
pub(crate) fn derivative(
    tail: &Point3<f64>,
    head: &Point3<f64>,
    l: f64,
    reference: &Reference,
) -> f64 {
    match reference {
        Reference::Point(v) => {
            let u = head - tail;
            u.dot(&(lerp(tail, head, l) - v)) / u.norm()
        }
        Reference::Heights(d_tail, d_head) => face_slope(*d_tail, *d_head, l),
    }
}

/// Sign of the derivative of `|D_P(e(l))|` from the heights of the ends:
/// `(d_h - d_t) sign(D_P(e(l)))`, 0 on the plane.
pub(crate) fn face_slope(d_tail: f64, d_head: f64, l: f64) -> f64 {
    let height = d_tail + (d_head - d_tail) * l;
    if height > 0.0 {
        d_head - d_tail
    } else if height < 0.0 {
        d_tail - d_head
    } else {
        0.0
    }
}

/// The standard check: `Some(N_lo)` if `D'(l_lo) > 0`, else `Some(N_hi)` if
/// `D'(l_hi) < 0`, else `None`. `reference` gives the reference of a
/// neighbour.
pub(crate) fn check(
    clip: &Clip,
    tail: &Point3<f64>,
    head: &Point3<f64>,
    reference: impl Fn(Feature) -> Reference,
) -> Option<Feature> {
    if let Some(n) = clip.n_lo
        && derivative(tail, head, clip.l_lo, &reference(n)) > clip.slack
    {
        return Some(n);
    }
    if let Some(n) = clip.n_hi
        && derivative(tail, head, clip.l_hi, &reference(n)) < -clip.slack
    {
        return Some(n);
    }
    None
}

/// The check after a compound exclusion, which must update: in exact
/// arithmetic one of the two conditions holds; if rounding hides both, the
/// neighbour at `l_hi` is taken (any neighbour keeps the walk valid, as the
/// edge lies in none of the region).
pub(crate) fn check_excluded(
    clip: &Clip,
    tail: &Point3<f64>,
    head: &Point3<f64>,
    reference: impl Fn(Feature) -> Reference,
) -> Option<Feature> {
    check(clip, tail, head, &reference)
        .or(clip.n_hi)
        .or(clip.n_lo)
}
