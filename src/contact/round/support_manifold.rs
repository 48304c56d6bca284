//! Contact points of a support-function pair (`support_pair`): a flat
//! contact gets points over the whole touching region, a curved one its
//! single deepest point.
//!
//! With the normal `n` (from B towards A), A's support plane
//! `n . x = t_A = -h_A(-n)` and B's `n . x = t_B = h_B(n)`
//! (`t_A - t_B = -o(n)`, the cores' signed distance `s`):
//!
//! - the central point: the witnesses of GJK/EPA, each moved along `n`
//!   onto its support plane (separation `s`, normal `n`), or, without
//!   witnesses, A's support point and its partner straight along `n` on
//!   B's plane;
//! - the outline points of each core within a band above its own support
//!   plane: polyhedron vertices, segment ends, the ends of a cylinder's or
//!   cone's side line facing the other, and a rim's samples when the
//!   whole rim lies within the window (a cap flat on the plane; a tilted
//!   rim touches at one point, the central one). The window is
//!   [`FEATURE_WINDOW_RELATIVE`] of the feature scale (the smaller core's
//!   reach plus radius); the band is the larger of the window and the
//!   contact margin `m` (of the cores: the call's margin plus the radii)
//!   less the pair's separation, so that a point the margin counts as
//!   touching is a row, as a face contact's clipped points are
//!   ([`crate::contact::manifold`]). Why: a cylinder lying slightly
//!   tilted, one end sunk and the other within the margin, would
//!   otherwise have one row, whose correction lifts the sunk end by
//!   turning the body and sinks the other, so that each pass undoes about
//!   half of the last (the Rapier mixed pile's engine state: 9 passes
//!   without the band, 5 with it; `benchmarks/results/call_cost.md`,
//!   thirty-second session). A rim's samples stay within the window:
//!   taken within the band they cost the loop's mixed pile more than they
//!   saved (same section);
//! - each such point `p` becomes a row with its own signed distance to
//!   the other core (`point_distance`): the points `p` and its nearest
//!   point `c` of the other core, the normal at `c`, the separation
//!   `sd(p)`; a row only if that normal is within [`ROW_ALIGNMENT_COS`]
//!   of `n` and `sd(p) <= s + band` (within the window of the pair's
//!   separation, or within the margin). A row so built is the exact
//!   linearization of the non-penetration of the point (grown by its core's
//!   radius) and the other solid: it never asks more than that point needs;
//! - an outline point that fails is replaced by the last point of the
//!   chord from the central point towards it that passes with its
//!   nearest point on a flat piece of the other (a face or a cap; by
//!   bisection, the passing points of a chord being an interval): the
//!   touching feature clipped by the other's flat feature (a capsule
//!   across a cap's rim, a cylinder lying across a box's edge). Off a
//!   curved side (a box face under a lying cylinder) nothing is clipped:
//!   the contact there is the side's line, whose ends are outline points.
//!
//! When some outline row carries the pair's separation (within
//! [`TIE_RELATIVE`] of the size), the central point is dropped: it lies on
//! the same flat feature. At most [`MAX_ROUND_POINTS`] are kept: the
//! deepest, the farthest from it, and the farthest on each side of the
//! line through those two; among rows of equal depth, the extremes of the
//! feature (a cylinder lying on a face: the two ends of its side line; on
//! its cap: four rim points; a tilted rim: the central point alone).

use nalgebra::{Point3, Vector3};

use super::point_distance::point_distance;
use super::support_map::PosedCore;
use super::{CorePoint, MAX_ROUND_POINTS};

/// Height above its own support plane, relative to the feature scale,
/// within which an outline point belongs to the touching feature, and
/// by which its own separation may exceed the pair's.
pub const FEATURE_WINDOW_RELATIVE: f64 = 1e-3;

/// Least cosine between a row's own normal and the pair's: a point whose
/// nearest surface of the other solid faces elsewhere (a side face, the
/// far face of a thin plate) is not on the contact.
pub const ROW_ALIGNMENT_COS: f64 = 0.999;

/// A row's separation within this of the pair's, relative to the size,
/// carries the pair's separation (the central point is then dropped).
pub const TIE_RELATIVE: f64 = 1e-9;

/// Two contact points closer than this, relative to the pair's size, are
/// one.
pub const SAME_POINT_RELATIVE: f64 = 1e-6;

/// The contact points of two cores along unit `n` (module docs), `size`
/// the pair's (both reaches and the centres' distance), `margin` the
/// cores' contact margin (the call's plus both radii), and how many of
/// them are valid.
pub fn points(
    a: &PosedCore,
    b: &PosedCore,
    n: &Vector3<f64>,
    witnesses: Option<[Point3<f64>; 2]>,
    size: f64,
    margin: f64,
) -> ([CorePoint; MAX_ROUND_POINTS], usize) {
    let [top_a, top_b] = support_planes(a, b, n);
    let separation = top_a - top_b;
    let central = central_at(a, n, witnesses, [top_a, top_b]);
    let feature = (a.reach() + a.radius).min(b.reach() + b.radius);
    let window = FEATURE_WINDOW_RELATIVE * feature;
    // Up to the contact margin, as a face contact's clipped points (module
    // docs, "band").
    let band = window.max(margin - separation);
    let mut rows: Vec<CorePoint> = Vec::new();
    // A's points against B, then B's against A (`flip`).
    for (ours, theirs, from, flip) in [(a, b, central.on_a, 1.0), (b, a, central.on_b, -1.0)] {
        let own_top = if flip > 0.0 { top_a } else { top_b };
        let row = |p: &Point3<f64>, clipped: bool| -> Option<CorePoint> {
            let distance = point_distance(theirs, p)?;
            let normal = distance.normal * flip;
            let passes = normal.dot(n) >= ROW_ALIGNMENT_COS
                && distance.signed <= separation + band
                && (distance.flat || !clipped);
            let (on_a, on_b) = if flip > 0.0 {
                (*p, distance.closest)
            } else {
                (distance.closest, *p)
            };
            passes.then_some(CorePoint {
                on_a,
                on_b,
                separation: distance.signed,
                normal,
            })
        };
        for p in ours.outline(&(-n * flip), window) {
            if flip * (n.dot(&p.coords) - own_top) > band {
                continue;
            }
            let kept = row(&p, false).or_else(|| clip(&from, &p, |x| row(x, true), window));
            rows.extend(kept);
        }
    }
    let ties = rows
        .iter()
        .any(|r| r.separation <= separation + TIE_RELATIVE * size);
    if !ties {
        rows.push(central);
    }
    reduce(&rows, n, SAME_POINT_RELATIVE * size)
}

/// The central point of two cores along unit `n` (module docs): the
/// witnesses moved along `n` onto their support planes, or A's support
/// point and its partner on B's plane.
pub fn central_point(
    a: &PosedCore,
    b: &PosedCore,
    n: &Vector3<f64>,
    witnesses: Option<[Point3<f64>; 2]>,
) -> CorePoint {
    central_at(a, n, witnesses, support_planes(a, b, n))
}

/// The offsets `[t_A, t_B]` of A's and B's support planes along `n`
/// (module docs).
fn support_planes(a: &PosedCore, b: &PosedCore, n: &Vector3<f64>) -> [f64; 2] {
    [-a.support_value(&-n), b.support_value(n)]
}

/// [`central_point`] with the support planes `[t_A, t_B]` at hand.
fn central_at(
    a: &PosedCore,
    n: &Vector3<f64>,
    witnesses: Option<[Point3<f64>; 2]>,
    [top_a, top_b]: [f64; 2],
) -> CorePoint {
    let separation = top_a - top_b;
    match witnesses {
        Some([p_a, p_b]) => CorePoint {
            on_a: p_a + n * (top_a - n.dot(&p_a.coords)),
            on_b: p_b + n * (top_b - n.dot(&p_b.coords)),
            separation,
            normal: *n,
        },
        None => {
            let p = a.support(&-n);
            CorePoint {
                on_a: p,
                on_b: p - n * (n.dot(&p.coords) - top_b),
                separation,
                normal: *n,
            }
        }
    }
}

/// Steps of the bisection that clips a chord to the other solid.
pub const CLIP_BISECTIONS: usize = 30;

/// The row of the last point of the chord from `from` towards `to` (which
/// fails) that passes `row`, by bisection to `resolution`; `None` when
/// no point of the chord but `from` passes.
fn clip(
    from: &Point3<f64>,
    to: &Point3<f64>,
    row: impl Fn(&Point3<f64>) -> Option<CorePoint>,
    resolution: f64,
) -> Option<CorePoint> {
    let mut inside = None;
    let (mut low, mut high) = (0.0, 1.0);
    for _ in 0..CLIP_BISECTIONS {
        if (high - low) * (to - from).norm() <= resolution {
            break;
        }
        let middle = 0.5 * (low + high);
        match row(&(from + (to - from) * middle)) {
            Some(found) => {
                inside = Some(found);
                low = middle;
            }
            None => high = middle,
        }
    }
    inside
}

/// At most [`MAX_ROUND_POINTS`] of `candidates` (module docs); the first
/// candidate is never empty.
fn reduce(
    candidates: &[CorePoint],
    n: &Vector3<f64>,
    same: f64,
) -> ([CorePoint; MAX_ROUND_POINTS], usize) {
    let deepest = candidates
        .iter()
        .copied()
        .min_by(|p, q| p.separation.total_cmp(&q.separation))
        .unwrap_or(candidates[0]);
    let mut chosen = [deepest; MAX_ROUND_POINTS];
    let flat = |p: &CorePoint| {
        let d = p.on_b - deepest.on_b;
        d - n * n.dot(&d)
    };
    let farthest = candidates
        .iter()
        .copied()
        .max_by(|p, q| flat(p).norm().total_cmp(&flat(q).norm()))
        .filter(|p| flat(p).norm() > same);
    let Some(farthest) = farthest else {
        return (chosen, 1);
    };
    chosen[1] = farthest;
    let mut count = 2;
    let line = flat(&farthest);
    let side = |p: &CorePoint| n.dot(&line.cross(&flat(p)));
    let left = candidates
        .iter()
        .copied()
        .max_by(|p, q| side(p).total_cmp(&side(q)));
    let right = candidates
        .iter()
        .copied()
        .min_by(|p, q| side(p).total_cmp(&side(q)));
    let area_floor = same * line.norm();
    if let Some(left) = left.filter(|p| side(p) > area_floor) {
        chosen[count] = left;
        count += 1;
    }
    if let Some(right) = right.filter(|p| side(p) < -area_floor) {
        chosen[count] = right;
        count += 1;
    }
    (chosen, count)
}
