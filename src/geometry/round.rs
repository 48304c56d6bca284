//! Round shapes: a *core* grown by a *radius* (the Minkowski sum of the
//! core and the ball of that radius, `docs/round-shapes.md`).
//!
//! | shape | core | radius |
//! |---|---|---|
//! | sphere | a point | the sphere's |
//! | capsule | a segment along the part's `z`, `[-h, h]` | the capsule's |
//! | rounded cuboid | the cuboid's polyhedron | the rounding's (`>= 0`) |
//! | rounded hull | the hull's polyhedron | the rounding's (`>= 0`) |
//!
//! Every point of the solid is within `radius` of the core, and the support
//! function is the core's plus the radius: `h(n) = h_core(n) + r` for a
//! unit `n`. The core is given in the part's frame (its origin at the
//! core's centre: the point, the segment's midpoint, the polyhedron's
//! centre of mass).

use nalgebra::{Point3, Vector3};

use super::{ConvexPolyhedron, GeometryError};

/// The core of a round part, in the part's frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RoundCore {
    /// The origin (a sphere).
    Point,
    /// The segment from `-half_length z` to `+half_length z` (a capsule).
    Segment {
        /// Half the segment's length (> 0).
        half_length: f64,
    },
    /// The part's polyhedron (a rounded cuboid or hull).
    Polyhedron,
}

/// A round part's core and radius.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rounding {
    /// The core.
    pub core: RoundCore,
    /// The radius by which the core is grown (>= 0; > 0 for a point or a
    /// segment).
    pub radius: f64,
}

impl Rounding {
    /// The ends of a point or segment core, part frame (`None` for a
    /// polyhedron core): the same point twice for a point.
    pub fn segment(&self) -> Option<[Point3<f64>; 2]> {
        match self.core {
            RoundCore::Point => Some([Point3::origin(); 2]),
            RoundCore::Segment { half_length } => Some([
                Point3::new(0.0, 0.0, -half_length),
                Point3::new(0.0, 0.0, half_length),
            ]),
            RoundCore::Polyhedron => None,
        }
    }

    /// Largest distance of a point of the solid from the part's origin,
    /// given the polyhedron that stands for the part.
    pub fn reach(&self, polyhedron: &ConvexPolyhedron) -> f64 {
        match self.core {
            RoundCore::Point => self.radius,
            RoundCore::Segment { half_length } => half_length + self.radius,
            RoundCore::Polyhedron => polyhedron.scale() + self.radius,
        }
    }
}

/// Checks a rounding radius: finite and `>= 0`.
pub fn check_radius(radius: f64) -> Result<(), GeometryError> {
    if radius.is_finite() && radius >= 0.0 {
        Ok(())
    } else {
        Err(GeometryError::InvalidRadius { value: radius })
    }
}

/// The polyhedron that stands for a point or segment core grown by
/// `radius` where a polyhedron is needed (warm-start keys, the length
/// scale): the box `[-r, r]^2 x [-(h + r), h + r]` that holds the solid.
/// The narrow phase never runs on it.
pub fn bounding_box(half_length: f64, radius: f64) -> Result<ConvexPolyhedron, GeometryError> {
    ConvexPolyhedron::cuboid(Vector3::new(radius, radius, half_length + radius))
}
