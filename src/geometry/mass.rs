//! Mass properties of a solid convex polyhedron at uniform density.
//!
//! The solid is split into tetrahedra `(r, a, b, c)` that fan each face
//! `(v0, v_i, v_{i+1})` from a reference point `r` inside the hull. With
//! `A = [a - r, b - r, c - r]` and `d = det A`, a tetrahedron has volume
//! `d / 6`, centroid `r + (a + b + c - 3r) / 4` and second moment about `r`
//!
//! ```text
//! C = d / 120 * (A A^T + (A 1)(A 1)^T),    C = ∫ x x^T dV  (x relative to r)
//! ```
//!
//! (Tonon 2004, "Explicit exact formulas for the 3-D tetrahedron inertia
//! tensor"). Summed over all tetrahedra, then moved to the centre of mass
//! `c` by `C_c = C_r - V (c - r)(c - r)^T`; the inertia tensor is
//! `I = tr(C) I3 - C` per unit density.

use nalgebra::{Matrix3, Point3, Vector3};

/// Volume, centre of mass and inertia of a solid at unit density.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MassProperties {
    /// Volume of the solid (length³).
    pub volume: f64,
    /// Centre of mass, in the frame in which the vertices were given.
    pub center_of_mass: Point3<f64>,
    /// Inertia tensor about the centre of mass at unit density
    /// (length⁵); multiply by the density to get mass·length².
    pub inertia_unit_density: Matrix3<f64>,
}

impl MassProperties {
    /// Mass properties of the solid bounded by the counter-clockwise `faces`
    /// (indices into `vertices`).
    pub fn of_polyhedron(vertices: &[Point3<f64>], faces: &[Vec<usize>]) -> Self {
        let reference = vertex_centroid(vertices);
        let mut volume = 0.0;
        let mut first_moment = Vector3::zeros();
        let mut second_moment = Matrix3::zeros();
        for cycle in faces {
            let a = vertices[cycle[0]] - reference;
            for i in 1..cycle.len() - 1 {
                let b = vertices[cycle[i]] - reference;
                let c = vertices[cycle[i + 1]] - reference;
                let basis = Matrix3::from_columns(&[a, b, c]);
                let det = basis.determinant();
                let sum = a + b + c;
                volume += det / 6.0;
                first_moment += sum * (det / 24.0);
                second_moment +=
                    (basis * basis.transpose() + sum * sum.transpose()) * (det / 120.0);
            }
        }
        let offset = first_moment / volume;
        let covariance = second_moment - offset * offset.transpose() * volume;
        MassProperties {
            volume,
            center_of_mass: reference + offset,
            inertia_unit_density: Matrix3::identity() * covariance.trace() - covariance,
        }
    }
}

fn vertex_centroid(vertices: &[Point3<f64>]) -> Point3<f64> {
    let sum = vertices
        .iter()
        .fold(Vector3::zeros(), |acc, v| acc + v.coords);
    Point3::from(sum / vertices.len() as f64)
}
