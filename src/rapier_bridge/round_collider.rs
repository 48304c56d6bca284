//! Rapier's round and curved colliders as library shapes.
//!
//! | Rapier shape | library shape | placed in the collider frame by |
//! |---|---|---|
//! | `Ball` | `Sphere` | identity |
//! | `Capsule` (segment `a`–`b`, radius) | `Capsule` along `z` | the segment's midpoint, `z` turned onto `b - a` |
//! | `RoundCuboid` | `RoundCuboid` | identity |
//! | `RoundConvexPolyhedron` | `RoundConvexHull` of its points | identity |
//! | `Cylinder`, `Cone` (along `y`) | `Cylinder`, `Cone` (along `z`) | a quarter turn about `x` (`z` onto `y`) |
//!
//! Rapier's rounded cylinders and cones (a cylinder or cone grown by a
//! border radius) have no library shape and are skipped. The placement is
//! a part's own pose: a lone collider with one becomes a compound of one
//! part; a compound's part composes it with the collider's offset.

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use rapier3d::geometry::Collider;

use super::convert::vector_to_f64;
use crate::body::Shape;

/// A round shape and its placement in the collider frame (`None`: the
/// identity).
pub(crate) type PlacedShape = (Shape, Option<Isometry3<f64>>);

/// The round or curved shape of a collider, placed (module docs); `None`
/// for any other shape.
pub(crate) fn round_shape_of(collider: &Collider) -> Option<PlacedShape> {
    let shape = collider.shape();
    if let Some(ball) = shape.as_ball() {
        let radius = f64::from(ball.radius);
        return Some((Shape::Sphere { radius }, None));
    }
    if let Some(capsule) = shape.as_capsule() {
        let (a, b) = (
            vector_to_f64(capsule.segment.a),
            vector_to_f64(capsule.segment.b),
        );
        let axis = b - a;
        let rotation = UnitQuaternion::rotation_between(&Vector3::z(), &axis)
            // `z` and the axis opposite: half a turn about `x`.
            .unwrap_or_else(|| {
                UnitQuaternion::from_scaled_axis(Vector3::x() * std::f64::consts::PI)
            });
        let placement = Isometry3::from_parts(Translation3::from((a + b) / 2.0), rotation);
        let shape = Shape::Capsule {
            half_height: axis.norm() / 2.0,
            radius: f64::from(capsule.radius),
        };
        return Some((
            shape,
            (placement != Isometry3::identity()).then_some(placement),
        ));
    }
    if let Some(rounded) = shape.as_round_cuboid() {
        let shape = Shape::RoundCuboid {
            half_extents: vector_to_f64(rounded.inner_shape.half_extents),
            radius: f64::from(rounded.border_radius),
        };
        return Some((shape, None));
    }
    if let Some(rounded) = shape.as_round_convex_polyhedron() {
        let points = rounded
            .inner_shape
            .points()
            .iter()
            .map(|&p| Point3::from(vector_to_f64(p)))
            .collect();
        let radius = f64::from(rounded.border_radius);
        return Some((Shape::RoundConvexHull { points, radius }, None));
    }
    let z_onto_y = Isometry3::rotation(Vector3::x() * -std::f64::consts::FRAC_PI_2);
    if let Some(cylinder) = shape.as_cylinder() {
        let shape = Shape::Cylinder {
            half_height: f64::from(cylinder.half_height),
            radius: f64::from(cylinder.radius),
        };
        return Some((shape, Some(z_onto_y)));
    }
    if let Some(cone) = shape.as_cone() {
        let shape = Shape::Cone {
            half_height: f64::from(cone.half_height),
            radius: f64::from(cone.radius),
        };
        return Some((shape, Some(z_onto_y)));
    }
    None
}

/// The bits of a round shape's numbers, its identity from step to step
/// (f32 bits; the shared shape's address and point count for a rounded
/// polyhedron, in the first three words).
pub(crate) fn round_signature(collider: &Collider) -> Option<(u8, [u32; 7])> {
    let shape = collider.shape();
    let bits = |v: &[f32]| {
        let mut out = [0u32; 7];
        for (slot, x) in out.iter_mut().zip(v) {
            *slot = x.to_bits();
        }
        out
    };
    if let Some(ball) = shape.as_ball() {
        return Some((0, bits(&[ball.radius])));
    }
    if let Some(c) = shape.as_capsule() {
        let (a, b) = (c.segment.a, c.segment.b);
        return Some((1, bits(&[a.x, a.y, a.z, b.x, b.y, b.z, c.radius])));
    }
    if let Some(r) = shape.as_round_cuboid() {
        let h = r.inner_shape.half_extents;
        return Some((2, bits(&[h.x, h.y, h.z, r.border_radius])));
    }
    if let Some(r) = shape.as_round_convex_polyhedron() {
        let address = std::ptr::from_ref(r) as *const u8 as usize as u64;
        let mut out = bits(&[r.border_radius]);
        // The address split into two words, the point count in a third.
        out[1] = (address >> 32) as u32;
        out[2] = address as u32;
        out[3] = r.inner_shape.points().len() as u32;
        return Some((3, out));
    }
    if let Some(c) = shape.as_cylinder() {
        return Some((4, bits(&[c.half_height, c.radius])));
    }
    if let Some(c) = shape.as_cone() {
        return Some((5, bits(&[c.half_height, c.radius])));
    }
    None
}
