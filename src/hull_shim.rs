//! TEMPORARY until branch `geometry` is merged (it provides the real
//! `ConvexPolyhedron::from_points`): hull by parry, faces left as triangles.

use nalgebra::Point3;
use parry3d_f64::math::Vector;

use crate::geometry::{ConvexPolyhedron, GeometryError};

impl ConvexPolyhedron {
    /// Convex hull of `points` (temporary shim).
    pub fn from_points(points: &[Point3<f64>]) -> Result<Self, GeometryError> {
        if points.is_empty() {
            return Err(GeometryError::Empty);
        }
        if let Some(index) = points.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
            return Err(GeometryError::NonFinite { index });
        }
        let input: Vec<Vector> = points.iter().map(|p| Vector::new(p.x, p.y, p.z)).collect();
        let (vertices, triangles) = parry3d_f64::transformation::try_convex_hull(&input)
            .map_err(|_| GeometryError::Degenerate)?;
        let vertices = vertices
            .iter()
            .map(|v| Point3::new(v.x, v.y, v.z))
            .collect();
        let faces = triangles
            .iter()
            .map(|t| t.iter().map(|&i| i as usize).collect())
            .collect();
        Self::from_faces(vertices, faces)
    }
}
