//! Pairs with a cylinder or cone part, on the true solids, by support
//! functions (`docs/round-shapes.md`, "Cylinders and cones").
//!
//! With the cores `C_A`, `C_B` ([`super::support_map`]) and the overlap
//! along a unit `n` (from B towards A)
//!
//! ```text
//! o(n) = h_A(-n) + h_B(n)
//! ```
//!
//! the cores' signed distance is `-min_n o(n)` (the widest separating gap
//! when apart, the least overlap when penetrating), and the solids' is that
//! minus both radii (module docs of [`super`]).
//!
//! 1. parry3d-f64's GJK (apart) or EPA (penetrating) on the two cores
//!    gives a first normal `n_0` and witness points.
//! 2. A pattern search on the sphere lowers `o` from `n_0` (steps from
//!    [`REFINE_FIRST_STEP`] down to [`REFINE_LAST_STEP`] radians, at most
//!    [`REFINE_EVALUATIONS`] evaluations of `o`). It only accepts a lower
//!    `o`, so the answer is never worse than EPA's, and the reported value
//!    `-o(n)` is an overlap actually reached on the exact support
//!    functions: the reported depth is never below the true depth and the
//!    reported distance never above the true distance (both are the safe
//!    side). How close it comes is measured against the oracle
//!    (`tests/it/round/oracle.rs`).
//! 3. The contact points come from [`super::support_manifold`], formed
//!    only when the pair's rows are built ([`DeferredPoints`]): most
//!    answers are read for their signed distance alone (every trial of a
//!    line search, and the detection of pairs that no solved island
//!    holds), and the points (each outline point with its own point
//!    distance, a bisection where it fails) cost about as much as the
//!    normal.
//!    The answer keeps its parts' poses, so the points formed later are
//!    the ones formed at the query, bit for bit.
//!
//! When EPA fails (degenerate simplex), the search starts from the best of
//! the centres' direction and the six axes.

use nalgebra::{Isometry3, Point3, Vector3};
use parry3d_f64::math::{Pose, Vector as ParryVector};
use parry3d_f64::query::details::contact_support_map_support_map_with_params;
use parry3d_f64::query::gjk::{GJKResult, VoronoiSimplex};

use super::super::BodyGeometry;
use super::support_manifold;
use super::support_map::PosedCore;
use super::{CoreContact, CorePoint, MAX_ROUND_POINTS};
use crate::contact::contact_row::tangent_basis;

/// First step of the pattern search on the sphere, radians.
pub const REFINE_FIRST_STEP: f64 = 1e-3;
/// Last step of the pattern search, radians (the overlap's change over
/// such a step is below 1e-20 of the size at a smooth minimum).
pub const REFINE_LAST_STEP: f64 = 1e-10;
/// Most evaluations of the overlap in one pattern search.
pub const REFINE_EVALUATIONS: usize = 160;

fn to_nalgebra(v: ParryVector) -> Vector3<f64> {
    Vector3::new(v.x, v.y, v.z)
}

/// The overlap `o(n) = h_A(-n) + h_B(n)` of two cores (module docs).
pub fn overlap(a: &PosedCore, b: &PosedCore, n: &Vector3<f64>) -> f64 {
    a.support_value(&-n) + b.support_value(n)
}

/// The cores' answer of a pair with a cylinder or cone (module docs).
pub fn contact(a: &BodyGeometry, b: &BodyGeometry) -> CoreContact {
    let core_a = PosedCore::of(a);
    let core_b = PosedCore::of(b);
    let centres = a.pose.translation.vector - b.pose.translation.vector;
    let size = core_a.reach() + core_b.reach() + centres.norm();
    let mut simplex = VoronoiSimplex::new();
    let towards_b = ParryVector::new(-centres.x, -centres.y, -centres.z);
    let answer = contact_support_map_support_map_with_params(
        &Pose::IDENTITY,
        &core_a,
        &core_b,
        // Larger than any distance between the cores: always an answer.
        2.0 * size,
        &mut simplex,
        towards_b.try_normalize(),
    );
    let (start, witnesses) = match answer {
        GJKResult::ClosestPoints(p_a, p_b, normal_a) => {
            let n = -to_nalgebra(normal_a);
            let witnesses = [p_a, p_b].map(|p| Point3::from(to_nalgebra(p)));
            (n.try_normalize(0.0), Some(witnesses))
        }
        _ => (None, None),
    };
    let start = start.unwrap_or_else(|| best_axis(&core_a, &core_b, &centres));
    let normal = refine(&core_a, &core_b, start);
    let signed_distance = -overlap(&core_a, &core_b, &normal);
    log::trace!(
        "support pair: start {start:?}, refined {normal:?}, overlap {:.6e}",
        -signed_distance
    );
    let central = support_manifold::central_point(&core_a, &core_b, &normal, witnesses);
    CoreContact {
        signed_distance,
        normal_world: normal,
        points: [central; MAX_ROUND_POINTS],
        count: 1,
        deferred: Some(DeferredPoints {
            poses: [a.pose, b.pose],
            witnesses,
            size,
        }),
    }
}

/// What [`support_manifold::points`] needs besides the pair's parts and
/// normal: the parts' poses at the query (so that the points are those of
/// the answer, wherever the parts are when they are read), GJK's or EPA's
/// witness points and the pair's size.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DeferredPoints {
    poses: [Isometry3<f64>; 2],
    witnesses: Option<[Point3<f64>; 2]>,
    size: f64,
}

impl DeferredPoints {
    /// The contact points of the answer along `normal` (its
    /// [`CoreContact::normal_world`]) of parts `a` and `b` at the poses of
    /// the query, with the cores' contact margin `margin`, and how many.
    pub fn points(
        &self,
        a: &BodyGeometry,
        b: &BodyGeometry,
        normal: &Vector3<f64>,
        margin: f64,
    ) -> ([CorePoint; MAX_ROUND_POINTS], usize) {
        let [pose_a, pose_b] = self.poses;
        let core_a = PosedCore::of(&BodyGeometry { pose: pose_a, ..*a });
        let core_b = PosedCore::of(&BodyGeometry { pose: pose_b, ..*b });
        let (points, count) =
            support_manifold::points(&core_a, &core_b, normal, self.witnesses, self.size, margin);
        log::trace!("support pair: {count} points");
        (points, count.min(MAX_ROUND_POINTS))
    }
}

/// The direction of least overlap among the centres' and the six axes.
fn best_axis(a: &PosedCore, b: &PosedCore, centres: &Vector3<f64>) -> Vector3<f64> {
    let axes = [
        Vector3::x(),
        -Vector3::x(),
        Vector3::y(),
        -Vector3::y(),
        Vector3::z(),
        -Vector3::z(),
    ];
    centres
        .try_normalize(0.0)
        .into_iter()
        .chain(axes)
        .min_by(|m, n| overlap(a, b, m).total_cmp(&overlap(a, b, n)))
        .unwrap_or_else(Vector3::z)
}

/// The pattern search on the sphere (module docs), from unit `start`.
///
/// A cylinder's or cone's side (or a segment) makes the overlap a ridge
/// along the great circle perpendicular to its axis `u`: off the ridge every compass move
/// climbs its flank. So a point within a step of the ridge is first moved
/// onto it, and on it the compass is turned to `u x n` (along the ridge)
/// and `u` (across it).
fn refine(a: &PosedCore, b: &PosedCore, start: Vector3<f64>) -> Vector3<f64> {
    let axes: Vec<Vector3<f64>> = [a.ridge_axis(), b.ridge_axis()]
        .into_iter()
        .flatten()
        .collect();
    let mut n = start;
    let mut best = overlap(a, b, &n);
    let mut step = REFINE_FIRST_STEP;
    let mut evaluations = 1;
    while step >= REFINE_LAST_STEP && evaluations < REFINE_EVALUATIONS {
        let mut basis = tangent_basis(&n);
        let mut candidates: Vec<Vector3<f64>> = Vec::with_capacity(10);
        for u in &axes {
            let across = n.dot(u);
            if across.abs() <= step {
                if let Some(on_ridge) = (n - u * across).try_normalize(0.0) {
                    candidates.push(on_ridge);
                }
                if let Some(along) = u.cross(&n).try_normalize(0.0) {
                    basis = [along, n.cross(&along)];
                }
            }
        }
        let [t1, t2] = basis;
        for t in [t1, -t1, t2, -t2, t1 + t2, -t1 - t2, t1 - t2, t2 - t1] {
            if let Some(candidate) = (n + t * step).try_normalize(0.0) {
                candidates.push(candidate);
            }
        }
        let mut moved = false;
        for candidate in candidates {
            let value = overlap(a, b, &candidate);
            evaluations += 1;
            if value < best {
                best = value;
                n = candidate;
                moved = true;
                break;
            }
        }
        if !moved {
            step *= 0.25;
        }
    }
    n
}
