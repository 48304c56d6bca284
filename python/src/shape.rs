//! `Shape`: a convex shape (or a compound of them) in its own shape frame,
//! as the library's [`constraint_stabilization::Shape`]. Built by static
//! constructors; checked by the library when a body is added.

use constraint_stabilization::{Shape as LibraryShape, ShapePart};
use nalgebra::{Point3, Vector3};
use numpy::PyReadonlyArray2;
use pyo3::prelude::*;

use crate::errors::input_error;
use crate::poses::{pose_rows, xyzw_of_row};

/// A shape in its own frame (the frame the pose of its body places).
#[pyclass(module = "constraint_stabilization._native", frozen)]
#[derive(Clone)]
pub struct Shape {
    pub shape: LibraryShape,
}

/// A length vector of three components.
fn vector3(values: [f64; 3]) -> Vector3<f64> {
    Vector3::new(values[0], values[1], values[2])
}

/// The rows of a `(k, 3)` array as points.
fn points(vertices: &PyReadonlyArray2<'_, f64>) -> PyResult<Vec<Point3<f64>>> {
    let array = vertices.as_array();
    if array.ncols() != 3 {
        return Err(input_error(format!(
            "vertices must have shape (k, 3), got {:?}",
            array.shape()
        )));
    }
    Ok(array
        .rows()
        .into_iter()
        .map(|row| Point3::new(row[0], row[1], row[2]))
        .collect())
}

#[pymethods]
impl Shape {
    /// A box `[-h, h]` about the frame's origin.
    #[staticmethod]
    fn cuboid(half_extents: [f64; 3]) -> Self {
        Shape {
            shape: LibraryShape::Cuboid {
                half_extents: vector3(half_extents),
            },
        }
    }

    /// The convex hull of `(k, 3)` points given in the shape frame.
    #[staticmethod]
    fn hull(vertices: PyReadonlyArray2<'_, f64>) -> PyResult<Self> {
        Ok(Shape {
            shape: LibraryShape::ConvexHull {
                points: points(&vertices)?,
            },
        })
    }

    /// A ball about the frame's origin.
    #[staticmethod]
    fn sphere(radius: f64) -> Self {
        Shape {
            shape: LibraryShape::Sphere { radius },
        }
    }

    /// The segment from `-half_height z` to `+half_height z` grown by
    /// `radius`.
    #[staticmethod]
    fn capsule(radius: f64, half_height: f64) -> Self {
        Shape {
            shape: LibraryShape::Capsule {
                half_height,
                radius,
            },
        }
    }

    /// A solid cylinder along `z` about the frame's origin.
    #[staticmethod]
    fn cylinder(radius: f64, half_height: f64) -> Self {
        Shape {
            shape: LibraryShape::Cylinder {
                half_height,
                radius,
            },
        }
    }

    /// A solid cone along `z`, base at `-half_height`, apex at
    /// `+half_height`.
    #[staticmethod]
    fn cone(radius: f64, half_height: f64) -> Self {
        Shape {
            shape: LibraryShape::Cone {
                half_height,
                radius,
            },
        }
    }

    /// A box grown by `radius` (outer half extents `h + radius`).
    #[staticmethod]
    fn round_cuboid(half_extents: [f64; 3], radius: f64) -> Self {
        Shape {
            shape: LibraryShape::RoundCuboid {
                half_extents: vector3(half_extents),
                radius,
            },
        }
    }

    /// The convex hull of `(k, 3)` points grown by `radius`.
    #[staticmethod]
    fn round_hull(vertices: PyReadonlyArray2<'_, f64>, radius: f64) -> PyResult<Self> {
        Ok(Shape {
            shape: LibraryShape::RoundConvexHull {
                points: points(&vertices)?,
                radius,
            },
        })
    }

    /// Several shapes moving as one body: part `i` placed in the
    /// compound's frame by row `i` of `poses_xyzw` (`(k, 7)`, scalar-last
    /// quaternions).
    #[staticmethod]
    fn compound_xyzw(
        parts: Vec<PyRef<'_, Shape>>,
        poses_xyzw: PyReadonlyArray2<'_, f64>,
    ) -> PyResult<Self> {
        let rows = pose_rows(&poses_xyzw, parts.len())?;
        let parts = parts
            .into_iter()
            .zip(rows.rows())
            .map(|(part, row)| ShapePart {
                shape: part.shape.clone(),
                translation: Vector3::new(row[0], row[1], row[2]),
                rotation_xyzw: xyzw_of_row(&row),
            })
            .collect();
        Ok(Shape {
            shape: LibraryShape::Compound { parts },
        })
    }

    /// The kind: `cuboid`, `hull`, `sphere`, `capsule`, `cylinder`,
    /// `cone`, `round_cuboid`, `round_hull` or `compound`.
    #[getter]
    fn kind(&self) -> &'static str {
        match &self.shape {
            LibraryShape::Cuboid { .. } => "cuboid",
            LibraryShape::ConvexHull { .. } => "hull",
            LibraryShape::Sphere { .. } => "sphere",
            LibraryShape::Capsule { .. } => "capsule",
            LibraryShape::Cylinder { .. } => "cylinder",
            LibraryShape::Cone { .. } => "cone",
            LibraryShape::RoundCuboid { .. } => "round_cuboid",
            LibraryShape::RoundConvexHull { .. } => "round_hull",
            LibraryShape::Compound { .. } => "compound",
        }
    }

    fn __repr__(&self) -> String {
        format!("Shape.{}(...)", self.kind())
    }
}
