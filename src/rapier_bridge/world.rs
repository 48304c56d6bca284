//! [`world_from_scene`]: the Rapier world of a scene, the inverse of what
//! [`super::RapierBridge`] reads.
//!
//! Each scene body becomes one rigid body (fixed or dynamic) placed at the
//! body's user pose, with one collider of the same shape at the identity
//! offset (collider frame = body frame = the scene's shape frame):
//!
//! | scene body | Rapier |
//! |---|---|
//! | fixed | `RigidBodyBuilder::fixed()` |
//! | dynamic, mass `m` | `RigidBodyBuilder::dynamic()`, collider with `mass(m)` (uniform density over the shape, so the same inertia) |
//! | `Shape::Cuboid` | `ColliderBuilder::cuboid` with the half extents |
//! | `Shape::ConvexHull` | `ColliderBuilder::convex_hull` of the points |
//! | `Shape::Compound` | one collider per part, at the part's pose in the body frame, each with the part's share of the mass (its share of the volume) |
//!
//! Every number is rounded to f32 (Rapier's default build); poses as in
//! [`super::pose_from_f64`]. The world has Rapier's default integration
//! parameters (60 Hz) and the given gravity; the bodies start at rest,
//! awake. A scene read back through the bridge equals the scene but for
//! that rounding (and a hull's interior points, which Rapier drops).

use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion, Vector3};
use rapier3d::dynamics::{RigidBodyBuilder, RigidBodyHandle};
use rapier3d::geometry::{ColliderBuilder, ColliderHandle};
use rapier3d::math::{Pose, Vector};
use rapier3d::pipeline::PhysicsWorld;

use super::convert::pose_from_f64;
use super::error::BridgeError;
use crate::body::Shape;
use crate::scene::Scene;

/// Standard gravity along `-z` (m/s^2): the engine states of
/// `tests/data/engine/` are z up.
pub const GRAVITY_Z_UP: Vector3<f64> = Vector3::new(0.0, 0.0, -9.81);

/// A Rapier world built from a scene, with the handles of each scene body.
#[derive(Default)]
pub struct SceneWorld {
    /// The world: bodies, colliders, pipeline, default integration
    /// parameters, the given gravity.
    pub world: PhysicsWorld,
    /// `bodies[i]`: the rigid body of scene body `i`.
    pub bodies: Vec<RigidBodyHandle>,
    /// `colliders[i]`: the collider of scene body `i` (a compound's first
    /// part's).
    pub colliders: Vec<ColliderHandle>,
    /// `part_colliders[i]`: the colliders of scene body `i`'s parts, in
    /// order (one for a convex body).
    pub part_colliders: Vec<Vec<ColliderHandle>>,
}

/// The Rapier world of `scene` (see the module doc); an error names a body
/// whose pose or shape does not fit in f32, or whose hull Rapier cannot
/// build.
pub fn world_from_scene(scene: &Scene, gravity: Vector3<f64>) -> Result<SceneWorld, BridgeError> {
    let mut out = SceneWorld {
        world: PhysicsWorld {
            gravity: f32_vector(&gravity),
            ..PhysicsWorld::default()
        },
        ..SceneWorld::default()
    };
    for (index, body) in scene.bodies().iter().enumerate() {
        let invalid = |reason: &str| BridgeError::SceneBody {
            index,
            name: body.name().to_owned(),
            reason: reason.to_owned(),
        };
        let pose = pose_from_f64(&body.user_pose());
        if !(pose.translation.is_finite() && pose.rotation.is_finite()) {
            return Err(invalid("pose not finite in f32"));
        }
        let rigid_body = match body.is_fixed() {
            true => RigidBodyBuilder::fixed(),
            false => RigidBodyBuilder::dynamic(),
        };
        let body_handle = out.world.insert_body(rigid_body.pose(pose));
        let pieces: Vec<(&Shape, Pose)> = match body.shape() {
            Shape::Compound { parts } => parts
                .iter()
                .map(|part| {
                    let q = part.rotation_xyzw;
                    let rotation =
                        UnitQuaternion::from_quaternion(Quaternion::new(q[3], q[0], q[1], q[2]));
                    let offset =
                        Isometry3::from_parts(Translation3::from(part.translation), rotation);
                    (&part.shape, pose_from_f64(&offset))
                })
                .collect(),
            convex => vec![(convex, Pose::IDENTITY)],
        };
        let volume_of = |shape: &Shape| shape.volume().unwrap_or(0.0);
        let total_volume: f64 = pieces.iter().map(|(shape, _)| volume_of(shape)).sum();
        let mut handles = Vec::with_capacity(pieces.len());
        for (shape, offset) in pieces {
            let (collider, axis) = collider_of(shape)
                .ok_or_else(|| invalid("Rapier cannot build the hull of its points"))?;
            let offset = offset * axis;
            let collider = match body.mass() {
                // Uniform density: each part's share of the mass is its
                // share of the volume.
                Some(mass) => collider.mass((mass.mass * volume_of(shape) / total_volume) as f32),
                None => collider,
            };
            handles.push(
                out.world
                    .insert_collider(collider.position(offset), Some(body_handle)),
            );
        }
        out.bodies.push(body_handle);
        out.colliders.push(handles[0]);
        out.part_colliders.push(handles);
    }
    Ok(out)
}

/// The collider of a convex shape and its pose in the shape frame (`None`
/// for a hull Rapier cannot build, or a compound). Rapier's cylinders and
/// cones stand along `y`, the library's along `z`: they are turned by a
/// quarter turn about `x`.
fn collider_of(shape: &Shape) -> Option<(ColliderBuilder, Pose)> {
    let hull = |points: &[nalgebra::Point3<f64>]| -> Vec<Vector> {
        points.iter().map(|p| f32_vector(&p.coords)).collect()
    };
    let y_to_z = pose_from_f64(&Isometry3::rotation(
        Vector3::x() * std::f64::consts::FRAC_PI_2,
    ));
    let builder = match shape {
        Shape::Cuboid { half_extents } => {
            let h = f32_vector(half_extents);
            ColliderBuilder::cuboid(h.x, h.y, h.z)
        }
        Shape::ConvexHull { points } => ColliderBuilder::convex_hull(&hull(points))?,
        Shape::Sphere { radius } => ColliderBuilder::ball(*radius as f32),
        Shape::Capsule {
            half_height,
            radius,
        } => ColliderBuilder::capsule_z(*half_height as f32, *radius as f32),
        Shape::RoundCuboid {
            half_extents,
            radius,
        } => {
            let h = f32_vector(half_extents);
            ColliderBuilder::round_cuboid(h.x, h.y, h.z, *radius as f32)
        }
        Shape::RoundConvexHull { points, radius } => {
            ColliderBuilder::round_convex_hull(&hull(points), *radius as f32)?
        }
        Shape::Cylinder {
            half_height,
            radius,
        } => {
            let builder = ColliderBuilder::cylinder(*half_height as f32, *radius as f32);
            return Some((builder, y_to_z));
        }
        Shape::Cone {
            half_height,
            radius,
        } => {
            let builder = ColliderBuilder::cone(*half_height as f32, *radius as f32);
            return Some((builder, y_to_z));
        }
        Shape::Compound { .. } => return None,
    };
    Some((builder, Pose::IDENTITY))
}

/// Components rounded to f32.
fn f32_vector(v: &Vector3<f64>) -> Vector {
    Vector::new(v.x as f32, v.y as f32, v.z as f32)
}
