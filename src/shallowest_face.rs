//! From a V-Clip penetration witness to a shallow separating face.
//!
//! The deepest-vertex search (DESIGN.md section 4) measures the depth of a
//! penetration below the witness face `f` of body F: `depth_f = -min_v
//! D_f(v)` over the vertices `v` of the other body V. Any face gives an
//! upper bound of the penetration depth (translating V by `depth_f` along
//! `f`'s normal separates the bodies), but the witness face can be a poor
//! one: an edge that pierces the side face of a box resting on it gives a
//! depth of the whole box. The stabilizer wants the smallest correction, so
//! this module descends over faces:
//!
//! ```text
//! depth(f) = max_v  -(n_f . v_world + w_f)         (support of V along -n_f)
//! f <- argmin over the faces adjacent to f of depth, while it decreases
//! ```
//!
//! on both bodies: from the witness face on its body, and from the face of
//! the other body whose normal is most opposed to the witness normal. The
//! support vertex is found by hill climbing over V's vertex graph (exact on
//! a convex polyhedron, since `n . v` is linear), warm-started from the
//! previous face's support vertex. The minimum over face normals is the
//! separating-axis depth restricted to face normals: continuous in the
//! poses, an upper bound of the exact depth (which may need an edge-edge
//! direction), and never worse than the witness face.

use nalgebra::{Isometry3, Point3, Vector3};

use crate::geometry::ConvexPolyhedron;
use crate::vclip::{BodyRole, DeepestVertex};

/// A body of the pair, with its role in the V-Clip query.
#[derive(Debug, Clone, Copy)]
pub struct PairBody<'a> {
    /// The polyhedron (body frame).
    pub shape: &'a ConvexPolyhedron,
    /// Centre-of-mass pose.
    pub pose: &'a Isometry3<f64>,
}

/// The vertex–face pair of smallest depth found by descent from `witness`.
pub fn shallowest_face(witness: DeepestVertex, a: PairBody, b: PairBody) -> DeepestVertex {
    let (vertex_body, face_body) = match witness.vertex_body {
        BodyRole::A => (a, b),
        BodyRole::B => (b, a),
    };
    let from_witness = descend(
        witness.vertex_body,
        face_body,
        vertex_body,
        witness.face,
        witness.vertex,
    );
    let opposed_face = most_aligned_face(vertex_body, &-witness.normal_world);
    let from_other = descend(
        witness.vertex_body.other(),
        vertex_body,
        face_body,
        opposed_face,
        0,
    );
    [witness, from_witness, from_other]
        .into_iter()
        .min_by(|x, y| x.depth.total_cmp(&y.depth))
        .unwrap_or(witness)
}

/// Descent over the faces of `face_body` starting at `face`; `vertex_role`
/// is the role of `vertex_body` in the query.
fn descend(
    vertex_role: BodyRole,
    face_body: PairBody,
    vertex_body: PairBody,
    start_face: usize,
    start_vertex: usize,
) -> DeepestVertex {
    let mut best = face_depth(
        vertex_role,
        face_body,
        vertex_body,
        start_face,
        start_vertex,
    );
    for _ in 0..face_body.shape.faces().len() {
        let neighbours = adjacent_faces(face_body.shape, best.face);
        let candidate = neighbours
            .map(|g| face_depth(vertex_role, face_body, vertex_body, g, best.vertex))
            .min_by(|x, y| x.depth.total_cmp(&y.depth));
        match candidate {
            Some(c) if c.depth < best.depth => best = c,
            _ => break,
        }
    }
    best
}

/// The depth of `vertex_body` below face `face` of `face_body`.
fn face_depth(
    vertex_role: BodyRole,
    face_body: PairBody,
    vertex_body: PairBody,
    face: usize,
    hint_vertex: usize,
) -> DeepestVertex {
    let plane = &face_body.shape.faces()[face].plane;
    let normal_world = face_body.pose.rotation * plane.normal;
    let point_on_plane = face_body.pose * Point3::from(plane.normal * -plane.offset);
    let direction_body = vertex_body.pose.rotation.inverse() * -normal_world;
    let vertex = support_vertex(vertex_body.shape, &direction_body, hint_vertex);
    let vertex_world = vertex_body.pose * vertex_body.shape.vertices()[vertex];
    DeepestVertex {
        vertex_body: vertex_role,
        vertex,
        face,
        depth: -normal_world.dot(&(vertex_world - point_on_plane)),
        vertex_world,
        normal_world,
    }
}

/// The vertex maximizing `direction . v`, by hill climbing from `start`.
fn support_vertex(shape: &ConvexPolyhedron, direction: &Vector3<f64>, start: usize) -> usize {
    let vertices = shape.vertices();
    let mut current = start.min(vertices.len() - 1);
    for _ in 0..vertices.len() {
        let height = direction.dot(&vertices[current].coords);
        let better = shape
            .vertex_edges(current)
            .iter()
            .map(|&e| shape.other_vertex(e, current))
            .map(|v| (v, direction.dot(&vertices[v].coords)))
            .filter(|&(_, h)| h > height)
            .max_by(|x, y| x.1.total_cmp(&y.1));
        match better {
            Some((v, _)) => current = v,
            None => break,
        }
    }
    current
}

/// Faces sharing an edge with `face`.
fn adjacent_faces(shape: &ConvexPolyhedron, face: usize) -> impl Iterator<Item = usize> + '_ {
    shape.faces()[face].edges.iter().map(move |&e| {
        let edge = &shape.edges()[e];
        if edge.left_face == face {
            edge.right_face
        } else {
            edge.left_face
        }
    })
}

/// The face whose world normal is most aligned with `direction_world`.
fn most_aligned_face(body: PairBody, direction_world: &Vector3<f64>) -> usize {
    let direction_body = body.pose.rotation.inverse() * direction_world;
    body.shape
        .faces()
        .iter()
        .enumerate()
        .max_by(|x, y| {
            let (dx, dy) = (
                x.1.plane.normal.dot(&direction_body),
                y.1.plane.normal.dot(&direction_body),
            );
            dx.total_cmp(&dy)
        })
        .map_or(0, |(f, _)| f)
}

/// Overlap, relative to the smaller circumradius of a pair, up to which a
/// pair that V-Clip reports as touching (distance 0) is taken as touching.
/// V-Clip can stop at coincident features with distance 0 while the solids
/// overlap (two equal boxes at one pose; a box stacked on an equal box, whose
/// bottom vertices lie on the side planes of the one below).
pub const TOUCHING_OVERLAP_RELATIVE: f64 = 1e-9;

/// Separating-axis check of a pair that V-Clip reports as touching: `None`
/// if a face normal of either body or a cross product of two edges
/// separates the bodies to within `threshold` (they touch at most), else
/// the shallowest vertex–face pair over the face normals of both bodies.
///
/// ```text
/// overlap(u) = min(max_A u.p - min_B u.p, max_B u.p - min_A u.p)
/// ```
///
/// over the world vertices; the bodies overlap iff `overlap(u) > 0` for
/// every face normal and edge–edge axis `u` (separating axis theorem for
/// convex polyhedra). Cost `O(E_A E_B (V_A + V_B))`, paid only on the rare
/// distance-0 outcome.
pub fn overlap_of_touching(a: PairBody, b: PairBody, threshold: f64) -> Option<DeepestVertex> {
    let faces_of_a = (0..a.shape.faces().len()).map(|f| face_depth(BodyRole::B, a, b, f, 0));
    let faces_of_b = (0..b.shape.faces().len()).map(|f| face_depth(BodyRole::A, b, a, f, 0));
    let shallowest = faces_of_a
        .chain(faces_of_b)
        .min_by(|x, y| x.depth.total_cmp(&y.depth))?;
    if shallowest.depth <= threshold || edge_axes_separate(a, b, threshold) {
        return None;
    }
    Some(shallowest)
}

/// Whether some axis `e_a x e_b` separates the bodies to within `threshold`.
fn edge_axes_separate(a: PairBody, b: PairBody, threshold: f64) -> bool {
    let world = |body: PairBody| -> Vec<Point3<f64>> {
        body.shape
            .vertices()
            .iter()
            .map(|v| body.pose * v)
            .collect()
    };
    let (points_a, points_b) = (world(a), world(b));
    let span = |points: &[Point3<f64>], axis: &Vector3<f64>| {
        points
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                let h = axis.dot(&p.coords);
                (lo.min(h), hi.max(h))
            })
    };
    a.shape.edges().iter().any(|edge_a| {
        let da = a.pose.rotation * edge_a.direction;
        b.shape.edges().iter().any(|edge_b| {
            let db = b.pose.rotation * edge_b.direction;
            // Parallel edges give no axis that the face normals miss.
            let Some(axis) = da.cross(&db).try_normalize(PARALLEL_EDGES_SINE) else {
                return false;
            };
            let (min_a, max_a) = span(&points_a, &axis);
            let (min_b, max_b) = span(&points_b, &axis);
            (max_a - min_b).min(max_b - min_a) <= threshold
        })
    })
}

/// Sine of the angle below which two edge directions count as parallel
/// (unit directions: `|d_a x d_b|` is that sine).
const PARALLEL_EDGES_SINE: f64 = 1e-9;
