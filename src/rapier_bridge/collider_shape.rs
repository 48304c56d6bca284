//! Which Rapier colliders the bridge reads, and their shapes.
//!
//! A collider is read when it is enabled, not a sensor, its shape is a
//! cuboid, a convex polyhedron or a round or curved shape
//! ([`super::round_collider`]: ball, capsule, rounded cuboid and convex
//! polyhedron, cylinder, cone), and its parent (if any) is enabled. A
//! Rapier cuboid is the box `[-h, h]` in the collider frame, and a convex
//! polyhedron's points are in the collider frame: both become the
//! library's [`Shape`] in the same frame, unchanged but for f32 -> f64.
//!
//! A dynamic body with several enabled non-sensor colliders is read whole,
//! as one compound ([`Shape::Compound`]) in the rigid body's frame: each
//! collider a part at its `P = position_wrt_parent`. Every one of its
//! colliders must be a cuboid or a convex polyhedron; otherwise all of
//! them are skipped with the reason of the first that is not.

use nalgebra::{Isometry3, Point3};
use rapier3d::dynamics::{RigidBodyHandle, RigidBodySet};
use rapier3d::geometry::{Collider, ColliderHandle, ColliderSet};

use super::convert::{pose_to_f64, vector_to_f64, xyzw};
use super::engine_mass::EngineMass;
use super::report::SkipReason;
use super::round_collider::{PlacedShape, round_shape_of, round_signature};
use crate::body::{Shape, ShapePart};

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
    /// A round or curved shape: its kind and numbers
    /// ([`super::round_collider::round_signature`]).
    Round { kind: u8, bits: [u32; 7] },
}

/// One collider of a compound, as read.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ReadPart {
    pub collider: ColliderHandle,
    /// `P_i`: the collider frame in the body frame.
    pub collider_in_body: Isometry3<f64>,
    pub signature: ShapeSignature,
}

/// A collider the bridge reads, as found in one call; or, for a dynamic
/// body with several colliders, the whole body.
#[derive(Debug, Clone)]
pub(crate) struct ReadCollider {
    /// The collider (a compound's first collider, in the body's order).
    pub collider: ColliderHandle,
    /// The parent body, if any.
    pub body: Option<RigidBodyHandle>,
    /// The body's mass (f32 exactly as f64) if the parent is dynamic;
    /// `None` for a fixed, kinematic or missing parent.
    pub dynamic_mass: Option<f64>,
    /// The dynamic parent's own mass properties (`super::engine_mass`);
    /// `None` for a fixed body, or when Rapier's are not usable.
    pub engine_mass: Option<EngineMass>,
    /// `P`: the collider frame in the body frame (identity without parent,
    /// and for a compound, whose frame is the body's).
    pub collider_in_body: Isometry3<f64>,
    pub signature: ShapeSignature,
    /// A compound's colliders, in the body's order (empty for one
    /// collider).
    pub parts: Vec<ReadPart>,
}

/// Reads a collider that is not part of a compound
/// ([`compound_parent`]), or says why it is skipped.
pub(crate) fn read_collider(
    handle: ColliderHandle,
    collider: &Collider,
    bodies: &RigidBodySet,
) -> Result<ReadCollider, SkipReason> {
    if collider.is_sensor() {
        return Err(SkipReason::Sensor);
    }
    if !collider.is_enabled() {
        return Err(SkipReason::Disabled);
    }
    let own_signature = signature(collider)?;
    let Some(body_handle) = collider.parent() else {
        return Ok(ReadCollider {
            collider: handle,
            body: None,
            dynamic_mass: None,
            engine_mass: None,
            collider_in_body: Isometry3::identity(),
            signature: own_signature,
            parts: Vec::new(),
        });
    };
    let body = bodies.get(body_handle).ok_or(SkipReason::Disabled)?;
    if !body.is_enabled() {
        return Err(SkipReason::Disabled);
    }
    Ok(ReadCollider {
        collider: handle,
        body: Some(body_handle),
        dynamic_mass: body.is_dynamic().then(|| f64::from(body.mass())),
        engine_mass: body.is_dynamic().then(|| EngineMass::of(body)).flatten(),
        collider_in_body: offset_in_body(collider),
        signature: own_signature,
        parts: Vec::new(),
    })
}

/// The dynamic, enabled body of which `collider` is one of several
/// enabled non-sensor colliders (a compound); `None` otherwise.
pub(crate) fn compound_parent(
    collider: &Collider,
    bodies: &RigidBodySet,
    colliders: &ColliderSet,
) -> Option<RigidBodyHandle> {
    if collider.is_sensor() || !collider.is_enabled() {
        return None;
    }
    let handle = collider.parent()?;
    let body = bodies.get(handle)?;
    let several = body.is_enabled()
        && body.is_dynamic()
        && solid_colliders(body.colliders(), colliders).len() > 1;
    several.then_some(handle)
}

/// Reads the compound of a body that [`compound_parent`] found: every
/// solid collider a part, or the reason of the first that cannot be one.
pub(crate) fn read_compound(
    handle: RigidBodyHandle,
    bodies: &RigidBodySet,
    colliders: &ColliderSet,
) -> Result<ReadCollider, SkipReason> {
    let body = bodies.get(handle).ok_or(SkipReason::Disabled)?;
    let parts = solid_colliders(body.colliders(), colliders)
        .into_iter()
        .map(|(part, collider)| {
            Ok(ReadPart {
                collider: part,
                collider_in_body: offset_in_body(collider),
                signature: signature(collider)?,
            })
        })
        .collect::<Result<Vec<_>, SkipReason>>()?;
    let first = parts.first().ok_or(SkipReason::Disabled)?;
    Ok(ReadCollider {
        collider: first.collider,
        body: Some(handle),
        dynamic_mass: Some(f64::from(body.mass())),
        engine_mass: EngineMass::of(body),
        collider_in_body: Isometry3::identity(),
        signature: first.signature,
        parts,
    })
}

/// `P`: the collider frame in its parent's frame (identity without one).
fn offset_in_body(collider: &Collider) -> Isometry3<f64> {
    collider
        .position_wrt_parent()
        .map(pose_to_f64)
        .unwrap_or_else(Isometry3::identity)
}

/// The enabled non-sensor colliders of a body, in its order, whatever
/// their shape.
fn solid_colliders<'a>(
    all: &[ColliderHandle],
    colliders: &'a ColliderSet,
) -> Vec<(ColliderHandle, &'a Collider)> {
    all.iter()
        .filter_map(|&handle| Some((handle, colliders.get(handle)?)))
        .filter(|(_, collider)| collider.is_enabled() && !collider.is_sensor())
        .collect()
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
    if let Some((kind, bits)) = round_signature(collider) {
        return Ok(ShapeSignature::Round { kind, bits });
    }
    Err(SkipReason::Shape(format!("{:?}", shape.shape_type())))
}

/// The library shape of what [`read_collider`] accepted: the collider's
/// shape, or the compound of a body's colliders.
pub(crate) fn shape_of_read(read: &ReadCollider, colliders: &ColliderSet) -> Option<Shape> {
    if read.parts.is_empty() {
        return match shape_of(colliders.get(read.collider)?)? {
            (shape, None) => Some(shape),
            // A shape placed off the collider frame: a compound of one.
            (shape, Some(placement)) => Some(Shape::Compound {
                parts: vec![ShapePart {
                    shape,
                    translation: placement.translation.vector,
                    rotation_xyzw: xyzw(&placement.rotation),
                }],
            }),
        };
    }
    let parts = read
        .parts
        .iter()
        .map(|part| {
            let (shape, placement) = shape_of(colliders.get(part.collider)?)?;
            let pose = match placement {
                None => part.collider_in_body,
                Some(placement) => part.collider_in_body * placement,
            };
            Some(ShapePart {
                shape,
                translation: pose.translation.vector,
                rotation_xyzw: xyzw(&pose.rotation),
            })
        })
        .collect::<Option<Vec<_>>>()?;
    Some(Shape::Compound { parts })
}

/// The library shape of a collider that [`read_collider`] accepted, and
/// its placement in the collider frame (`None`: the identity).
fn shape_of(collider: &Collider) -> Option<PlacedShape> {
    if let Some(placed) = round_shape_of(collider) {
        return Some(placed);
    }
    polyhedral_shape_of(collider).map(|shape| (shape, None))
}

/// A cuboid or convex polyhedron collider's shape.
fn polyhedral_shape_of(collider: &Collider) -> Option<Shape> {
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
