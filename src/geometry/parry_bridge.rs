//! Conversions between this crate's nalgebra types and parry3d-f64's glam
//! types (`parry3d_f64::math::{Vector, Pose}` = glamx `DVec3`, `DPose3`).
//!
//! The broad phase uses parry's AABBs and BVH; the tests use parry's
//! `query::distance` / `query::contact` (GJK/EPA) as oracles. A pose maps
//! body coordinates to world coordinates, `p_world = R p_body + t`, in both
//! libraries: an `Isometry3 { rotation: R, translation: t }` is the
//! `Pose { rotation: R, translation: t }`.
//!
//! [`ConvexPolyhedron::to_parry`] keeps the body-frame vertices (origin at
//! the centre of mass), so the same pose places both shapes.

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use parry3d_f64::math::{Pose, Vector};
use parry3d_f64::shape::ConvexPolyhedron as ParryConvexPolyhedron;

use super::{ConvexPolyhedron, GeometryError};

impl ConvexPolyhedron {
    /// The same solid as a parry3d-f64 convex polyhedron, in the body frame
    /// (same vertices, same order). Faces are fanned into triangles and
    /// given to parry's `from_convex_mesh`; should parry reject that mesh,
    /// its own hull of the vertices is used.
    ///
    /// The vertices, hence the support function (all that GJK, EPA and
    /// AABBs use), are exactly ours. parry's *faces* are not: it merges
    /// adjacent triangles whose normals are within about `1.7e-4` rad
    /// (`1 - n1·n2 < sqrt(ε)`), and on thin hulls its
    /// `Shape::mass_properties` then loses volume (half of it for a slab of
    /// relative thickness `3e-5`). Use [`ConvexPolyhedron::mass_properties`].
    pub fn to_parry(&self) -> Result<ParryConvexPolyhedron, GeometryError> {
        let points: Vec<Vector> = self.vertices().iter().map(point_to_parry).collect();
        let triangles: Vec<[u32; 3]> = self
            .faces()
            .iter()
            .flat_map(|face| {
                let cycle = &face.vertices;
                (1..cycle.len() - 1)
                    .map(move |i| [cycle[0], cycle[i], cycle[i + 1]].map(|v| v as u32))
            })
            .collect();
        ParryConvexPolyhedron::from_convex_mesh(points.clone(), &triangles)
            .or_else(|| ParryConvexPolyhedron::from_convex_hull(&points))
            .ok_or_else(|| GeometryError::HullFailed("parry rejected the polyhedron".into()))
    }
}

/// A nalgebra isometry (body → world) as a parry pose.
pub fn isometry_to_parry(isometry: &Isometry3<f64>) -> Pose {
    Pose::from_parts(
        vector_to_parry(&isometry.translation.vector),
        isometry.rotation.into(),
    )
}

/// A parry pose as a nalgebra isometry (body → world).
pub fn isometry_from_parry(pose: &Pose) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::from(vector_from_parry(pose.translation)),
        UnitQuaternion::from(pose.rotation),
    )
}

/// A point as a parry vector (parry represents points by vectors).
pub fn point_to_parry(point: &Point3<f64>) -> Vector {
    Vector::new(point.x, point.y, point.z)
}

/// A parry vector read as a point.
pub fn point_from_parry(point: Vector) -> Point3<f64> {
    Point3::new(point.x, point.y, point.z)
}

/// A vector as a parry vector.
pub fn vector_to_parry(vector: &Vector3<f64>) -> Vector {
    Vector::new(vector.x, vector.y, vector.z)
}

/// A parry vector as a nalgebra vector.
pub fn vector_from_parry(vector: Vector) -> Vector3<f64> {
    Vector3::new(vector.x, vector.y, vector.z)
}
