//! Contact points of a support-function pair (`support_pair`): a flat
//! contact gets points over the whole touching region, a curved one its
//! single deepest point.
//!
//! With the normal `n` (from B towards A), A's support plane
//! `n . x = t_A = -h_A(-n)` and B's `n . x = t_B = h_B(n)`
//! (`t_A - t_B = -o(n)`):
//!
//! - the central point: the witnesses of GJK/EPA, each moved along `n`
//!   onto its support plane (separation `t_A - t_B`, the pair's signed
//!   distance), or, without witnesses, A's support point and its partner
//!   straight along `n` on B's plane;
//! - each outline point `p` of A within [`FEATURE_WINDOW_RELATIVE`] of the
//!   size above A's plane (its face, side line or rim towards B), paired
//!   with `q = p - (n . p - t_B) n` on B's plane when `q` lies in B (within
//!   [`CONTAINS_SLACK_RELATIVE`]): separation `n . p - t_B`, the point's
//!   own height above B's plane;
//! - the same for B's outline points, onto A's plane;
//! - for an outline point whose partner falls outside the other solid,
//!   the last point of the chord from the central point towards it whose
//!   partner is still in it (by bisection): the touching feature clipped
//!   by the other's (a capsule across a cap's rim, a cap over an edge).
//!
//! Every point pairs a point of A with a point of B straight along `n`, so
//! a row's lever arms are those of the contact. A cylinder on its cap gets
//! the rim samples over a face (and the face's corners over the cap), a
//! cylinder lying on its side the ends of its side line; the containment
//! slack adds clipped points up to `sqrt(2 r slack)` beside a side line or
//! a rim (rows asking at most the slack more than needed). At most
//! [`MAX_ROUND_POINTS`] are kept: the deepest, the farthest from it, and
//! the farthest on each side of the line through those two.

use nalgebra::{Point3, Vector3};

use super::support_map::PosedCore;
use super::{CorePoint, MAX_ROUND_POINTS};

/// Height above a support plane, relative to the pair's size, within
/// which an outline point belongs to the touching feature (at `1e-2` a
/// lying cylinder's rim samples next to its bottom line, 1.1 cm above the
/// face, were kept as the farthest points and then dropped by the contact
/// margin, leaving no row at the ends of the line).
pub const FEATURE_WINDOW_RELATIVE: f64 = 1e-3;

/// Distance, relative to the pair's size, by which a point projected onto
/// the other's support plane may lie outside the other solid and still
/// count as on it (the rounding of the projection; two nearly parallel side
/// lines).
pub const CONTAINS_SLACK_RELATIVE: f64 = 1e-2;

/// Two contact points closer than this, relative to the pair's size, are
/// one.
pub const SAME_POINT_RELATIVE: f64 = 1e-6;

/// The contact points of two cores along unit `n` (module docs), `size`
/// the pair's (both reaches and the centres' distance), and how many of
/// them are valid.
pub fn points(
    a: &PosedCore,
    b: &PosedCore,
    n: &Vector3<f64>,
    witnesses: Option<[Point3<f64>; 2]>,
    size: f64,
) -> ([CorePoint; MAX_ROUND_POINTS], usize) {
    let top_a = -a.support_value(&-n);
    let top_b = b.support_value(n);
    let central = match witnesses {
        Some([p_a, p_b]) => CorePoint {
            on_a: p_a + n * (top_a - n.dot(&p_a.coords)),
            on_b: p_b + n * (top_b - n.dot(&p_b.coords)),
            separation: top_a - top_b,
        },
        None => {
            let p = a.support(&-n);
            CorePoint {
                on_a: p,
                on_b: p - n * (n.dot(&p.coords) - top_b),
                separation: top_a - top_b,
            }
        }
    };
    let window = FEATURE_WINDOW_RELATIVE * size;
    let slack = CONTAINS_SLACK_RELATIVE * size;
    let mut candidates = vec![central];
    // A's points over B's plane, then B's under A's plane (`flip`): the
    // outline point, and where it leaves the other solid, the last point
    // on the chord from the central point towards it that stays over the
    // other (its feature clipped by the other's).
    for (ours, theirs, from, flip) in [(a, b, central.on_a, 1.0), (b, a, central.on_b, -1.0)] {
        let (own_top, other_top) = if flip > 0.0 {
            (top_a, top_b)
        } else {
            (top_b, top_a)
        };
        let d = n * flip;
        let over = |p: &Point3<f64>| {
            let height = n.dot(&p.coords);
            theirs.contains(&(p - n * (height - other_top)), slack)
        };
        for p in ours.outline(&-d) {
            let height = n.dot(&p.coords);
            if flip * (height - own_top) > window {
                continue;
            }
            let kept = if over(&p) {
                Some(p)
            } else {
                clip(&from, &p, &over, slack)
            };
            if let Some(p) = kept {
                let height = n.dot(&p.coords);
                let partner = p - n * (height - other_top);
                let (on_a, on_b) = if flip > 0.0 {
                    (p, partner)
                } else {
                    (partner, p)
                };
                candidates.push(CorePoint {
                    on_a,
                    on_b,
                    separation: n.dot(&(on_a - on_b)),
                });
            }
        }
    }
    reduce(&candidates, n, SAME_POINT_RELATIVE * size)
}

/// Steps of the bisection that clips a chord to the other solid.
pub const CLIP_BISECTIONS: usize = 30;

/// The last point of the chord from `from` (over the other solid) towards
/// `to` (not over it) that is still over it, by bisection to `slack`;
/// `None` when `from` itself is not over it.
fn clip(
    from: &Point3<f64>,
    to: &Point3<f64>,
    over: &impl Fn(&Point3<f64>) -> bool,
    slack: f64,
) -> Option<Point3<f64>> {
    if !over(from) {
        return None;
    }
    let (mut inside, mut outside) = (0.0, 1.0);
    for _ in 0..CLIP_BISECTIONS {
        if (outside - inside) * (to - from).norm() <= slack {
            break;
        }
        let middle = 0.5 * (inside + outside);
        if over(&(from + (to - from) * middle)) {
            inside = middle;
        } else {
            outside = middle;
        }
    }
    (inside > 0.0).then(|| from + (to - from) * inside)
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
