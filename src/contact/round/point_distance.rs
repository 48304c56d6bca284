//! The signed distance from a point to a core, with the nearest surface
//! point and the outward normal there: what a contact point of the
//! support-function manifold (`support_manifold`) asks of the other
//! solid.
//!
//! For a core `C` and a point `p` (world frame), `sd(p) = |p - c|` with
//! `c` the nearest point of `C` when `p` is outside, `-min` distance to
//! the boundary when inside; the normal is `(p - c)/|p - c|` outside and
//! the outward normal of the nearest boundary piece inside. A ball of
//! radius `r_p` about `p` and the core grown by `r_c` are then apart by
//! `sd(p) - r_p - r_c` along that normal, to first order in any rigid
//! motion of either: a row built on it is the exact linearization of the
//! non-penetration of that ball, never asking more than it needs.
//!
//! | core | nearest point |
//! |---|---|
//! | point | the point |
//! | segment | the clamped projection on it |
//! | polyhedron | inside: the nearest face plane (its foot lies in that face, the polyhedron being convex); outside: the nearest of the faces whose plane foot lies in the face and of every edge |
//! | cylinder, cone | the profile in the half plane through the axis (`CurvedSolid::signed_distance`) |

use nalgebra::Point3;

use super::support_map::{CoreShape, PosedCore};
use crate::geometry::ConvexPolyhedron;
use crate::geometry::curved::SurfaceDistance;

/// The signed distance of world point `p` to `core` (module docs), world
/// frame; `None` when no normal is defined (the point on a point or
/// segment core).
pub fn point_distance(core: &PosedCore, p: &Point3<f64>) -> Option<SurfaceDistance> {
    let local = core.pose.inverse_transform_point(p);
    let found = match &core.core {
        CoreShape::Point => away_from(&local, Point3::origin())?,
        CoreShape::Segment { half_length } => {
            let foot = Point3::new(0.0, 0.0, local.z.clamp(-half_length, *half_length));
            away_from(&local, foot)?
        }
        CoreShape::Polyhedron(polyhedron) => polyhedron_distance(polyhedron, &local)?,
        CoreShape::Curved(curved) => curved.signed_distance(&local)?,
    };
    Some(SurfaceDistance {
        closest: core.pose * found.closest,
        normal: core.pose.rotation * found.normal,
        ..found
    })
}

/// Distance of `p` from the core point `c` and the direction from `c`.
fn away_from(p: &Point3<f64>, c: Point3<f64>) -> Option<SurfaceDistance> {
    let offset = p - c;
    Some(SurfaceDistance {
        signed: offset.norm(),
        closest: c,
        normal: offset.try_normalize(0.0)?,
        flat: false,
    })
}

/// The signed distance of `p` (body frame) to a convex polyhedron (module
/// docs).
fn polyhedron_distance(polyhedron: &ConvexPolyhedron, p: &Point3<f64>) -> Option<SurfaceDistance> {
    let faces = polyhedron.faces();
    let (nearest_face, value) = faces
        .iter()
        .enumerate()
        .map(|(f, face)| (f, face.plane.signed_distance(p)))
        .max_by(|x, y| x.1.total_cmp(&y.1))?;
    if !value.is_finite() {
        return None;
    }
    if value <= 0.0 {
        let normal = faces[nearest_face].plane.normal;
        return Some(SurfaceDistance {
            signed: value,
            closest: p - normal * value,
            normal,
            flat: true,
        });
    }
    let mut best: Option<(f64, Point3<f64>, bool)> = None;
    let mut consider = |distance: f64, c: Point3<f64>, flat: bool| {
        if best.is_none_or(|(d, _, _)| distance < d) {
            best = Some((distance, c, flat));
        }
    };
    for (f, face) in faces.iter().enumerate() {
        let height = face.plane.signed_distance(p);
        if height <= 0.0 {
            continue;
        }
        let foot = p - face.plane.normal * height;
        let in_face = face
            .edges
            .iter()
            .all(|&e| polyhedron.face_edge_plane(e, f).signed_distance(&foot) >= 0.0);
        if in_face {
            consider(height, foot, true);
        }
    }
    for edge in polyhedron.edges() {
        let tail = polyhedron.vertices()[edge.tail];
        let t = (p - tail).dot(&edge.direction).clamp(0.0, edge.length);
        let c = tail + edge.direction * t;
        consider((p - c).norm(), c, false);
    }
    let (signed, closest, flat) = best?;
    Some(SurfaceDistance {
        signed,
        closest,
        normal: (p - closest).try_normalize(0.0)?,
        flat,
    })
}
