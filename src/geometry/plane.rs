//! Oriented planes `{x : n . x + w = 0}` with unit normal `n`.
//!
//! The signed distance of a point `y` is `D(y) = n . y + w`; positive on the
//! side the normal points to.

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
