//! Cylinders and cones as polyhedra that bound the true solid within a
//! stated deviation (`docs/round-shapes.md`, "Cylinders and cones").
//!
//! The circle of radius `r` is replaced by the regular `N`-gon
//! *circumscribed* about it: its edges touch the circle and its vertices
//! lie at `r / cos(π/N)`. The polygon holds the circle, so the polyhedron
//! holds the solid (a correction that separates the polyhedra separates the
//! true shapes too), and no point of its surface is farther from the true
//! surface than `r (1/cos(π/N) - 1)`. `N` is the least number of sides for
//! which that deviation is at most [`CURVED_DEVIATION_RELATIVE`] of `r`:
//!
//! ```text
//! N = ceil( π / acos( 1 / (1 + ε) ) )      (ε = 1e-3: N = 71)
//! ```
//!
//! The flat faces (a cylinder's two caps, a cone's base) are exact, so a
//! cylinder standing on its cap rests exactly; only contacts on the curved
//! side are approximate. Mass properties are the true solid's, in closed
//! form (`round_mass`).

use std::f64::consts::PI;

use nalgebra::Point3;

use super::{ConvexPolyhedron, GeometryError};

/// The largest distance between the polyhedral approximation of a
/// cylinder's or cone's curved surface and the true surface, relative to
/// the radius (module docs). The narrow phase's depths on curved sides
/// exceed the true depth by at most this times the radius.
pub const CURVED_DEVIATION_RELATIVE: f64 = 1e-3;

/// Number of sides of the circumscribed polygon for relative deviation
/// `deviation` (module docs), at least 3.
pub fn sides_for(deviation: f64) -> usize {
    let half_angle = (1.0 / (1.0 + deviation)).acos();
    // The ratio is finite and positive for any deviation > 0, the count
    // small (71 at 1e-3); `as` saturates for an absurdly small deviation.
    ((PI / half_angle).ceil() as usize).max(3)
}

/// The deviation, relative to the radius, of the circumscribed polygon of
/// `sides` sides: `1/cos(π/N) - 1`.
pub fn deviation_of(sides: usize) -> f64 {
    1.0 / (PI / sides as f64).cos() - 1.0
}

fn ring(radius: f64, sides: usize, z: f64) -> impl Iterator<Item = Point3<f64>> {
    let circumradius = circumradius(radius, sides);
    (0..sides).map(move |i| {
        let angle = 2.0 * PI * i as f64 / sides as f64;
        Point3::new(circumradius * angle.cos(), circumradius * angle.sin(), z)
    })
}

fn circumradius(radius: f64, sides: usize) -> f64 {
    radius * (1.0 + deviation_of(sides))
}

/// The cylinder along `z` of half height `half_height` and radius
/// `radius`, as the prism over the circumscribed polygon.
pub fn cylinder(half_height: f64, radius: f64) -> Result<ConvexPolyhedron, GeometryError> {
    check_positive("half_height", half_height)?;
    check_positive("radius", radius)?;
    let sides = sides_for(CURVED_DEVIATION_RELATIVE);
    ConvexPolyhedron::disk(circumradius(radius, sides), 2.0 * half_height, sides)
}

/// The cone along `z` (base of radius `radius` at `z = -half_height`, apex
/// at `z = half_height`), as the pyramid over the circumscribed polygon.
pub fn cone(half_height: f64, radius: f64) -> Result<ConvexPolyhedron, GeometryError> {
    check_positive("half_height", half_height)?;
    check_positive("radius", radius)?;
    let sides = sides_for(CURVED_DEVIATION_RELATIVE);
    let mut points: Vec<Point3<f64>> = ring(radius, sides, -half_height).collect();
    points.push(Point3::new(0.0, 0.0, half_height));
    let apex = sides;
    let mut faces = vec![(0..sides).rev().collect::<Vec<_>>()];
    faces.extend((0..sides).map(|i| vec![i, (i + 1) % sides, apex]));
    ConvexPolyhedron::from_faces(points, faces)
}

fn check_positive(name: &'static str, value: f64) -> Result<(), GeometryError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(GeometryError::InvalidDimension { name, value })
    }
}
