//! The vertex–face local minimum (Mirtich 1998, section 5.3).
//!
//! V-F with `V` on or below the plane of `F` and no edge of `V` pointing
//! toward `F`: `V` may be inside the other body, or the walk sits in a local
//! minimum of the signed distance. Test `V` against every face plane of
//! `F`'s body: if `V` is on or below all of them, it is inside (or on the
//! surface): penetration, witnessed by the face whose plane `V` is least
//! below (docs/design.md section 4). Otherwise `F ->` the face with the largest
//! signed distance of `V`, which is positive, so the walk cannot come back
//! to the same minimum. O(faces).

use super::pair::Pair;
use super::state::{Step, Witness};
use crate::geometry::Feature;

/// Handles the local minimum of vertex `v` (body `vertex_body`) under face
/// `f` of the other body.
pub(crate) fn local_minimum(pair: &Pair, vertex_body: usize, v: usize, f: usize) -> Step {
    let face_body = 1 - vertex_body;
    let p = pair.vertex_in_other(vertex_body, v);
    let mut best = (f, f64::NEG_INFINITY);
    for (g, face) in pair.polys[face_body].faces().iter().enumerate() {
        let d = face.plane.signed_distance(&p);
        if d > best.1 {
            best = (g, d);
        }
    }
    let (face, height) = best;
    if height <= 0.0 {
        Step::Penetration(Witness::VertexFace {
            vertex_body,
            vertex: v,
            face,
        })
    } else if face == f {
        // `V` is above `F` in `F`'s frame but not in its own: it lies on
        // `F`'s plane up to rounding, inside `VR(F)`: touching, distance ~0.
        Step::Done
    } else {
        Step::Move {
            body: face_body,
            to: Feature::Face(face),
        }
    }
}
