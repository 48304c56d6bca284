//! The calls: one layout (`stabilize_xyzw`) and a batch of layouts of one
//! scene on a thread pool (`stabilize_batch_xyzw`), both with the GIL
//! released while the library works.
//!
//! Each layout is solved on its own copy of the scene by its own fresh
//! `Stabilizer` (no warm start carried between layouts), by the same
//! function in both calls: a layout's result does not depend on the batch
//! it is in nor on the number of threads (the library's islands are merged
//! in a fixed order whatever the threads), so the batch equals the
//! sequential calls bit for bit.

use std::panic::{AssertUnwindSafe, catch_unwind};

use constraint_stabilization::{Error, Report, Scene as LibraryScene, Settings, Stabilizer};
use numpy::ndarray::{Array2, Array3, ArrayView2, Axis};
use numpy::{IntoPyArray, PyArray2, PyArray3, PyReadonlyArray2, PyReadonlyArray3};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;

use crate::errors::{input_error, library_error, package_error, panic_message};
use crate::poses::{check_pose_shape, poses_of, set_poses};
use crate::report::report_dict;
use crate::scene::Scene;
use crate::settings::settings_from_kwargs;

/// Why a layout has no result.
enum Failure {
    /// The library returned an error (invalid input).
    Library(Error),
    /// The library panicked (a bug), with the panic's message.
    Panic(String),
}

impl Failure {
    fn into_py(self, context: &str) -> PyErr {
        match self {
            Failure::Library(error) => {
                if context.is_empty() {
                    library_error(error)
                } else {
                    let err = library_error(error);
                    Python::attach(|py| {
                        let message = format!("{context}: {}", err.value(py));
                        PyErr::from_type(err.get_type(py), message)
                    })
                }
            }
            Failure::Panic(message) => package_error(
                "InternalError",
                format!("{context} internal error (a panic): {message}"),
            ),
        }
    }
}

/// One layout: a copy of `scene` at the poses `rows`, stabilized by a
/// fresh stabilizer; the corrected poses and the report.
fn solve_layout(
    scene: &LibraryScene,
    rows: ArrayView2<'_, f64>,
    settings: &Settings,
) -> Result<(Array2<f64>, Report), Failure> {
    let run = || -> Result<(Array2<f64>, Report), Error> {
        let mut layout = scene.clone();
        set_poses(&mut layout, &rows)?;
        let mut stabilizer = Stabilizer::new(settings.clone())?;
        let report = stabilizer.stabilize(&mut layout)?;
        Ok((poses_of(&layout), report))
    };
    match catch_unwind(AssertUnwindSafe(run)) {
        Ok(result) => result.map_err(Failure::Library),
        Err(payload) => Err(Failure::Panic(panic_message(&payload))),
    }
}

/// Stabilizes one layout: `(n, 7)` poses (scalar-last quaternions) in,
/// the corrected poses and the report (a `dict`) out.
#[pyfunction]
#[pyo3(signature = (scene, poses_xyzw, **settings))]
pub fn stabilize_xyzw<'py>(
    py: Python<'py>,
    scene: &Scene,
    poses_xyzw: PyReadonlyArray2<'py, f64>,
    settings: Option<&Bound<'py, PyDict>>,
) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyDict>)> {
    let settings = settings_from_kwargs(settings)?;
    let rows = poses_xyzw.as_array();
    check_pose_shape(rows.shape(), scene.scene.len())?;
    let library_scene = &scene.scene;
    let result = py.detach(|| solve_layout(library_scene, rows, &settings));
    let (poses, report) = result.map_err(|failure| failure.into_py(""))?;
    Ok((poses.into_pyarray(py), report_dict(py, &report)?))
}

/// Stabilizes `B` layouts of one scene, `(B, n, 7)`, on `threads` threads
/// (rayon's default, one per core, if `None`). Returns the corrected poses
/// and a `dict` of per-layout lists (`status`, `converged`, `passes`,
/// `depth_before`, `depth_after`, `tolerance`, `bodies_moved`, `seconds`).
/// On an invalid layout the error of the lowest such layout is raised,
/// naming it.
#[pyfunction]
#[pyo3(signature = (scene, poses_xyzw, threads=None, **settings))]
pub fn stabilize_batch_xyzw<'py>(
    py: Python<'py>,
    scene: &Scene,
    poses_xyzw: PyReadonlyArray3<'py, f64>,
    threads: Option<usize>,
    settings: Option<&Bound<'py, PyDict>>,
) -> PyResult<(Bound<'py, PyArray3<f64>>, Bound<'py, PyDict>)> {
    let settings = settings_from_kwargs(settings)?;
    let layouts = poses_xyzw.as_array();
    let shape = layouts.shape();
    check_pose_shape(&shape[1..], scene.scene.len())?;
    if threads == Some(0) {
        return Err(input_error("threads must be at least 1".to_owned()));
    }
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(threads) = threads {
        builder = builder.num_threads(threads);
    }
    let pool = builder
        .build()
        .map_err(|e| package_error("StabilizationError", format!("no thread pool: {e}")))?;
    let library_scene = &scene.scene;
    let results: Vec<Result<(Array2<f64>, Report), Failure>> = py.detach(|| {
        pool.install(|| {
            let views: Vec<ArrayView2<'_, f64>> = layouts.outer_iter().collect();
            views
                .into_par_iter()
                .map(|rows| solve_layout(library_scene, rows, &settings))
                .collect()
        })
    });
    let mut poses = Array3::zeros(layouts.raw_dim());
    let mut reports = Vec::with_capacity(results.len());
    for (index, (result, mut slot)) in results
        .into_iter()
        .zip(poses.axis_iter_mut(Axis(0)))
        .enumerate()
    {
        let (layout_poses, report) =
            result.map_err(|failure| failure.into_py(&format!("layout {index}")))?;
        slot.assign(&layout_poses);
        reports.push(report);
    }
    let d = PyDict::new(py);
    let column = |f: &dyn Fn(&Report) -> f64| reports.iter().map(f).collect::<Vec<f64>>();
    d.set_item(
        "status",
        reports.iter().map(|r| r.status.name()).collect::<Vec<_>>(),
    )?;
    d.set_item(
        "converged",
        reports
            .iter()
            .map(|r| r.status.is_resolved())
            .collect::<Vec<_>>(),
    )?;
    d.set_item(
        "passes",
        reports.iter().map(|r| r.passes).collect::<Vec<_>>(),
    )?;
    d.set_item(
        "bodies_moved",
        reports.iter().map(|r| r.bodies_moved).collect::<Vec<_>>(),
    )?;
    d.set_item("depth_before", column(&|r| r.depth_before))?;
    d.set_item("depth_after", column(&|r| r.depth_after))?;
    d.set_item("tolerance", column(&|r| r.tolerance))?;
    d.set_item("seconds", column(&|r| r.times.total))?;
    Ok((poses.into_pyarray(py), d))
}
