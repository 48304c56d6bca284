//! Poses as `(n, 7)` rows `[x, y, z, qx, qy, qz, qw]`: read from numpy,
//! set on a scene's bodies, read back.
//!
//! A body's pose is its *user pose*: the world pose of its shape frame
//! (module docs of the library's `body`), so a body the library did not
//! move comes back bit for bit as given.

use constraint_stabilization::error::SceneError;
use constraint_stabilization::{Error, Scene};
use nalgebra::Vector3;
use numpy::PyReadonlyArray2;
use numpy::ndarray::{Array2, ArrayView1, ArrayView2};
use pyo3::prelude::*;

use crate::errors::input_error;

/// Numbers per pose row.
pub const POSE_WIDTH: usize = 7;

/// The `(n, 7)` view of `poses`, checked for its shape.
pub fn pose_rows<'a>(
    poses: &'a PyReadonlyArray2<'_, f64>,
    n: usize,
) -> PyResult<ArrayView2<'a, f64>> {
    let view = poses.as_array();
    check_pose_shape(view.shape(), n)?;
    Ok(view)
}

/// Checks that an array of shape `shape` holds `n` poses.
pub fn check_pose_shape(shape: &[usize], n: usize) -> PyResult<()> {
    if shape.len() != 2 || shape[0] != n || shape[1] != POSE_WIDTH {
        return Err(input_error(format!(
            "poses must have shape ({n}, {POSE_WIDTH}), got {shape:?}"
        )));
    }
    Ok(())
}

/// The quaternion `[qx, qy, qz, qw]` of a pose row.
pub fn xyzw_of_row(row: &ArrayView1<'_, f64>) -> [f64; 4] {
    [row[3], row[4], row[5], row[6]]
}

/// Sets every body's user pose from its row of `rows` (as many rows as
/// bodies, checked by the caller). On an invalid pose the error names the
/// body; the scene is then partly set, so callers work on a copy.
pub fn set_poses(scene: &mut Scene, rows: &ArrayView2<'_, f64>) -> Result<(), Error> {
    for (index, (body, row)) in scene.bodies_mut().iter_mut().zip(rows.rows()).enumerate() {
        let translation = Vector3::new(row[0], row[1], row[2]);
        body.set_user_pose(translation, xyzw_of_row(&row))
            .map_err(|source| SceneError::Body {
                index,
                name: body.name().to_owned(),
                source,
            })?;
    }
    Ok(())
}

/// The user poses of every body, `(n, 7)`.
pub fn poses_of(scene: &Scene) -> Array2<f64> {
    let mut poses = Array2::zeros((scene.len(), POSE_WIDTH));
    for (mut row, body) in poses.rows_mut().into_iter().zip(scene.bodies()) {
        let t = body.translation_user();
        let q = body.rotation_user_xyzw();
        for (slot, value) in row.iter_mut().zip([t.x, t.y, t.z, q[0], q[1], q[2], q[3]]) {
            *slot = value;
        }
    }
    poses
}
