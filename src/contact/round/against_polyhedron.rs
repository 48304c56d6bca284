//! A segment (or point) core `S` against a polyhedron `P`, in `P`'s frame:
//! the signed distance, the normal from `P` towards `S`, and the contact
//! points.
//!
//! **Penetration** (the segment meets the solid): `S` and `P` overlap
//! along every axis of the separating-axis test of a polytope and a
//! segment, whose Minkowski difference `P - S` has only two kinds of
//! facets: `P`'s faces (normal `n_f`) and the parallelograms of an edge `e`
//! of `P` and the segment `d` (normal `±e x d`). The overlap along unit `n`
//! (translate `S` by it along `n` to separate) is
//! `h_P(n) - min_{x in S} n.x`; the depth is its minimum over those axes,
//! exact since every facet normal is evaluated (extra axes only give
//! larger overlaps). A point core has the face axes only.
//!
//! **Separation** (some axis has overlap `<= 0`): the closest points lie
//! on `P`'s boundary, so the distance is the least over faces of the
//! distance between the segment and the face polygon. For a segment and a
//! convex polygon that do not meet, the closest pair has an end of the
//! segment (against the polygon: its projection if inside, else the
//! nearest boundary point) or a boundary edge of the polygon (against the
//! segment).
//!
//! **Points.** On a face (the axis of a penetration, or the face the
//! closest point of an apart pair lies on, [`FACE_NORMAL_EXACT`]): the segment clipped to the face's prism (the side planes
//! through its edges), both ends, each with its height above the face (a
//! capsule lying on a face gives its two ends; across a box's edge, the
//! end inside and the point above the edge). Otherwise one point: the
//! closest points, or for an edge axis the closest points of the edge and
//! the segment.

use nalgebra::{Point3, Vector3};

use super::segments::closest_points;
use super::{CoreContact, CorePoint, MAX_ROUND_POINTS};
use crate::contact::penetration::EDGE_PARALLEL_SINE;
use crate::geometry::{ConvexPolyhedron, Edge};

/// Relative distance (to the pair's size) below which the closest points
/// of a separated pair are too close to give a normal: the widest
/// separating axis gives it instead.
pub const NORMAL_FROM_POINTS_MIN_RELATIVE: f64 = 1e-9;

/// `1 - cos` of the largest angle between an apart pair's normal and a
/// face normal for which the face carries the manifold (the closest point
/// lies on the face, up to rounding).
pub const FACE_NORMAL_EXACT: f64 = 1e-9;

/// A face's clipped points stand for the deepest point when one of them
/// is within this fraction of the depth; else the deepest end (outside the
/// face's prism) is added.
pub const CLIPPED_DEPTH_RELATIVE: f64 = 1e-6;

/// The best axis of the separating-axis test.
struct Axis {
    normal: Vector3<f64>,
    overlap: f64,
    /// The face, for a face axis.
    face: Option<usize>,
    /// The edge, for an edge–segment axis.
    edge: Option<usize>,
}

fn support(poly: &ConvexPolyhedron, n: &Vector3<f64>) -> f64 {
    poly.vertices()
        .iter()
        .map(|v| n.dot(&v.coords))
        .fold(f64::NEG_INFINITY, f64::max)
}

/// The axis of least overlap (module docs).
fn least_overlap(s: &[Point3<f64>; 2], poly: &ConvexPolyhedron) -> Axis {
    let low = |n: &Vector3<f64>| n.dot(&s[0].coords).min(n.dot(&s[1].coords));
    let mut best = Axis {
        normal: Vector3::z(),
        overlap: f64::INFINITY,
        face: None,
        edge: None,
    };
    for (f, face) in poly.faces().iter().enumerate() {
        let overlap = -face.plane.offset - low(&face.plane.normal);
        if overlap < best.overlap {
            best = Axis {
                normal: face.plane.normal,
                overlap,
                face: Some(f),
                edge: None,
            };
        }
    }
    let d = s[1] - s[0];
    let length = d.norm();
    if length == 0.0 {
        return best;
    }
    for (e, edge) in poly.edges().iter().enumerate() {
        let cross = edge.direction.cross(&d);
        let sine = cross.norm() / length;
        if sine < EDGE_PARALLEL_SINE {
            continue;
        }
        let n = cross / (sine * length);
        for n in [n, -n] {
            let overlap = support(poly, &n) - low(&n);
            if overlap < best.overlap {
                best = Axis {
                    normal: n,
                    overlap,
                    face: None,
                    edge: Some(e),
                };
            }
        }
    }
    best
}

/// The edge parallel to edge `e` on which `poly` reaches its support along
/// `n` (perpendicular to `e`): the edge–segment axis is the same for every
/// edge parallel to `e` (a prism's side edges), so the axis search keeps
/// whichever came first, while the contact lies on the supporting one.
fn supporting_parallel_edge<'p>(
    poly: &'p ConvexPolyhedron,
    e: usize,
    n: &Vector3<f64>,
) -> &'p Edge {
    let direction = poly.edges()[e].direction;
    let height = |edge: &Edge| n.dot(&poly.vertices()[edge.tail].coords);
    poly.edges()
        .iter()
        .filter(|edge| edge.direction.cross(&direction).norm() < EDGE_PARALLEL_SINE)
        .max_by(|x, y| height(x).total_cmp(&height(y)))
        // Edge `e` itself passes the filter: the fallback is never taken.
        .unwrap_or(&poly.edges()[e])
}

/// Whether `y` (on the face's plane) lies in the face polygon.
fn inside_face(poly: &ConvexPolyhedron, f: usize, y: &Point3<f64>) -> bool {
    let face = &poly.faces()[f];
    let v = poly.vertices();
    let k = face.vertices.len();
    (0..k).all(|i| {
        let (p, q) = (v[face.vertices[i]], v[face.vertices[(i + 1) % k]]);
        (q - p).cross(&(y - p)).dot(&face.plane.normal) >= 0.0
    })
}

/// The closest pair `(on S, on the face)` of the segment and face `f`.
fn closest_to_face(
    s: &[Point3<f64>; 2],
    poly: &ConvexPolyhedron,
    f: usize,
) -> (Point3<f64>, Point3<f64>) {
    let face = &poly.faces()[f];
    let v = poly.vertices();
    let k = face.vertices.len();
    let mut best = (s[0], v[face.vertices[0]]);
    let mut best_distance = f64::INFINITY;
    let mut consider = |pair: (Point3<f64>, Point3<f64>)| {
        let distance = (pair.0 - pair.1).norm();
        if distance < best_distance {
            best_distance = distance;
            best = pair;
        }
    };
    for x in s {
        let y = x - face.plane.normal * face.plane.signed_distance(x);
        if inside_face(poly, f, &y) {
            consider((*x, y));
        }
    }
    for i in 0..k {
        let (p, q) = (v[face.vertices[i]], v[face.vertices[(i + 1) % k]]);
        consider(closest_points(&s[0], &s[1], &p, &q));
    }
    best
}

/// The segment clipped to the prism of face `f`, `None` if nothing is
/// left.
fn clip_to_face(
    s: &[Point3<f64>; 2],
    poly: &ConvexPolyhedron,
    f: usize,
) -> Option<[Point3<f64>; 2]> {
    let face = &poly.faces()[f];
    let v = poly.vertices();
    let k = face.vertices.len();
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    let d = s[1] - s[0];
    for i in 0..k {
        let (p, q) = (v[face.vertices[i]], v[face.vertices[(i + 1) % k]]);
        let inward = face.plane.normal.cross(&(q - p));
        let (h0, slope) = (inward.dot(&(s[0] - p)), inward.dot(&d));
        if slope == 0.0 {
            if h0 < 0.0 {
                return None;
            }
            continue;
        }
        let t = -h0 / slope;
        if slope > 0.0 {
            t0 = t0.max(t);
        } else {
            t1 = t1.min(t);
        }
    }
    (t0 <= t1).then(|| [s[0] + d * t0, s[0] + d * t1])
}

/// The points on face `f` (module docs), normal `n_f`.
fn face_points(s: &[Point3<f64>; 2], poly: &ConvexPolyhedron, f: usize) -> Option<CoreContact> {
    let [c0, c1] = clip_to_face(s, poly, f)?;
    let plane = poly.faces()[f].plane;
    let point = |c: Point3<f64>| {
        let separation = plane.signed_distance(&c);
        CorePoint {
            on_a: c,
            on_b: c - plane.normal * separation,
            separation,
            normal: plane.normal,
        }
    };
    let (p0, p1) = (point(c0), point(c1));
    let deepest = p0.separation.min(p1.separation);
    Some(CoreContact {
        signed_distance: deepest,
        normal_world: plane.normal,
        points: [p0, p1, p1, p1],
        count: if c0 == c1 { 1 } else { 2 },
        deferred: None,
    })
}

fn deepest_end(s: &[Point3<f64>; 2], n: &Vector3<f64>) -> Point3<f64> {
    if n.dot(&s[0].coords) <= n.dot(&s[1].coords) {
        s[0]
    } else {
        s[1]
    }
}

fn single(on_a: Point3<f64>, on_b: Point3<f64>, normal: Vector3<f64>, signed: f64) -> CoreContact {
    let point = CorePoint {
        on_a,
        on_b,
        separation: normal.dot(&(on_a - on_b)),
        normal,
    };
    CoreContact {
        signed_distance: signed,
        normal_world: normal,
        points: [point; MAX_ROUND_POINTS],
        count: 1,
        deferred: None,
    }
}

/// The segment `s` (a point when its ends coincide) against `poly`, all in
/// `poly`'s frame (module docs); the normal points from `poly` towards the
/// segment, `signed_distance` is the cores' (distance, or minus the depth).
pub fn segment_polyhedron(s: &[Point3<f64>; 2], poly: &ConvexPolyhedron) -> CoreContact {
    let axis = least_overlap(s, poly);
    if axis.overlap > 0.0 {
        let depth = axis.overlap;
        if let Some(contact) = axis.face.and_then(|f| face_points(s, poly, f)) {
            let mut contact = CoreContact {
                signed_distance: -depth,
                ..contact
            };
            // The deepest end hangs outside the face's prism: its row asks
            // for the whole depth along the face's normal.
            if contact.points[..contact.count]
                .iter()
                .all(|p| p.separation > -depth * (1.0 - CLIPPED_DEPTH_RELATIVE))
            {
                let x = deepest_end(s, &axis.normal);
                contact.points[contact.count] = CorePoint {
                    on_a: x,
                    on_b: x + axis.normal * depth,
                    separation: -depth,
                    normal: axis.normal,
                };
                contact.count += 1;
            }
            return contact;
        }
        let n = axis.normal;
        let deepest = deepest_end(s, &n);
        let whole_depth = (deepest, deepest + n * depth);
        let (on_a, on_b) = match axis.edge {
            Some(e) => {
                let edge = supporting_parallel_edge(poly, e, &n);
                let (p, q) = (poly.vertices()[edge.tail], poly.vertices()[edge.head]);
                let pair = closest_points(&s[0], &s[1], &p, &q);
                // The pair realizes the depth when the origin's projection
                // lies in the edge–segment facet; else (rounding at a
                // facet's border) the deepest end carries the whole depth.
                let realized = n.dot(&(pair.0 - pair.1)) <= -depth * (1.0 - CLIPPED_DEPTH_RELATIVE);
                if realized { pair } else { whole_depth }
            }
            None => whole_depth,
        };
        return single(on_a, on_b, n, -depth);
    }
    let (on_a, on_b) = (0..poly.faces().len())
        .map(|f| closest_to_face(s, poly, f))
        .min_by(|x, y| (x.0 - x.1).norm().total_cmp(&(y.0 - y.1).norm()))
        // A polyhedron has faces: the fallback is never taken.
        .unwrap_or((s[0], s[0]));
    let distance = (on_a - on_b).norm();
    let size = poly.scale() + (s[1] - s[0]).norm();
    let normal = if distance > NORMAL_FROM_POINTS_MIN_RELATIVE * size {
        (on_a - on_b) / distance
    } else {
        axis.normal
    };
    let aligned = poly
        .faces()
        .iter()
        .enumerate()
        .map(|(f, face)| (f, face.plane.normal.dot(&normal)))
        .max_by(|x, y| x.1.total_cmp(&y.1));
    // The face carries the manifold only when the closest point of the
    // polyhedron lies on it (the normal is the face's): its clipped ends'
    // heights then bound the distance from below at every point.
    let aligned = aligned.filter(|(_, cos)| *cos >= 1.0 - FACE_NORMAL_EXACT);
    if let Some(contact) = aligned.and_then(|(f, _)| face_points(s, poly, f)) {
        return CoreContact {
            signed_distance: distance,
            ..contact
        };
    }
    single(on_a, on_b, normal, distance)
}
