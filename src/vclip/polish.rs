//! Polishing a vertex–vertex or vertex–edge end state.
//!
//! The derivative check against a vertex `v`, `sign(u . (e(l) - v))`, is
//! decided by rounding when the edge is nearly parallel to an edge of `v`
//! and passes close by: `e(l) - v` is then nearly perpendicular to `u`, and
//! the dot product (exactly tiny) carries an absolute error of about `ε`
//! times the coordinates. The walk may then stop at the vertex while the
//! closest point lies inside one of its edges; the distance is off by up to
//! the edge length times the (tiny) angle, which Mirtich's degeneracy test
//! shows at the 1e-9 level. The remedy is cheap: compare the end pair with
//! the pairs that replace each end vertex by one of its edges (closest
//! points of segments, accurate for nearly parallel edges, see
//! [`super::closest`]) and keep the nearest. Every candidate is a pair of
//! points of the bodies, so this never reports less than the distance.

use nalgebra::Point3;

use super::closest::segment_segment;
use super::pair::Pair;
use crate::geometry::Feature;

/// The end points of a feature that is a vertex or an edge, in A's frame.
fn segment(pair: &Pair, body: usize, feature: Feature) -> Option<(Point3<f64>, Point3<f64>)> {
    let point = |v: usize| {
        if body == 0 {
            pair.vertex(0, v)
        } else {
            pair.vertex_in_other(1, v)
        }
    };
    match feature {
        Feature::Vertex(v) => Some((point(v), point(v))),
        Feature::Edge(e) => {
            let edge = &pair.polys[body].edges()[e];
            Some((point(edge.tail), point(edge.head)))
        }
        Feature::Face(_) => None,
    }
}

/// The nearest of the end pair and the pairs with one end vertex replaced by
/// an incident edge; features and closest points (`[on A, on B]`, A's frame).
pub(crate) fn polish(
    pair: &Pair,
    features: [Feature; 2],
    points: [Point3<f64>; 2],
) -> ([Feature; 2], [Point3<f64>; 2]) {
    let mut best = (features, points, (points[0] - points[1]).norm_squared());
    for body in 0..2 {
        let Feature::Vertex(v) = features[body] else {
            continue;
        };
        let Some((q0, q1)) = segment(pair, 1 - body, features[1 - body]) else {
            continue;
        };
        for &e in pair.polys[body].vertex_edges(v) {
            let mut candidate = features;
            candidate[body] = Feature::Edge(e);
            let Some((p0, p1)) = segment(pair, body, candidate[body]) else {
                continue;
            };
            let closest = segment_segment(&p0, &p1, &q0, &q1);
            if closest.distance_squared < best.2 {
                let on_body = p0 + (p1 - p0) * closest.s;
                let on_other = q0 + (q1 - q0) * closest.t;
                let points = if body == 0 {
                    [on_body, on_other]
                } else {
                    [on_other, on_body]
                };
                best = (candidate, points, closest.distance_squared);
            }
        }
    }
    (best.0, best.1)
}
