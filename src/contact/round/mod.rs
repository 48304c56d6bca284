//! Pairs with a round part (`geometry::round`: a core grown by a radius;
//! `docs/round-shapes.md`).
//!
//! The solids are `A = C_A + B(r_a)` and `B = C_B + B(r_b)`. Their
//! Minkowski difference is the cores' grown by the ball of `r_a + r_b`, so
//! the signed distance (distance, or minus the penetration depth) of the
//! solids is the cores' minus both radii:
//!
//! ```text
//! sd(A, B) = sd(C_A, C_B) - r_a - r_b
//! ```
//!
//! with the same normal `n` (from B towards A): the cores' closest-point
//! direction when they are apart, their minimum translation when they
//! overlap. A contact point `(p_a, p_b)` of the cores, separation `s`
//! along `n`, becomes `(p_a - r_a n, p_b + r_b n)` on the surfaces with
//! separation `s - r_a - r_b`.
//!
//! The cores' answer comes from:
//! - two polyhedra (rounded cuboids and hulls, or one of them and a plain
//!   polyhedron): V-Clip and the exact depth walk, unchanged, their
//!   manifold built with the margin raised by the radii;
//! - a point or segment against a polyhedron: [`against_polyhedron`]
//!   (separating axes for the depth, face polygons for the distance);
//! - two points or segments: their closest points ([`segments`]), and for
//!   two nearly parallel segments the ends of their common stretch;
//! - a cylinder or cone with anything, when
//!   `VClipSettings::curved_support_functions` is on (the default):
//!   support functions on the true solids ([`support_pair`],
//!   [`support_manifold`], rows by [`point_distance`]).

pub mod against_polyhedron;
pub mod point_distance;
pub mod segments;
pub mod support_manifold;
pub mod support_map;
pub mod support_pair;

use nalgebra::{Isometry3, Point3, Vector3};

use super::BodyGeometry;
use super::manifold::ContactPoint;
use super::penetration::FACE_ALIGNMENT_COS;
use crate::geometry::Rounding;

/// Most contact points of a pair answered in closed form (a point or
/// segment core) or by support functions (a cylinder or cone).
pub const MAX_ROUND_POINTS: usize = 4;

/// Distance between the cores, relative to the pair's size, below which
/// the cores' closest points give no normal (the cores touch or cross).
pub const CORE_NORMAL_MIN_RELATIVE: f64 = 1e-9;

/// A contact point of two cores.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CorePoint {
    /// Point of A's core.
    pub on_a: Point3<f64>,
    /// Point of B's core.
    pub on_b: Point3<f64>,
    /// `n . (on_a - on_b)`.
    pub separation: f64,
    /// The row's unit normal `n` from B towards A: the pair's, or for a
    /// point of a support-function manifold its own
    /// (`support_manifold`).
    pub normal: Vector3<f64>,
}

/// The cores' answer in closed form (a point or segment core), or by
/// support functions (a cylinder or cone).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoreContact {
    /// The cores' signed distance (distance, or minus the depth).
    pub signed_distance: f64,
    /// Unit normal from B's core towards A's.
    pub normal_world: Vector3<f64>,
    /// The contact points (the first `count`); with `deferred`, only the
    /// central point (`support_manifold`) until [`CoreContact::points_of`]
    /// forms them.
    pub points: [CorePoint; MAX_ROUND_POINTS],
    /// How many points.
    pub count: usize,
    /// What a support-function answer needs to form its contact points,
    /// which only a pair that gets rows reads: a query's answer is also
    /// measured by its signed distance alone (every line-search trial,
    /// and the detection of pairs no solved island holds), so the points
    /// are formed on demand (`support_pair`).
    pub deferred: Option<support_pair::DeferredPoints>,
}

impl CoreContact {
    /// The contact points and their count: formed now from `a` and `b`
    /// (the pair's parts; their poses at the query are kept) with the
    /// cores' contact margin `margin` (the call's plus both radii) when
    /// they were deferred, else the answer's own.
    pub fn points_of(
        &self,
        a: &BodyGeometry,
        b: &BodyGeometry,
        margin: f64,
    ) -> ([CorePoint; MAX_ROUND_POINTS], usize) {
        match &self.deferred {
            Some(deferred) => deferred.points(a, b, &self.normal_world, margin),
            None => (self.points, self.count),
        }
    }

    fn moved(self, pose: &Isometry3<f64>) -> Self {
        let mut points = self.points;
        for p in &mut points {
            p.on_a = pose * p.on_a;
            p.on_b = pose * p.on_b;
            p.normal = pose.rotation * p.normal;
        }
        CoreContact {
            normal_world: pose.rotation * self.normal_world,
            points,
            ..self
        }
    }

    /// The same contact with A and B exchanged.
    fn swapped(self) -> Self {
        let mut points = self.points;
        for p in &mut points {
            std::mem::swap(&mut p.on_a, &mut p.on_b);
            p.normal = -p.normal;
        }
        CoreContact {
            normal_world: -self.normal_world,
            points,
            ..self
        }
    }
}

/// What rounding adds to a pair's answer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoundAnswer {
    /// The radii of A and B (0 for a plain polyhedron).
    pub radii: [f64; 2],
    /// The cores' answer when one is a point or a segment; `None` when
    /// both are polyhedra (V-Clip answered them).
    pub closed_form: Option<CoreContact>,
}

impl RoundAnswer {
    /// `r_a + r_b`.
    pub fn radius_sum(&self) -> f64 {
        self.radii[0] + self.radii[1]
    }

    /// A core contact point put on the surfaces along its normal (module
    /// docs).
    pub fn on_surfaces(&self, point: &CorePoint) -> ContactPoint {
        let normal = &point.normal;
        ContactPoint {
            point_a_world: point.on_a - normal * self.radii[0],
            point_b_world: point.on_b + normal * self.radii[1],
            normal_world: *normal,
            separation: point.separation - self.radius_sum(),
        }
    }
}

/// A point or segment core, world frame.
fn segment_world(geometry: &BodyGeometry) -> Option<[Point3<f64>; 2]> {
    let ends = geometry.rounding.as_ref()?.segment()?;
    Some(ends.map(|p| geometry.pose * p))
}

/// The cores' answer in closed form, when a core is a point or a segment
/// (`None` when both are polyhedra).
pub fn closed_form(a: &BodyGeometry, b: &BodyGeometry) -> Option<CoreContact> {
    match (segment_world(a), segment_world(b)) {
        (None, None) => None,
        (Some(sa), Some(sb)) => Some(segment_segment(&sa, &sb, a, b)),
        (Some(sa), None) => {
            let in_b = sa.map(|p| b.pose.inverse_transform_point(&p));
            Some(against_polyhedron::segment_polyhedron(&in_b, b.shape).moved(&b.pose))
        }
        (None, Some(sb)) => {
            let in_a = sb.map(|p| a.pose.inverse_transform_point(&p));
            let contact = against_polyhedron::segment_polyhedron(&in_a, a.shape);
            Some(contact.moved(&a.pose).swapped())
        }
    }
}

/// The radii of a pair, if either part is round.
pub fn radii(a: &BodyGeometry, b: &BodyGeometry) -> Option<[f64; 2]> {
    let radius = |g: &BodyGeometry| g.rounding.map_or(0.0, |r: Rounding| r.radius);
    (a.rounding.is_some() || b.rounding.is_some()).then(|| [radius(a), radius(b)])
}

/// Two points or segments (module docs).
fn segment_segment(
    sa: &[Point3<f64>; 2],
    sb: &[Point3<f64>; 2],
    a: &BodyGeometry,
    b: &BodyGeometry,
) -> CoreContact {
    let (p, q) = segments::closest_points(&sa[0], &sa[1], &sb[0], &sb[1]);
    let distance = (p - q).norm();
    let (da, db) = (sa[1] - sa[0], sb[1] - sb[0]);
    let size = da.norm() + db.norm() + (a.com_world - b.com_world).norm();
    let normal = if distance > CORE_NORMAL_MIN_RELATIVE * size {
        (p - q) / distance
    } else {
        crossing_normal(
            &da,
            &db,
            &(a.pose.translation.vector - b.pose.translation.vector),
        )
    };
    let point = |on_a: Point3<f64>, on_b: Point3<f64>| CorePoint {
        on_a,
        on_b,
        separation: normal.dot(&(on_a - on_b)),
        normal,
    };
    let mut contact = CoreContact {
        signed_distance: distance,
        normal_world: normal,
        points: [point(p, q); MAX_ROUND_POINTS],
        count: 1,
        deferred: None,
    };
    let parallel = da.norm() * db.norm() > 0.0
        && da.dot(&db).abs() >= FACE_ALIGNMENT_COS * da.norm() * db.norm();
    if !parallel || distance <= CORE_NORMAL_MIN_RELATIVE * size {
        return contact;
    }
    // The ends of the common stretch: each end's closest point on the
    // other segment, where that pair lies along the normal.
    let mut ends: Vec<CorePoint> = Vec::with_capacity(4);
    for x in sa {
        ends.push(point(*x, segments::closest_to_point(x, &sb[0], &sb[1])));
    }
    for y in sb {
        ends.push(point(segments::closest_to_point(y, &sa[0], &sa[1]), *y));
    }
    ends.retain(|c| c.separation >= FACE_ALIGNMENT_COS * (c.on_a - c.on_b).norm());
    let along = |c: &CorePoint| da.dot(&c.on_a.coords);
    let first = ends.iter().min_by(|x, y| along(x).total_cmp(&along(y)));
    let last = ends.iter().max_by(|x, y| along(x).total_cmp(&along(y)));
    if let (Some(first), Some(last)) = (first, last)
        && (first.on_a - last.on_a).norm() > CORE_NORMAL_MIN_RELATIVE * size
    {
        contact.points = [*first, *last, *last, *last];
        contact.count = 2;
    }
    contact
}

/// A normal for cores that touch or cross: across both directions, else
/// across the first, else along the centres, else `z`; turned towards the
/// centres' difference `centres` (A minus B).
fn crossing_normal(da: &Vector3<f64>, db: &Vector3<f64>, centres: &Vector3<f64>) -> Vector3<f64> {
    let across_first = || {
        let helper = if da.x.abs() < da.y.abs().max(da.z.abs()) {
            Vector3::x()
        } else {
            Vector3::y()
        };
        da.cross(&helper).try_normalize(0.0)
    };
    let normal = da
        .cross(db)
        .try_normalize(CORE_NORMAL_MIN_RELATIVE)
        .or_else(|| {
            if da.norm() > 0.0 {
                // Perpendicular to the segment, towards the centres when
                // that is defined.
                let off_axis = centres - da * (da.dot(centres) / da.norm_squared());
                off_axis.try_normalize(0.0).or_else(across_first)
            } else {
                centres.try_normalize(0.0)
            }
        })
        .unwrap_or_else(Vector3::z);
    if normal.dot(centres) < 0.0 {
        -normal
    } else {
        normal
    }
}
