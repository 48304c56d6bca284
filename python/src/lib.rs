//! The native half of the Python package `constraint_stabilization`
//! (imported as `constraint_stabilization._native`; the pure-Python half,
//! in `python/constraint_stabilization/`, checks inputs, handles the
//! quaternion order and holds the MuJoCo adapter).
//!
//! Everything here takes and returns poses as `(n, 7)` arrays
//! `[x, y, z, qx, qy, qz, qw]` (the library's order, scalar last); the
//! Python layer permutes a `"wxyz"` input exactly (no arithmetic), so a
//! wxyz layout and its xyzw twin reach the library bit for bit alike.
//!
//! No panic crosses into Python: every call into the library runs inside
//! [`errors::guarded`], which turns a panic into the package's
//! `InternalError`, and every library error into the exception class of its
//! family (`errors.rs`).

use pyo3::prelude::*;

mod errors;
mod poses;
mod report;
mod scene;
mod settings;
mod shape;
mod stabilize;

/// The extension module `constraint_stabilization._native`.
#[pymodule]
fn _native(module: &Bound<'_, PyModule>) -> PyResult<()> {
    module.add_class::<shape::Shape>()?;
    module.add_class::<scene::Scene>()?;
    module.add_function(wrap_pyfunction!(stabilize::stabilize_xyzw, module)?)?;
    module.add_function(wrap_pyfunction!(stabilize::stabilize_batch_xyzw, module)?)?;
    module.add_function(wrap_pyfunction!(settings::setting_names, module)?)?;
    module.add_function(wrap_pyfunction!(errors::raise_for_test, module)?)?;
    Ok(())
}
