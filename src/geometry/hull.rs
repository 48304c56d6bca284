//! Convex hull of a point set: [`ConvexPolyhedron::from_points`].
//!
//! Pipeline, every tolerance relative to the extent `L` of the input (the
//! diagonal of its axis-aligned bounding box):
//! 1. Reject an empty set and non-finite coordinates (the index is named).
//! 2. Merge points closer than [`DUPLICATE_TOLERANCE`]` * L` to an earlier
//!    kept point (greedy, in input order), so that near duplicates are never
//!    handed to the hull algorithm as distinct vertices.
//! 3. Reject sets without volume before any hull is computed: with `p0` an
//!    extreme point, `p1` the point farthest from `p0`, `p2` the point
//!    farthest from the line `p0 p1` and `p3` the point farthest from the
//!    plane `p0 p1 p2`, the set is all equal, collinear or coplanar when
//!    `d1 = |p1 - p0|`, `d2 = dist(p2, line)` or `d3 = dist(p3, plane)` is
//!    at most [`FLATNESS_TOLERANCE`]` * L`.
//! 4. Triangulated hull by parry3d-f64 (`transformation::try_convex_hull`,
//!    an incremental quickhull), computed on the affine image of the set in
//!    the frame of step 3 scaled by `1/d1, 1/d2, 1/d3` (see
//!    `parry_hull_triangles` for why). Its output vertices are bitwise
//!    copies of its input, which maps them back to input indices.
//! 5. Triangles are merged into polygonal faces and vertices that are not
//!    corners of the hull are dropped (see [`super::coplanar`]).
//! 6. [`ConvexPolyhedron::from_faces`] checks topology, planarity and
//!    convexity; finally every kept input point must lie on or below every
//!    face plane within [`CONTAINMENT_TOLERANCE`]` * L`.

use std::collections::HashMap;
use std::panic::{AssertUnwindSafe, catch_unwind};

use nalgebra::{Point3, Vector3};
use parry3d_f64::math::Vector as ParryVector;
use parry3d_f64::transformation::try_convex_hull;

use super::coplanar::{HullFaces, polygon_faces};
use super::{ConvexPolyhedron, GeometryError};

/// Two input points closer than `DUPLICATE_TOLERANCE * L` are one point.
pub const DUPLICATE_TOLERANCE: f64 = 1e-10;

/// A point set whose width (as estimated in step 3 of the module doc) is at
/// most `FLATNESS_TOLERANCE * L` has no volume at the precision of `f64`
/// face normals and is rejected as degenerate.
pub const FLATNESS_TOLERANCE: f64 = 1e-8;

/// After the hull is built, every (merged) input point must lie at most
/// `CONTAINMENT_TOLERANCE * L` above every face plane.
pub const CONTAINMENT_TOLERANCE: f64 = 1e-9;

impl ConvexPolyhedron {
    /// The convex hull of `points` (given in the shape frame), with
    /// coplanar triangles merged into polygonal faces. The vertices of the
    /// result are a subset of the input points (stored relative to the
    /// centre of mass, see [`ConvexPolyhedron::shape_origin_offset`]).
    ///
    /// Errors: [`GeometryError::Empty`], [`GeometryError::NonFinite`],
    /// [`GeometryError::Degenerate`] (all equal, collinear or coplanar after
    /// merging near duplicates), [`GeometryError::HullFailed`] when the
    /// hull algorithm fails numerically.
    pub fn from_points(points: &[Point3<f64>]) -> Result<Self, GeometryError> {
        let extent = checked_extent(points)?;
        let kept = merge_near_duplicates(points, DUPLICATE_TOLERANCE * extent);
        let kept_points: Vec<Point3<f64>> = kept.iter().map(|&i| points[i]).collect();
        let frame = extreme_frame(&kept_points, FLATNESS_TOLERANCE * extent)?;
        let triangles = parry_hull_triangles(&kept_points, &frame)?;
        let HullFaces { vertices, faces } = polygon_faces(&kept_points, &triangles, extent)?;
        log::debug!(
            "hull of {} points ({} after merging): {} triangles -> {} vertices, {} faces",
            points.len(),
            kept_points.len(),
            triangles.len(),
            vertices.len(),
            faces.len()
        );
        let hull_points = vertices.iter().map(|&i| kept_points[i]).collect();
        let polyhedron = Self::from_faces(hull_points, faces)?;
        polyhedron.check_contains(&kept_points, CONTAINMENT_TOLERANCE * extent)?;
        Ok(polyhedron)
    }

    /// Checks that every point (shape frame) is on or below every face plane
    /// within `tolerance`.
    fn check_contains(
        &self,
        points_shape: &[Point3<f64>],
        tolerance: f64,
    ) -> Result<(), GeometryError> {
        let offset = self.shape_origin_offset();
        for (index, p_shape) in points_shape.iter().enumerate() {
            let p_body = p_shape - offset;
            let height = self
                .faces()
                .iter()
                .map(|face| face.plane.signed_distance(&p_body))
                .fold(f64::NEG_INFINITY, f64::max);
            if height > tolerance {
                return Err(GeometryError::HullFailed(format!(
                    "point {index} is {height:e} outside the hull"
                )));
            }
        }
        Ok(())
    }
}

/// Validates the coordinates and returns the extent `L` (bounding-box
/// diagonal) of the point set.
fn checked_extent(points: &[Point3<f64>]) -> Result<f64, GeometryError> {
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
    let extent = (upper - lower).norm();
    if !extent.is_finite() {
        return Err(GeometryError::ExtentTooLarge);
    }
    if extent == 0.0 {
        return Err(GeometryError::Degenerate);
    }
    Ok(extent)
}

/// Indices of the points kept after merging: a point is dropped when an
/// earlier kept point is within `tolerance`. Sorting by `x` limits the
/// comparisons to a slab of width `tolerance`.
fn merge_near_duplicates(points: &[Point3<f64>], tolerance: f64) -> Vec<usize> {
    let mut by_x: Vec<usize> = (0..points.len()).collect();
    by_x.sort_by(|&a, &b| points[a].x.total_cmp(&points[b].x).then(a.cmp(&b)));
    let mut duplicate = vec![false; points.len()];
    for (rank, &i) in by_x.iter().enumerate() {
        if duplicate[i] {
            continue;
        }
        for &j in by_x[rank + 1..].iter() {
            if points[j].x - points[i].x > tolerance {
                break;
            }
            if !duplicate[j] && (points[j] - points[i]).norm() <= tolerance {
                // Keep the point that comes first in the input.
                duplicate[i.max(j)] = true;
                if i > j {
                    break;
                }
            }
        }
    }
    (0..points.len()).filter(|&i| !duplicate[i]).collect()
}

/// An affine frame spanned by four extreme points of the set: origin
/// `p0`, orthonormal right-handed axes `e1, e2, e3` and the extent of the
/// set along each, `d1 = |p1 - p0|`, `d2 = dist(p2, line)`,
/// `d3 = dist(p3, plane)`.
struct ExtremeFrame {
    origin: Point3<f64>,
    axes: [Vector3<f64>; 3],
    extents: [f64; 3],
}

impl ExtremeFrame {
    /// Coordinates `((x - p0) . e_i) / d_i`. Every point of the set lies in
    /// `[-1, 1]^3` in this frame (each `d_i` is a maximum over the set), and
    /// `p1, p2, p3` have coordinate 1 on their axis: the set is "round",
    /// however thin it was.
    fn normalized(&self, x: &Point3<f64>) -> Vector3<f64> {
        let r = x - self.origin;
        Vector3::from_fn(|i, _| r.dot(&self.axes[i]) / self.extents[i])
    }
}

/// The extreme frame of the module doc, or [`GeometryError::Degenerate`]
/// when the set is all equal, collinear or coplanar within `tolerance`
/// (absolute).
fn extreme_frame(points: &[Point3<f64>], tolerance: f64) -> Result<ExtremeFrame, GeometryError> {
    if points.len() < 4 {
        return Err(GeometryError::Degenerate);
    }
    let p0 = points
        .iter()
        .min_by(|a, b| a.x.total_cmp(&b.x))
        .copied()
        .unwrap_or(points[0]);
    let (p1, d1) = farthest(points, |p| (p - p0).norm());
    if d1 <= tolerance {
        return Err(GeometryError::Degenerate);
    }
    let e1 = (p1 - p0) / d1;
    let (p2, d2) = farthest(points, |p| (p - p0).cross(&e1).norm());
    if d2 <= tolerance {
        return Err(GeometryError::Degenerate);
    }
    let in_plane = (p2 - p0) - e1 * (p2 - p0).dot(&e1);
    let e2 = in_plane / in_plane.norm();
    let e3 = e1.cross(&e2);
    let (_, d3) = farthest(points, |p| (p - p0).dot(&e3).abs());
    if d3 <= tolerance {
        return Err(GeometryError::Degenerate);
    }
    Ok(ExtremeFrame {
        origin: p0,
        axes: [e1, e2, e3],
        extents: [d1, d2, d3],
    })
}

/// The point maximizing `measure`, and the maximum.
fn farthest(points: &[Point3<f64>], measure: impl Fn(&Point3<f64>) -> f64) -> (Point3<f64>, f64) {
    points.iter().map(|p| (*p, measure(p))).fold(
        (points[0], f64::NEG_INFINITY),
        |best, candidate| {
            if candidate.1 > best.1 {
                candidate
            } else {
                best
            }
        },
    )
}

/// Triangles of the hull by parry3d-f64, as indices into `points`,
/// counter-clockwise seen from outside.
///
/// parry treats a set as flat when an eigenvalue of its covariance (in
/// coordinates scaled by the bounding-box diagonal) is below `1e-7`, which
/// flattens solids thinner than about `3e-4 L`. The hull is therefore
/// computed in the coordinates of the [`ExtremeFrame`], an affine image of
/// the set that is round; a convex hull's combinatorics are invariant under
/// invertible affine maps, and the orientation is fixed afterwards in the
/// original coordinates.
fn parry_hull_triangles(
    points: &[Point3<f64>],
    frame: &ExtremeFrame,
) -> Result<Vec<[usize; 3]>, GeometryError> {
    let normalized: Vec<ParryVector> = points
        .iter()
        .map(|p| {
            let x = frame.normalized(p);
            ParryVector::new(x.x, x.y, x.z)
        })
        .collect();
    // parry's hull asserts internal invariants that rounding can break on
    // nearly degenerate input; a panic there becomes a typed error here
    // rather than unwinding through the caller. (With `panic = "abort"` this
    // guard does nothing, which is why degenerate sets are rejected first.)
    let result = catch_unwind(AssertUnwindSafe(|| try_convex_hull(&normalized)));
    let (hull_points, indices) = match result {
        Ok(Ok(hull)) => hull,
        Ok(Err(error)) => return Err(GeometryError::HullFailed(error.to_string())),
        Err(_) => return Err(GeometryError::HullFailed("parry's hull panicked".into())),
    };
    let index_of: HashMap<[u64; 3], usize> = normalized
        .iter()
        .enumerate()
        .map(|(i, p)| (bits(p), i))
        .collect();
    let to_input = |k: u32| -> Result<usize, GeometryError> {
        let p = hull_points
            .get(k as usize)
            .ok_or_else(|| GeometryError::HullFailed(format!("index {k} out of range")))?;
        index_of
            .get(&bits(p))
            .copied()
            .ok_or_else(|| GeometryError::HullFailed("a hull vertex is not an input point".into()))
    };
    let triangles = indices
        .iter()
        .map(|t| Ok([to_input(t[0])?, to_input(t[1])?, to_input(t[2])?]))
        .collect::<Result<Vec<_>, GeometryError>>()?;
    orient_outward(points, triangles)
}

fn bits(p: &ParryVector) -> [u64; 3] {
    [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]
}

/// Flips every triangle if the signed volume they enclose is negative; a
/// hull without volume (parry returns a flat, two-sided mesh for a set it
/// judges coplanar) is an error.
fn orient_outward(
    points: &[Point3<f64>],
    mut triangles: Vec<[usize; 3]>,
) -> Result<Vec<[usize; 3]>, GeometryError> {
    let origin = points[0];
    let signed_volume: f64 = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| points[i] - origin);
            a.dot(&b.cross(&c))
        })
        .sum();
    if signed_volume == 0.0 || !signed_volume.is_finite() {
        return Err(GeometryError::HullFailed(
            "the triangle hull has no volume".into(),
        ));
    }
    if signed_volume < 0.0 {
        for t in &mut triangles {
            t.swap(1, 2);
        }
    }
    Ok(triangles)
}

/// Unit normal of a triangle (zero when the triangle is degenerate).
pub(super) fn triangle_normal(points: &[Point3<f64>], t: &[usize; 3]) -> Vector3<f64> {
    let n = (points[t[1]] - points[t[0]]).cross(&(points[t[2]] - points[t[0]]));
    n.try_normalize(0.0).unwrap_or_else(Vector3::zeros)
}
