//! Directions on the unit sphere: the pieces of the Gauss map that the exact
//! penetration search walks on.
//!
//! The Gauss map of a convex polyhedron sends each face to its outward unit
//! normal (a point of the sphere), each edge to the minor great-circle arc
//! between the normals of its two faces, and each vertex to the spherical
//! polygon bounded by the arcs of its edges (the directions in which that
//! vertex is the support point). Two facts are used:
//!
//! - a minor arc and a great circle: the minimum of the linear function
//!   `x . t` over the arc is at an end, or at the point of the arc's circle
//!   nearest to `-t` if that point lies on the arc;
//! - two arcs cross where their circles do: at `±(p1 x p2)/|p1 x p2|`, with
//!   `p1`, `p2` the poles of the circles, if one of those two points lies on
//!   both arcs.
//!
//! All vectors are in one frame (the search uses body A's frame).

use nalgebra::Vector3;

/// The minor arc of a great circle from `from` to `to` (unit vectors, not
/// antipodal: the normals of two adjacent faces of a convex polyhedron).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GreatArc {
    /// First end (unit).
    pub from: Vector3<f64>,
    /// Second end (unit).
    pub to: Vector3<f64>,
}

impl GreatArc {
    /// `from x to`: normal to the arc's plane, oriented so that the arc runs
    /// counter-clockwise about it.
    fn pole(&self) -> Vector3<f64> {
        self.from.cross(&self.to)
    }

    /// Whether `x`, a unit vector on the arc's great circle, lies on the arc
    /// (ends included): it must be counter-clockwise of `from` and clockwise
    /// of `to` about the pole.
    pub fn contains(&self, x: &Vector3<f64>) -> bool {
        let pole = self.pole();
        pole.dot(&self.from.cross(x)) >= 0.0 && pole.dot(&x.cross(&self.to)) >= 0.0
    }

    /// Whether `below(x . t)` holds at some point `x` of the arc, for a
    /// threshold test `below` (`v <= b` or `v < b`): the ends first, since
    /// most arcs a walk tests have an end past the threshold, then the
    /// arc's minimum ([`GreatArc::min_dot`]).
    pub fn dips(&self, t: &Vector3<f64>, below: impl Fn(f64) -> bool) -> bool {
        below(self.from.dot(t)) || below(self.to.dot(t)) || below(self.min_dot(t))
    }

    /// The smallest value of `x . t` over the points `x` of the arc.
    ///
    /// With the pole `p = from x to` (not normalized), the part of `t` in
    /// the arc's plane is `t_p = t - p (p . t) / (p . p)`, and `x . t =
    /// x . t_p` is least on the circle at `-t_p / |t_p|`, where it is
    /// `-|t_p|`. Whether that point is on the arc does not depend on its
    /// length, so `-t_p` is tested as it is: one square root in all.
    pub fn min_dot(&self, t: &Vector3<f64>) -> f64 {
        let at_ends = self.from.dot(t).min(self.to.dot(t));
        let pole = self.pole();
        let pole_squared = pole.norm_squared();
        if pole_squared <= 0.0 || !pole_squared.is_finite() {
            return at_ends;
        }
        let t_in_plane = t - pole * (pole.dot(t) / pole_squared);
        let nearest = -t_in_plane;
        let on_arc = pole.dot(&self.from.cross(&nearest)) >= 0.0
            && pole.dot(&nearest.cross(&self.to)) >= 0.0;
        match t_in_plane.norm() {
            length if length > 0.0 && on_arc => -length,
            _ => at_ends,
        }
    }
}
