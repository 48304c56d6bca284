//! The contact manifold of a penetrating pair, built on the normal of its
//! minimum translation ([`super::penetration`]).
//!
//! **Face contact** (a vertex below a reference face): the incident face is
//! the face of the other body, among those at its support vertex, whose
//! outward normal is most opposed to the reference face's. Its polygon is
//! clipped (Sutherland–Hodgman) against the side planes of the reference
//! face, the planes through the reference face's edges perpendicular to it,
//! as box–box manifolds are built in game engines (Box2D's `b2ClipPolygons`,
//! Bullet's `btPolyhedralContactClipping`). Every clipped point `p` with
//! signed distance `s = n . (p - c)` to the reference plane below the
//! contact margin is a contact: `p` on the incident body, its projection
//! `p - s n` on the reference body, separation `s`. The support vertex lies
//! on the incident face and inside the reference face's prism (the foot of
//! the minimum translation lies in the facet it spans), so the deepest
//! point is always among them.
//!
//! **Reduction** to at most [`MAX_POINTS`]: the deepest point, then the point
//! farthest from it, then the one spanning the largest triangle with those
//! two, then the one spanning the largest area on the other side of the
//! first two (the quadrilateral of largest area that keeps the deepest).
//! Points closer than [`MIN_SPACING_RELATIVE`] of the smaller body to a kept
//! point are dropped first. Distances and areas are measured between the
//! midpoints of the contacts' two points in the plane normal to the
//! contact, which do not depend on which body is A: the same pair gives the
//! same contacts whatever the order of the scene's bodies.
//!
//! **Edge–edge contact**: one point, the closest points of the two edges
//! (interior points: the foot of the minimum translation lies inside the
//! parallelogram the two edges span).
//!
//! **A face standing in for an edge–edge contact** (nearly parallel faces,
//! see [`super::penetration::FACE_PREFERENCE_RELATIVE`]): the face's points,
//! with every separation raised by `delta` so that the deepest asks for the
//! exact depth (`delta = -deepest - exact depth`, between 0 and the
//! difference of the two axes' depths; the point on B moves by
//! `-delta n`, which leaves the Jacobian unchanged), plus the edge–edge
//! point on the exact normal. The raised face rows keep the body level; the
//! edge–edge row is the exact constraint. Without the raise the face rows
//! would ask for the face's depth, more than the exact one; raised by the
//! full difference of the axes' depths instead, they would lift the
//! deepest clipped point clear whenever the face's deepest vertex lies
//! outside the reference face (measured on the demo scene:
//! `benchmarks/results/contact_geometry.md`, "The face preference").

use nalgebra::{Point3, Vector3};

use super::BodyGeometry;
use super::penetration::{ContactAxis, Penetration, PenetrationFeatures};

/// Largest number of contact points of one pair: four span a face contact
/// (three would do for rigid support; the fourth keeps a resting box level
/// under small rotations).
pub const MAX_POINTS: usize = 4;

/// Two contact points of one pair closer than this fraction of the smaller
/// body's scale are one point (the second would be a redundant row).
pub const MIN_SPACING_RELATIVE: f64 = 1e-3;

/// One contact point, world frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactPoint {
    /// Point on body A.
    pub point_a_world: Point3<f64>,
    /// Point on body B.
    pub point_b_world: Point3<f64>,
    /// Unit normal, world frame, from B towards A.
    pub normal_world: Vector3<f64>,
    /// `n . (point_a - point_b)`: negative = penetration.
    pub separation: f64,
}

/// The contact points of a penetrating (or near) pair.
#[derive(Debug, Clone, PartialEq)]
pub struct Manifold {
    /// Unit normal of the reference axis, world frame, from B towards A.
    pub normal_world: Vector3<f64>,
    /// At most [`MAX_POINTS`] points on the reference axis, the deepest
    /// first, then the exact edge–edge point when the reference is a face
    /// standing in for it.
    pub points: Vec<ContactPoint>,
}

/// The manifold of `penetration` (on its reference axis) between `a` and `b`: points with
/// separation below `margin`; `all_points = false` keeps only the deepest.
pub fn manifold(
    penetration: &Penetration,
    a: &BodyGeometry,
    b: &BodyGeometry,
    margin: f64,
    all_points: bool,
) -> Manifold {
    let axis = &penetration.reference;
    let normal = axis.normal_world;
    let stand_in = penetration.reference_offset();
    let mut points = reference_points(axis, a, b, margin + stand_in);
    shift_to_exact_depth(&mut points, &normal, penetration.exact.depth, stand_in);
    points.retain(|p| p.separation < margin);
    points.sort_by(|p, q| p.separation.total_cmp(&q.separation));
    if !all_points {
        points.truncate(1);
    }
    let spacing = MIN_SPACING_RELATIVE * a.shape.scale().min(b.shape.scale());
    let mut points = reduce(points, &normal, spacing);
    if let (PenetrationFeatures::EdgeEdge { edge_a, edge_b }, true) =
        (penetration.exact.features, stand_in > 0.0 && all_points)
    {
        let crossing = edge_contact(a, edge_a, b, edge_b, penetration.exact.normal_world);
        if points.iter().all(|kept| apart(kept, &crossing, spacing)) {
            points.push(crossing);
        }
    }
    Manifold {
        normal_world: normal,
        points,
    }
}

/// The contact points on the reference axis with separation below
/// `margin` (at least one: the support vertex when clipping, through
/// rounding, leaves nothing).
fn reference_points(
    axis: &ContactAxis,
    a: &BodyGeometry,
    b: &BodyGeometry,
    margin: f64,
) -> Vec<ContactPoint> {
    let normal = axis.normal_world;
    let points: Vec<ContactPoint> = match axis.features {
        PenetrationFeatures::FaceOfB { face_b } => {
            face_contact(b, face_b, a, axis.support_a, normal, margin)
        }
        PenetrationFeatures::FaceOfA { face_a } => {
            face_contact(a, face_a, b, axis.support_b, -normal, margin)
                .into_iter()
                .map(swap_roles)
                .collect()
        }
        PenetrationFeatures::EdgeEdge { edge_a, edge_b } => {
            vec![edge_contact(a, edge_a, b, edge_b, normal)]
        }
        // Not an axis of polyhedra: the support contact below.
        PenetrationFeatures::Round => Vec::new(),
    };
    if points.is_empty() {
        vec![support_contact(axis, a)]
    } else {
        points
    }
}

/// Raises every separation by the amount (at most `stand_in`) that brings
/// the deepest point to `-exact_depth`, moving the point on B by `-delta n`
/// (the Jacobian is unchanged: `(delta n) x n = 0`).
fn shift_to_exact_depth(
    points: &mut [ContactPoint],
    normal: &Vector3<f64>,
    exact_depth: f64,
    stand_in: f64,
) {
    if stand_in <= 0.0 {
        return;
    }
    let deepest = points
        .iter()
        .map(|p| p.separation)
        .fold(f64::INFINITY, f64::min);
    let delta = (-deepest - exact_depth).clamp(0.0, stand_in);
    for point in points {
        point.separation += delta;
        point.point_b_world -= normal * delta;
    }
}

/// Points of the incident body below the reference face `face` of
/// `reference` (outward normal `normal`, world): `point_a` on the incident
/// body, `point_b` on the reference face.
fn face_contact(
    reference: &BodyGeometry,
    face: usize,
    incident: &BodyGeometry,
    support: usize,
    normal: Vector3<f64>,
    margin: f64,
) -> Vec<ContactPoint> {
    let reference_face = &reference.shape.faces()[face];
    let on_plane = reference.pose * reference.shape.vertices()[reference_face.vertices[0]];
    let incident_face = incident_face(incident, support, &normal);
    let mut polygon: Vec<Point3<f64>> = incident.shape.faces()[incident_face]
        .vertices
        .iter()
        .map(|&v| incident.pose * incident.shape.vertices()[v])
        .collect();
    // The clipped polygon and the one being clipped swap buffers per edge.
    let mut clipped = Vec::with_capacity(polygon.len() + reference_face.edges.len());
    for &edge in &reference_face.edges {
        let side = reference.shape.face_edge_plane(edge, face);
        let inward = reference.pose.rotation * side.normal;
        let through =
            reference.pose * reference.shape.vertices()[reference.shape.edges()[edge].tail];
        clip_into(&polygon, &inward, &through, &mut clipped);
        std::mem::swap(&mut polygon, &mut clipped);
    }
    polygon
        .into_iter()
        .filter_map(|p| {
            let separation = normal.dot(&(p - on_plane));
            (separation < margin).then(|| ContactPoint {
                point_a_world: p,
                point_b_world: p - normal * separation,
                normal_world: normal,
                separation,
            })
        })
        .collect()
}

/// The face at `support` of `incident` whose normal is most opposed to
/// `normal` (world).
fn incident_face(incident: &BodyGeometry, support: usize, normal: &Vector3<f64>) -> usize {
    let shape = incident.shape;
    let opposition =
        |face: usize| (incident.pose.rotation * shape.faces()[face].plane.normal).dot(normal);
    shape
        .vertex_edges(support)
        .iter()
        .flat_map(|&e| [shape.edges()[e].left_face, shape.edges()[e].right_face])
        .min_by(|&f, &g| opposition(f).total_cmp(&opposition(g)).then(f.cmp(&g)))
        // A vertex of a closed polyhedron has at least three edges.
        .unwrap_or(0)
}

/// Sutherland–Hodgman: the part of `polygon` on the side of the plane
/// through `through` that `inward` points to, into `kept` (its contents
/// replaced).
fn clip_into(
    polygon: &[Point3<f64>],
    inward: &Vector3<f64>,
    through: &Point3<f64>,
    kept: &mut Vec<Point3<f64>>,
) {
    let height = |p: &Point3<f64>| inward.dot(&(p - through));
    kept.clear();
    for (i, p) in polygon.iter().enumerate() {
        let q = &polygon[(i + 1) % polygon.len()];
        let (hp, hq) = (height(p), height(q));
        if hp >= 0.0 {
            kept.push(*p);
        }
        if (hp >= 0.0) != (hq >= 0.0) {
            kept.push(p + (q - p) * (hp / (hp - hq)));
        }
    }
}

/// The contact of a face of A (computed with A as reference) with roles of
/// the points swapped back to (A, B).
fn swap_roles(point: ContactPoint) -> ContactPoint {
    ContactPoint {
        point_a_world: point.point_b_world,
        point_b_world: point.point_a_world,
        normal_world: -point.normal_world,
        separation: point.separation,
    }
}

/// Closest points of the two edges; separation along `normal`.
fn edge_contact(
    a: &BodyGeometry,
    edge_a: usize,
    b: &BodyGeometry,
    edge_b: usize,
    normal: Vector3<f64>,
) -> ContactPoint {
    let ends = |g: &BodyGeometry, e: usize| {
        let edge = &g.shape.edges()[e];
        (
            g.pose * g.shape.vertices()[edge.tail],
            g.pose * g.shape.vertices()[edge.head],
        )
    };
    let (p0, p1) = ends(a, edge_a);
    let (q0, q1) = ends(b, edge_b);
    let (s, t) = segment_parameters(&p0, &(p1 - p0), &q0, &(q1 - q0));
    let point_a_world = p0 + (p1 - p0) * s;
    let point_b_world = q0 + (q1 - q0) * t;
    ContactPoint {
        point_a_world,
        point_b_world,
        normal_world: normal,
        separation: normal.dot(&(point_a_world - point_b_world)),
    }
}

/// Parameters in `[0, 1]` of the closest points of segments `p + s u` and
/// `q + t v` (not parallel: the caller's edges cross).
fn segment_parameters(
    p: &Point3<f64>,
    u: &Vector3<f64>,
    q: &Point3<f64>,
    v: &Vector3<f64>,
) -> (f64, f64) {
    let w = p - q;
    let (uu, uv, vv) = (u.dot(u), u.dot(v), v.dot(v));
    let (uw, vw) = (u.dot(&w), v.dot(&w));
    let det = uu * vv - uv * uv;
    let s = if det > 0.0 {
        ((uv * vw - vv * uw) / det).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let t = ((uv * s + vw) / vv).clamp(0.0, 1.0);
    let s = ((uv * t - uw) / uu).clamp(0.0, 1.0);
    (s, t)
}

/// The single contact at A's support vertex (when clipping leaves nothing,
/// which only rounding can cause).
fn support_contact(axis: &ContactAxis, a: &BodyGeometry) -> ContactPoint {
    let point_a_world = a.pose * a.shape.vertices()[axis.support_a];
    ContactPoint {
        point_a_world,
        point_b_world: point_a_world + axis.normal_world * axis.depth,
        normal_world: axis.normal_world,
        separation: -axis.depth,
    }
}

/// At most [`MAX_POINTS`] of `points` (sorted, deepest first), none closer
/// than `spacing` to another.
fn reduce(points: Vec<ContactPoint>, normal: &Vector3<f64>, spacing: f64) -> Vec<ContactPoint> {
    let mut distinct: Vec<ContactPoint> = Vec::with_capacity(points.len());
    for point in points {
        if distinct.iter().all(|kept| apart(kept, &point, spacing)) {
            distinct.push(point);
        }
    }
    if distinct.len() <= MAX_POINTS {
        return distinct;
    }
    let offset = |i: usize, j: usize| location_offset(&distinct[i], &distinct[j]);
    let area = |i: usize, j: usize, k: usize| offset(j, i).cross(&offset(k, i)).dot(normal);
    let first = 0;
    let second = argmax(distinct.len(), |k| {
        in_plane(&offset(k, first), normal).norm_squared()
    });
    let third = argmax(distinct.len(), |k| area(first, second, k).abs());
    let side = area(first, second, third).signum();
    let fourth = argmax(distinct.len(), |k| -side * area(first, second, k));
    let mut chosen = vec![first, second, third];
    if -side * area(first, second, fourth) > 0.0 {
        chosen.push(fourth);
    } else {
        let beyond_third = argmax(distinct.len(), |k| {
            (side * area(second, third, k)).min(0.0).abs()
                + (side * area(third, first, k)).min(0.0).abs()
        });
        chosen.push(beyond_third);
    }
    chosen.sort_unstable();
    chosen.dedup();
    chosen.into_iter().map(|i| distinct[i]).collect()
}

/// Whether two contact points are at least `spacing` apart, measured
/// between their locations ([`location_offset`]) in the plane normal to
/// their (common) normal.
fn apart(p: &ContactPoint, q: &ContactPoint, spacing: f64) -> bool {
    in_plane(&location_offset(p, q), &p.normal_world).norm() >= spacing
}

/// Where contact `p` is from contact `q`, for the reduction: the offset of
/// the midpoints of their two points (formed from differences, so that it
/// overflows only where the points' differences do). Swapping the roles of
/// A and B leaves it unchanged, and its component in the plane normal to
/// the contact does not depend on which body carries the reference face
/// (the two points of a contact differ along the normal only), so the kept
/// points are those of the pair whatever the order of its bodies.
fn location_offset(p: &ContactPoint, q: &ContactPoint) -> Vector3<f64> {
    (p.point_a_world - q.point_a_world) * 0.5 + (p.point_b_world - q.point_b_world) * 0.5
}

/// The component of `v` in the plane normal to the unit `normal`.
fn in_plane(v: &Vector3<f64>, normal: &Vector3<f64>) -> Vector3<f64> {
    v - normal * normal.dot(v)
}

/// The index in `0..count` with the largest `value` (the first on ties).
fn argmax(count: usize, value: impl Fn(usize) -> f64) -> usize {
    (0..count).fold(0, |best, k| if value(k) > value(best) { k } else { best })
}
