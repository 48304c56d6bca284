//! The closest points of the final feature pair of a separated query.
//!
//! When V-Clip stops, the closest points of the two features are the
//! closest points of the two bodies (Theorem 1). Computed in A's frame:
//! vertex–vertex directly, vertex–edge by clamped projection, vertex–face by
//! projection on the face plane (the vertex is in the face's Voronoi prism),
//! edge–edge by [`segment_segment`]. A done state is never edge–face or
//! face–face (those states always move or report penetration).

use nalgebra::Point3;

use super::closest::{project_on_segment, segment_segment};
use super::pair::Pair;
use crate::geometry::Feature;

/// Closest points `(on A, on B)`, both in A's frame, or `None` for a pair
/// that is never a done state.
pub(crate) fn closest_points(pair: &Pair, features: [Feature; 2]) -> Option<[Point3<f64>; 2]> {
    use Feature::{Edge, Face, Vertex};
    let points = match (features[0], features[1]) {
        (Vertex(a), Vertex(b)) => [pair.vertex(0, a), pair.vertex_in_other(1, b)],
        (Vertex(a), Edge(b)) => {
            let p = pair.vertex(0, a);
            [p, point_on_edge_near(pair, 1, b, &p)]
        }
        (Edge(a), Vertex(b)) => {
            let p = pair.vertex_in_other(1, b);
            [point_on_edge_near(pair, 0, a, &p), p]
        }
        (Vertex(a), Face(b)) => {
            let p_b = pair.vertex_in_other(0, a);
            let plane = pair.polys[1].faces()[b].plane;
            let q_b = p_b - plane.normal * plane.signed_distance(&p_b);
            [pair.vertex(0, a), pair.to_other[1].point(&q_b)]
        }
        (Face(a), Vertex(b)) => {
            let p = pair.vertex_in_other(1, b);
            let plane = pair.polys[0].faces()[a].plane;
            [p - plane.normal * plane.signed_distance(&p), p]
        }
        (Edge(a), Edge(b)) => {
            let edge_a = &pair.polys[0].edges()[a];
            let (t_a, h_a) = (pair.vertex(0, edge_a.tail), pair.vertex(0, edge_a.head));
            let (t_b, h_b) = pair.edge_in_other(1, b);
            let closest = segment_segment(&t_a, &h_a, &t_b, &h_b);
            [t_a + (h_a - t_a) * closest.s, t_b + (h_b - t_b) * closest.t]
        }
        _ => return None,
    };
    Some(points)
}

/// The point of edge `e` of `body`, in A's frame, closest to `p` (A's frame).
fn point_on_edge_near(pair: &Pair, body: usize, e: usize, p: &Point3<f64>) -> Point3<f64> {
    let (tail, head) = if body == 0 {
        let edge = &pair.polys[0].edges()[e];
        (pair.vertex(0, edge.tail), pair.vertex(0, edge.head))
    } else {
        pair.edge_in_other(1, e)
    };
    tail + (head - tail) * project_on_segment(p, &tail, &head)
}
