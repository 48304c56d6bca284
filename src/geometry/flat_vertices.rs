//! Vertices that barely rise above their neighbours.
//!
//! A vertex `v` on an almost flat part of the hull (a bump of points just
//! above a face, higher than the coplanar merge tolerance) makes faces
//! whose normals differ by tiny angles: valid, but V-Clip's Voronoi planes
//! between them are then nearly parallel. With `n̄` the normalized sum of
//! the (Newell, area-weighted) normals of the faces around `v`, its height
//! above its neighbours `u` is `h(v) = max_u (v - u)·n̄`: about the bump
//! height on a flat area, about `|v - u|·sin(angle)` at a real corner. When
//! `h(v)` is below [`FLAT_VERTEX_TOLERANCE`]` * max(L, M)` and every face
//! around `v` has its unit normal within [`FLAT_VERTEX_MAX_ANGLE`] of `n̄`,
//! `v` is dropped and the hull rebuilt. The angle condition makes the star
//! of `v` project one-to-one on the plane normal to `n̄`, so `v` is within
//! `h(v) / cos(angle)` of the fan of its neighbours, which stays (they are
//! protected for the round): the hull moves by about `h(v)`. (Without it a
//! real corner with only short edges would look flat: fuzz-tested.)
//! Bumps above [`FLAT_VERTEX_TOLERANCE`] stay: they are the corners of
//! solids at least that thin, which V-Clip must handle anyway.

use nalgebra::{Point3, Vector3};

use super::coplanar::HullFaces;
use super::index_maps::IndexSet;
use super::thin_faces::THIN_FACE_TOLERANCE;

/// Vertices less than `FLAT_VERTEX_TOLERANCE * max(L, M)` above their
/// neighbours are dropped; the same scale as thin faces, so that the hull
/// moves by at most about that much per round. Below
/// [`super::FLATNESS_TOLERANCE`] for the same reason as thin faces: the
/// apex of a flat pyramid (a square base and a point `h` above its
/// centre) has aligned faces and height `h`, so a larger tolerance would
/// drop the apex of a pyramid that the flatness test accepts as a solid.
pub const FLAT_VERTEX_TOLERANCE: f64 = THIN_FACE_TOLERANCE;

/// Largest angle between a face normal around a flat vertex and their mean.
pub const FLAT_VERTEX_MAX_ANGLE: f64 = 0.1;

/// Vertices (indices into `points`) lower than `min_height` above their
/// neighbours, no two of them adjacent.
pub(crate) fn flat_vertices(
    points: &[Point3<f64>],
    hull: &HullFaces,
    min_height: f64,
) -> Vec<usize> {
    let count = hull.vertices.len();
    let position = |v: usize| points[hull.vertices[v]];
    let mut normal_sum = vec![Vector3::zeros(); count];
    let mut face_normals: Vec<Vec<Vector3<f64>>> = vec![Vec::new(); count];
    let mut neighbours: Vec<Vec<usize>> = vec![Vec::new(); count];
    for cycle in &hull.faces {
        let area_normal = newell_area_normal(cycle.iter().map(|&v| position(v)));
        let unit = area_normal
            .try_normalize(0.0)
            .unwrap_or_else(Vector3::zeros);
        for (i, &v) in cycle.iter().enumerate() {
            normal_sum[v] += area_normal;
            face_normals[v].push(unit);
            neighbours[v].push(cycle[(i + 1) % cycle.len()]);
        }
    }
    let min_cosine = FLAT_VERTEX_MAX_ANGLE.cos();
    let mut protected: IndexSet<usize> = IndexSet::default();
    let mut dropped = Vec::new();
    for v in 0..count {
        let Some(n) = normal_sum[v].try_normalize(0.0) else {
            continue;
        };
        let height = neighbours[v]
            .iter()
            .map(|&u| (position(v) - position(u)).dot(&n))
            .fold(f64::NEG_INFINITY, f64::max);
        let aligned = face_normals[v].iter().all(|m| m.dot(&n) >= min_cosine);
        if height < min_height && aligned && !protected.contains(&v) {
            dropped.push(hull.vertices[v]);
            protected.extend(neighbours[v].iter().copied());
        }
    }
    dropped.sort_unstable();
    dropped
}

/// Twice the area times the unit normal of a polygon (Newell's sum).
fn newell_area_normal(corners: impl Iterator<Item = Point3<f64>> + Clone) -> Vector3<f64> {
    let first = corners.clone().next();
    let shifted = corners.clone().skip(1).chain(first);
    corners.zip(shifted).fold(Vector3::zeros(), |acc, (a, b)| {
        acc + a.coords.cross(&b.coords)
    })
}
