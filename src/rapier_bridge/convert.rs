//! Poses across the boundary: Rapier's f32 `Pose` (glam) and the library's
//! f64 `Isometry3` (nalgebra).
//!
//! f32 to f64 is exact. f64 to f32 rounds each component to nearest; the
//! quaternion is renormalized in f32 afterwards, as Rapier expects unit
//! rotations.

use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion, Vector3};
use rapier3d::math::{Pose, Rotation, Vector};

/// The f64 isometry of a Rapier pose (exact conversion of each component;
/// the quaternion is renormalized in f64).
pub fn pose_to_f64(pose: &Pose) -> Isometry3<f64> {
    let t = pose.translation;
    let q = pose.rotation;
    let rotation = UnitQuaternion::from_quaternion(Quaternion::new(
        f64::from(q.w),
        f64::from(q.x),
        f64::from(q.y),
        f64::from(q.z),
    ));
    Isometry3::from_parts(
        Translation3::new(f64::from(t.x), f64::from(t.y), f64::from(t.z)),
        rotation,
    )
}

/// The Rapier pose nearest to an f64 isometry (components rounded to f32,
/// quaternion renormalized in f32).
pub fn pose_from_f64(isometry: &Isometry3<f64>) -> Pose {
    let t = isometry.translation.vector;
    let q = isometry.rotation.quaternion();
    let rotation = Rotation::from_xyzw(q.i as f32, q.j as f32, q.k as f32, q.w as f32).normalize();
    Pose::from_parts(Vector::new(t.x as f32, t.y as f32, t.z as f32), rotation)
}

/// An f32 Rapier vector as f64 (exact).
pub(crate) fn vector_to_f64(v: Vector) -> Vector3<f64> {
    Vector3::new(f64::from(v.x), f64::from(v.y), f64::from(v.z))
}

/// `[x, y, z, w]` of a unit quaternion.
pub(crate) fn xyzw(rotation: &UnitQuaternion<f64>) -> [f64; 4] {
    let q = rotation.quaternion();
    [q.i, q.j, q.k, q.w]
}
