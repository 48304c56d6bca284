//! `Scene`: the library's [`constraint_stabilization::Scene`] as a Python
//! class. It holds the bodies (shape, mass or fixed, friction, name); the
//! poses are given to each call, so one scene serves every layout of a
//! batch.

use constraint_stabilization::error::SceneError;
use constraint_stabilization::stabilizer::scene_scale;
use constraint_stabilization::{Body, BodyDesc, Error, MassSpec, Scene as LibraryScene};
use nalgebra::{Matrix3, Vector3};
use numpy::PyReadonlyArray2;
use pyo3::prelude::*;

use crate::errors::{guarded, input_error, library_error};
use crate::shape::Shape;

/// The bodies of a scene, in index order (the rows of a pose array).
#[pyclass(module = "constraint_stabilization._native")]
#[derive(Clone, Default)]
pub struct Scene {
    pub scene: LibraryScene,
}

/// The mass specification of `add_body`'s keywords: exactly one of a
/// mass, a density or `fixed`; none means unit density.
fn mass_spec(mass: Option<f64>, density: Option<f64>, fixed: bool) -> PyResult<MassSpec> {
    match (mass, density, fixed) {
        (None, None, true) => Ok(MassSpec::Fixed),
        (Some(m), None, false) => Ok(MassSpec::Mass(m)),
        (None, Some(rho), false) => Ok(MassSpec::Density(rho)),
        (None, None, false) => Ok(MassSpec::Density(1.0)),
        _ => Err(input_error(
            "give at most one of mass, density and fixed=True".to_owned(),
        )),
    }
}

#[pymethods]
impl Scene {
    #[new]
    fn new() -> Self {
        Scene::default()
    }

    /// Adds a body and returns its index. Placed at the identity until a
    /// call gives it a pose.
    #[pyo3(signature = (shape, *, mass=None, density=None, fixed=false, friction=None, name=None))]
    fn add_body(
        &mut self,
        shape: &Shape,
        mass: Option<f64>,
        density: Option<f64>,
        fixed: bool,
        friction: Option<f64>,
        name: Option<String>,
    ) -> PyResult<usize> {
        let mass = mass_spec(mass, density, fixed)?;
        let name = name.unwrap_or_else(|| format!("body {}", self.scene.len()));
        guarded("add_body", || {
            let desc = BodyDesc {
                name: name.clone(),
                shape: shape.shape.clone(),
                translation: Vector3::zeros(),
                rotation_xyzw: [0.0, 0.0, 0.0, 1.0],
                mass,
            };
            let in_scene = |source| {
                library_error(Error::Scene(SceneError::Body {
                    index: self.scene.len(),
                    name: name.clone(),
                    source,
                }))
            };
            let mut body = Body::new(desc).map_err(in_scene)?;
            body.set_friction(friction).map_err(in_scene)?;
            Ok(self.scene.push_body(body))
        })
    }

    /// Replaces a dynamic body's uniform-density mass properties by given
    /// ones (an engine's): `mass`, the centre of mass `com` in the body's
    /// shape frame, the inertia `inertia` (3 x 3, about the centre of mass,
    /// in the shape frame's axes).
    fn set_mass_properties(
        &mut self,
        index: usize,
        mass: f64,
        com: [f64; 3],
        inertia: PyReadonlyArray2<'_, f64>,
    ) -> PyResult<()> {
        let inertia = inertia.as_array();
        if inertia.shape() != [3, 3] {
            return Err(input_error(format!(
                "inertia must have shape (3, 3), got {:?}",
                inertia.shape()
            )));
        }
        let inertia = Matrix3::from_fn(|r, c| inertia[[r, c]]);
        guarded("set_mass_properties", || {
            let body = self
                .scene
                .body_mut(index)
                .map_err(|e| library_error(Error::Scene(e)))?;
            body.set_mass_properties(mass, Vector3::from(com), inertia)
                .map_err(|e| library_error(Error::Body(e)))
        })
    }

    fn __len__(&self) -> usize {
        self.scene.len()
    }

    /// The bodies' names, in index order.
    #[getter]
    fn names(&self) -> Vec<String> {
        self.scene
            .bodies()
            .iter()
            .map(|b| b.name().to_owned())
            .collect()
    }

    /// Whether each body is fixed, in index order.
    #[getter]
    fn fixed(&self) -> Vec<bool> {
        self.scene.fixed_flags()
    }

    /// Each body's mass (`None` for a fixed body).
    #[getter]
    fn masses(&self) -> Vec<Option<f64>> {
        self.scene
            .bodies()
            .iter()
            .map(|b| b.mass().map(|m| m.mass))
            .collect()
    }

    /// The scene's length scale `L` (circumradius of the smallest dynamic
    /// body), to which the relative tolerances refer.
    #[getter]
    fn scale(&self) -> f64 {
        scene_scale(&self.scene)
    }

    /// A copy (shapes are shared, not rebuilt).
    fn copy(&self) -> Self {
        self.clone()
    }

    fn __repr__(&self) -> String {
        let fixed = self.scene.fixed_flags().iter().filter(|f| **f).count();
        format!("Scene({} bodies, {} fixed)", self.scene.len(), fixed)
    }
}
