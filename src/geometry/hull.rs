//! Convex hull of a point set: [`ConvexPolyhedron::from_points`].
//!
//! Pipeline. `L` is the extent of the input (diagonal of its axis-aligned
//! bounding box) and `M` its largest absolute coordinate; tolerances that
//! absorb rounding of the input scale with `max(L, M)`, because a
//! coordinate carries rounding of order `ε M`.
//! 1. Reject an empty set, non-finite coordinates (the index is named),
//!    coordinates beyond [`MAX_COORDINATE`] and extents below
//!    [`MIN_EXTENT`].
//! 2. Merge points closer than [`DUPLICATE_TOLERANCE`]` * L` to a kept
//!    point (greedy, in order of `x`), so that near duplicates are never
//!    handed to the hull algorithm as distinct vertices.
//! 3. Reject sets without volume before any hull is computed: with `p0` an
//!    extreme point, `p1` the point farthest from `p0`, `p2` the point
//!    farthest from the line `p0 p1` and `p3` the point farthest from the
//!    plane `p0 p1 p2`, the set is all equal, collinear or coplanar when
//!    `|p1 - p0|`, `dist(p2, line)` or `dist(p3, plane)` is at most
//!    [`FLATNESS_TOLERANCE`]` * L`.
//! 4. Triangulated hull with exact predicates from the simplex
//!    `p0 p1 p2 p3` (`super::exact_hull`): exactly convex for the given
//!    floats, whatever the coplanar and collinear points.
//! 5. Coplanar triangles are merged into polygonal faces and vertices that
//!    are not corners are dropped (`super::coplanar`).
//! 6. Faces too thin for an accurate plane lose their inner vertices
//!    (`super::thin_faces`); when there are none, vertices that barely rise
//!    above their neighbours are dropped (`super::flat_vertices`). The hull
//!    is rebuilt from the remaining vertices, at most
//!    [`MAX_SIMPLIFICATION_ROUNDS`] times.
//!
//! The tolerances are ordered: duplicates ([`DUPLICATE_TOLERANCE`]` = 1e-10`)
//! < thin faces and flat vertices ([`THIN_FACE_TOLERANCE`]` = 1e-9`) <
//! flatness ([`FLATNESS_TOLERANCE`]` = 1e-8`). So a set accepted as a solid
//! in step 3 is wider than anything step 6 removes, and keeps its corners
//! (a slab of relative thickness just above the flatness tolerance is its
//! box), as long as `M < 10 L`.
//! 7. [`ConvexPolyhedron::from_faces`] checks topology, planarity and
//!    convexity; finally every merged input point must lie on or below every
//!    face plane within [`CONTAINMENT_TOLERANCE`]` * max(L, M)`.
//!
//! Why not parry's hull (`parry3d_f64::transformation::try_convex_hull`):
//! it decides that a set is flat when an eigenvalue of its normalized
//! covariance is below `1e-7`, so solids thinner than about `3e-4 L` come
//! back as a flat double-sided mesh; and on a rotated `5 × 5 × 3` lattice
//! (many coplanar points) it can return a non-convex triangle mesh. Exact
//! predicates cannot produce either.

use nalgebra::Point3;

use super::coplanar::{COPLANAR_TOLERANCE, HullFaces, polygon_faces};
use super::exact_hull::hull_triangles;
use super::flat_vertices::flat_vertices;
use super::index_maps::IndexSet;
use super::thin_faces::{THIN_FACE_TOLERANCE, thin_face_vertices};
use super::{ConvexPolyhedron, GeometryError};

/// Two input points closer than `DUPLICATE_TOLERANCE * L` are one point.
pub const DUPLICATE_TOLERANCE: f64 = 1e-10;

/// A point set whose width (as estimated in step 3 of the module doc) is at
/// most `FLATNESS_TOLERANCE * L` has no volume at the precision of `f64`
/// face normals and is rejected as degenerate.
pub const FLATNESS_TOLERANCE: f64 = 1e-8;

/// Largest accepted absolute coordinate. Inertia scales as `L⁵` and the
/// exact orientation predicate multiplies three coordinate differences:
/// below `1e50` neither comes near overflow (`f64::MAX ≈ 1.8e308`).
pub const MAX_COORDINATE: f64 = 1e50;

/// Smallest accepted extent `L` (a set of distinct points closer together
/// is rejected): keeps `L⁵` and the predicate's products far from
/// underflow (`f64::MIN_POSITIVE ≈ 2.2e-308`).
pub const MIN_EXTENT: f64 = 1e-50;

/// After the hull is built, every (merged) input point must lie at most
/// `CONTAINMENT_TOLERANCE * max(L, M)` above every face plane: a few rounds
/// of thin-face removal, each moving the hull by at most about
/// [`THIN_FACE_TOLERANCE`]` * max(L, M)`.
pub const CONTAINMENT_TOLERANCE: f64 = 8.0 * THIN_FACE_TOLERANCE;

/// Rounds of thin-face removal (each drops at least one vertex) before the
/// hull is declared failed.
pub const MAX_SIMPLIFICATION_ROUNDS: usize = 32;

impl ConvexPolyhedron {
    /// The convex hull of `points` (given in the shape frame), with
    /// coplanar triangles merged into polygonal faces. The vertices of the
    /// result are a subset of the input points (stored relative to the
    /// centre of mass, see [`ConvexPolyhedron::shape_origin_offset`]).
    ///
    /// Vertices closer than about [`THIN_FACE_TOLERANCE`]` * max(L, M)` to
    /// the hull of the others may be dropped (module doc, step 6), so the
    /// result contains every input point within
    /// [`CONTAINMENT_TOLERANCE`]` * max(L, M)`.
    ///
    /// Errors: [`GeometryError::Empty`], [`GeometryError::NonFinite`],
    /// [`GeometryError::CoordinatesOutOfRange`],
    /// [`GeometryError::Degenerate`] (all equal, collinear or coplanar after
    /// merging near duplicates), and, should the checks of the result fail
    /// (possible far from the origin, where the rounding of the
    /// coordinates approaches the tolerances and a face can collapse when
    /// edge points are removed; `benchmarks/results/reliability.md`),
    /// [`GeometryError::HullFailed`],
    /// [`GeometryError::InvalidTopology`] or [`GeometryError::NotConvex`].
    pub fn from_points(points: &[Point3<f64>]) -> Result<Self, GeometryError> {
        let (extent, largest) = checked_extent(points)?;
        let tolerances = Tolerances::new(extent, largest);
        let kept = merge_near_duplicates(points, tolerances.duplicate);
        let kept_points: Vec<Point3<f64>> = kept.iter().map(|&i| points[i]).collect();
        let mut active = kept_points.clone();
        for round in 0..MAX_SIMPLIFICATION_ROUNDS {
            let hull = polygon_hull(&active, &tolerances)?;
            let mut thin = thin_face_vertices(&active, &hull, tolerances.thin_face);
            if thin.is_empty() {
                thin = flat_vertices(&active, &hull, tolerances.thin_face);
            }
            log::trace!(
                "hull round {round}: {} of {} points -> {} vertices, {} faces; {} thin-face vertices dropped",
                active.len(),
                points.len(),
                hull.vertices.len(),
                hull.faces.len(),
                thin.len()
            );
            if thin.is_empty() {
                let hull_points: Vec<Point3<f64>> =
                    hull.vertices.iter().map(|&i| active[i]).collect();
                let polyhedron = Self::from_faces(hull_points.clone(), hull.faces)?;
                let inner = inner_points(&kept_points, &hull_points);
                polyhedron.check_contains(&inner, tolerances.containment)?;
                return Ok(polyhedron);
            }
            active = hull
                .vertices
                .iter()
                .filter(|i| thin.binary_search(i).is_err())
                .map(|&i| active[i])
                .collect();
        }
        Err(GeometryError::HullFailed(format!(
            "thin faces remain after {MAX_SIMPLIFICATION_ROUNDS} rounds"
        )))
    }

    /// Checks that every point (shape frame) is on or below every face plane
    /// within `tolerance`.
    fn check_contains(
        &self,
        points_shape: &[Point3<f64>],
        tolerance: f64,
    ) -> Result<(), GeometryError> {
        let offset = self.shape_origin_offset();
        for p_shape in points_shape {
            let p_body = p_shape - offset;
            let height = self
                .faces()
                .iter()
                .map(|face| face.plane.signed_distance(&p_body))
                .fold(f64::NEG_INFINITY, f64::max);
            if height > tolerance {
                return Err(GeometryError::HullFailed(format!(
                    "point {p_shape} is {height:e} outside the hull"
                )));
            }
        }
        Ok(())
    }
}

/// The absolute tolerances of one call, from the extent `L` and the largest
/// coordinate `M` of the input (module doc).
struct Tolerances {
    duplicate: f64,
    flatness: f64,
    coplanar: f64,
    thin_face: f64,
    containment: f64,
}

impl Tolerances {
    fn new(extent: f64, largest: f64) -> Self {
        let precision_scale = extent.max(largest);
        Tolerances {
            duplicate: DUPLICATE_TOLERANCE * extent,
            flatness: FLATNESS_TOLERANCE * extent,
            coplanar: COPLANAR_TOLERANCE * precision_scale,
            thin_face: THIN_FACE_TOLERANCE * precision_scale,
            containment: CONTAINMENT_TOLERANCE * precision_scale,
        }
    }
}

/// Steps 3 to 5 of the module doc on `points`.
fn polygon_hull(
    points: &[Point3<f64>],
    tolerances: &Tolerances,
) -> Result<HullFaces, GeometryError> {
    let simplex = extreme_simplex(points, tolerances.flatness)?;
    let triangles = hull_triangles(points, simplex)?;
    polygon_faces(points, &triangles, tolerances.coplanar)
}

/// The points that are not (bitwise) vertices of the hull: vertices are
/// checked by [`ConvexPolyhedron::from_faces`] already.
fn inner_points(points: &[Point3<f64>], hull_points: &[Point3<f64>]) -> Vec<Point3<f64>> {
    let bits = |p: &Point3<f64>| p.coords.map(f64::to_bits);
    let vertices: IndexSet<_> = hull_points.iter().map(bits).collect();
    points
        .iter()
        .filter(|p| !vertices.contains(&bits(p)))
        .copied()
        .collect()
}

/// Validates the coordinates and returns the extent `L` (bounding-box
/// diagonal) of the point set and its largest absolute coordinate `M`.
fn checked_extent(points: &[Point3<f64>]) -> Result<(f64, f64), GeometryError> {
    if points.is_empty() {
        return Err(GeometryError::Empty);
    }
    if let Some(index) = points
        .iter()
        .position(|p| !p.coords.iter().all(|c| c.is_finite()))
    {
        return Err(GeometryError::NonFinite { index });
    }
    let (lower, upper) = points
        .iter()
        .fold((points[0].coords, points[0].coords), |(lower, upper), p| {
            (lower.inf(&p.coords), upper.sup(&p.coords))
        });
    let largest = lower.abs().sup(&upper.abs()).max();
    let extent = (upper - lower).norm();
    if extent == 0.0 {
        return Err(GeometryError::Degenerate);
    }
    if largest > MAX_COORDINATE || extent < MIN_EXTENT {
        return Err(GeometryError::CoordinatesOutOfRange { largest, extent });
    }
    Ok((extent, largest))
}

/// Indices of the points kept after merging: in order of increasing `x`,
/// each kept point drops every later point within `tolerance` of it, so
/// every dropped point is within `tolerance` of a kept one. Sorting by `x`
/// limits the comparisons to a slab of width `tolerance`.
fn merge_near_duplicates(points: &[Point3<f64>], tolerance: f64) -> Vec<usize> {
    let mut by_x: Vec<usize> = (0..points.len()).collect();
    by_x.sort_by(|&a, &b| points[a].x.total_cmp(&points[b].x).then(a.cmp(&b)));
    let mut duplicate = vec![false; points.len()];
    for (rank, &i) in by_x.iter().enumerate() {
        if duplicate[i] {
            continue;
        }
        for &j in &by_x[rank + 1..] {
            if points[j].x - points[i].x > tolerance {
                break;
            }
            if (points[j] - points[i]).norm() <= tolerance {
                duplicate[j] = true;
            }
        }
    }
    (0..points.len()).filter(|&i| !duplicate[i]).collect()
}

/// Indices of four extreme points `p0, p1, p2, p3` (module doc, step 3),
/// or [`GeometryError::Degenerate`] when the set is all equal, collinear or
/// coplanar within `tolerance` (absolute).
fn extreme_simplex(points: &[Point3<f64>], tolerance: f64) -> Result<[usize; 4], GeometryError> {
    if points.len() < 4 {
        return Err(GeometryError::Degenerate);
    }
    let (i0, _) = farthest(points, |p| -p.x);
    let p0 = points[i0];
    let (i1, d1) = farthest(points, |p| (p - p0).norm());
    if d1 <= tolerance {
        return Err(GeometryError::Degenerate);
    }
    let e1 = (points[i1] - p0) / d1;
    let (i2, d2) = farthest(points, |p| (p - p0).cross(&e1).norm());
    if d2 <= tolerance {
        return Err(GeometryError::Degenerate);
    }
    let normal = e1.cross(&(points[i2] - p0)).normalize();
    let (i3, d3) = farthest(points, |p| (p - p0).dot(&normal).abs());
    if d3 <= tolerance {
        return Err(GeometryError::Degenerate);
    }
    Ok([i0, i1, i2, i3])
}

/// The index of the point maximizing `measure`, and the maximum.
fn farthest(points: &[Point3<f64>], measure: impl Fn(&Point3<f64>) -> f64) -> (usize, f64) {
    points
        .iter()
        .map(measure)
        .enumerate()
        .fold((0, f64::NEG_INFINITY), |best, candidate| {
            if candidate.1 > best.1 {
                candidate
            } else {
                best
            }
        })
}
