//! Which Rapier colliders the bridge reads, and their shapes.
//!
//! A collider is read when it is enabled, not a sensor, its shape is a
//! cuboid or a convex polyhedron, and its parent (if any) is enabled; a
//! dynamic parent must have no other enabled non-sensor collider. A
//! Rapier cuboid is the box `[-h, h]` in the collider frame, and a convex
//! polyhedron's points are in the collider frame: both become the
//! library's [`Shape`] in the same frame, unchanged but for f32 -> f64.

use nalgebra::{Isometry3, Point3};
use rapier3d::dynamics::{RigidBodyHandle, RigidBodySet};
use rapier3d::geometry::{Collider, ColliderHandle, ColliderSet};

use super::convert::{pose_to_f64, vector_to_f64};
use super::report::SkipReason;
use crate::body::Shape;

/// A cheap identity of a collider's shape, compared from step to step so
/// that shapes are built only when they change: a cuboid's half extents
/// (f32 bits), or the address and point count of a polyhedron's shared
/// shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum ShapeSignature {
    /// Half extents, f32 bits.
    Cuboid([u32; 3]),
    /// Address of the shared shape and number of points.
    Polyhedron { address: usize, points: usize },
}

/// A collider the bridge reads, as found in one call.
#[derive(Debug, Clone)]
pub(crate) struct ReadCollider {
    pub collider: ColliderHandle,
    /// The parent body, if any.
    pub body: Option<RigidBodyHandle>,
    /// The body's mass (f32 exactly as f64) if the parent is dynamic;
    /// `None` for a fixed, kinematic or missing parent.
    pub dynamic_mass: Option<f64>,
    /// `P`: the collider frame in the body frame (identity without parent).
    pub collider_in_body: Isometry3<f64>,
    pub signature: ShapeSignature,
}

/// Reads a collider, or says why it is skipped.
pub(crate) fn read_collider(
    handle: ColliderHandle,
    collider: &Collider,
    bodies: &RigidBodySet,
    colliders: &ColliderSet,
) -> Result<ReadCollider, SkipReason> {
    if collider.is_sensor() {
        return Err(SkipReason::Sensor);
    }
    if !collider.is_enabled() {
        return Err(SkipReason::Disabled);
    }
    let signature = signature(collider)?;
    let Some(body_handle) = collider.parent() else {
        return Ok(ReadCollider {
            collider: handle,
            body: None,
            dynamic_mass: None,
            collider_in_body: Isometry3::identity(),
            signature,
        });
    };
    let body = bodies.get(body_handle).ok_or(SkipReason::Disabled)?;
    if !body.is_enabled() {
        return Err(SkipReason::Disabled);
    }
    let collider_in_body = collider
        .position_wrt_parent()
        .map(pose_to_f64)
        .unwrap_or_else(Isometry3::identity);
    let dynamic_mass = if body.is_dynamic() {
        if other_solid_colliders(body.colliders(), handle, colliders) > 0 {
            return Err(SkipReason::SeveralColliders);
        }
        Some(f64::from(body.mass()))
    } else {
        None
    };
    Ok(ReadCollider {
        collider: handle,
        body: Some(body_handle),
        dynamic_mass,
        collider_in_body,
        signature,
    })
}

/// Number of enabled non-sensor colliders of a body other than `this`,
/// whatever their shape (a dynamic body is read only when `this` is its
/// single solid collider).
fn other_solid_colliders(
    all: &[ColliderHandle],
    this: ColliderHandle,
    colliders: &ColliderSet,
) -> usize {
    all.iter()
        .filter(|&&other| other != this)
        .filter_map(|&other| colliders.get(other))
        .filter(|other| other.is_enabled() && !other.is_sensor())
        .count()
}

fn signature(collider: &Collider) -> Result<ShapeSignature, SkipReason> {
    let shape = collider.shape();
    if let Some(cuboid) = shape.as_cuboid() {
        let h = cuboid.half_extents;
        return Ok(ShapeSignature::Cuboid([
            h.x.to_bits(),
            h.y.to_bits(),
            h.z.to_bits(),
        ]));
    }
    if let Some(polyhedron) = shape.as_convex_polyhedron() {
        return Ok(ShapeSignature::Polyhedron {
            address: std::ptr::from_ref(polyhedron) as *const u8 as usize,
            points: polyhedron.points().len(),
        });
    }
    Err(SkipReason::Shape(format!("{:?}", shape.shape_type())))
}

/// The library shape of a collider that [`read_collider`] accepted.
pub(crate) fn shape_of(collider: &Collider) -> Option<Shape> {
    let shape = collider.shape();
    if let Some(cuboid) = shape.as_cuboid() {
        return Some(Shape::Cuboid {
            half_extents: vector_to_f64(cuboid.half_extents),
        });
    }
    shape
        .as_convex_polyhedron()
        .map(|polyhedron| Shape::ConvexHull {
            points: polyhedron
                .points()
                .iter()
                .map(|&p| Point3::from(vector_to_f64(p)))
                .collect(),
        })
}
