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
