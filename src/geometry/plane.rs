//! Oriented planes `{x : n . x + w = 0}` with unit normal `n`.
//!
//! The signed distance of a point `y` is `D(y) = n . y + w`; positive on the
//! side the normal points to.
//!
//! [`triangle_area_vector`] is the one place where a normal is taken from
//! three points: `(b - a) × (c - a)` rounds each component at about
//! `ε |b - a| |c - a|`, so it is computed at the corner opposite the
//! longest side, where the two sides are shortest and their angle largest
//! (at least 60°). A thin right triangle (legs `l` and `w`) then has a
//! normal accurate to about `ε`, instead of `ε l / w` when taken from two
//! long sides (Shewchuk, "Lecture notes on geometric robustness", 2013,
//! on triangle normals).

use nalgebra::{Point3, Vector3};

/// An oriented plane with a unit normal, in the frame of its polyhedron.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    /// Unit normal.
    pub normal: Vector3<f64>,
    /// Offset `w`, so that `normal . x + offset = 0` on the plane.
    pub offset: f64,
}

impl Plane {
    /// The plane through `point` with unit normal `normal`.
    pub fn through(point: &Point3<f64>, normal: Vector3<f64>) -> Self {
        Plane {
            normal,
            offset: -normal.dot(&point.coords),
        }
    }

    /// Signed distance `n . y + w` of `y`.
    pub fn signed_distance(&self, y: &Point3<f64>) -> f64 {
        self.normal.dot(&y.coords) + self.offset
    }

    /// The same plane with the opposite orientation.
    pub fn flipped(&self) -> Self {
        Plane {
            normal: -self.normal,
            offset: -self.offset,
        }
    }
}

/// Twice the area times the unit normal of the counter-clockwise triangle
/// `(a, b, c)`, taken at the corner opposite its longest side (module doc).
pub(crate) fn triangle_area_vector(
    a: &Point3<f64>,
    b: &Point3<f64>,
    c: &Point3<f64>,
) -> Vector3<f64> {
    let side = |p: &Point3<f64>, q: &Point3<f64>| (q - p).norm_squared();
    let (ab, bc, ca) = (side(a, b), side(b, c), side(c, a));
    if bc >= ab && bc >= ca {
        (b - a).cross(&(c - a))
    } else if ca >= ab {
        (c - b).cross(&(a - b))
    } else {
        (a - c).cross(&(b - c))
    }
}
