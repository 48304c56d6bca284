//! The linearized non-penetration constraint of one contact point.
//!
//! Two bodies A and B touch or overlap at world points `p_a` (on A) and
//! `p_b` (on B) with unit normal `n` pointing from B towards A. The
//! constraint and its Jacobian (DESIGN.md section 3) are
//!
//! ```text
//! phi = n . (p_a - p_b)                                  (negative = penetration)
//! J   = [ n^T, (r_a x n)^T | -n^T, -(r_b x n)^T ],    r_a = p_a - x_a,  r_b = p_b - x_b
//! ```
//!
//! because a rotation `dtheta` moves a point at `r` by `dtheta x r`, and
//! `n . (dtheta x r) = dtheta . (r x n)`. The rotation of `n` itself is a
//! second-order term, left to the line search and the next pass.
//! For a vertex `p` of A below a face of B, `p_b` is the projection of `p` on
//! the face plane; `(p_b - x_b) x n = (p - x_b) x n`, so the row is the same
//! as with `r_b = p - x_b`. Fixed bodies contribute no block.

use nalgebra::{Point3, Vector3, Vector6};

use super::ConstraintRow;

/// A body's side of a contact: its index in the configuration and its
/// centre of mass, or `None` for a fixed body.
pub type ContactSide = Option<(usize, Point3<f64>)>;

/// The constraint row of a contact between `p_a` on A and `p_b` on B with
/// normal `normal` (unit, from B towards A).
pub fn contact_row(
    p_a: &Point3<f64>,
    p_b: &Point3<f64>,
    normal: &Vector3<f64>,
    side_a: ContactSide,
    side_b: ContactSide,
) -> ConstraintRow {
    let mut blocks = Vec::with_capacity(2);
    if let Some((index, com)) = side_a {
        blocks.push((index, jacobian_block(normal, &(p_a - com))));
    }
    if let Some((index, com)) = side_b {
        blocks.push((index, -jacobian_block(normal, &(p_b - com))));
    }
    ConstraintRow {
        phi: normal.dot(&(p_a - p_b)),
        blocks,
    }
}

/// `[n; r x n]`.
fn jacobian_block(normal: &Vector3<f64>, arm: &Vector3<f64>) -> Vector6<f64> {
    let angular = arm.cross(normal);
    Vector6::new(
        normal.x, normal.y, normal.z, angular.x, angular.y, angular.z,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::projector::BodyState;
    use approx::assert_relative_eq;
    use nalgebra::UnitQuaternion;

    /// The row predicts the first-order change of `phi` under a small motion
    /// of body A (finite differences on the rigidly moved point).
    #[test]
    fn jacobian_matches_finite_differences() {
        let com_a = Point3::new(0.3, -0.2, 1.0);
        let p_a = Point3::new(1.0, 0.5, 0.1);
        let p_b = Point3::new(1.0, 0.5, 0.4);
        let normal = Vector3::new(0.0, 0.0, 1.0);
        let row = contact_row(&p_a, &p_b, &normal, Some((0, com_a)), None);
        let dx = Vector3::new(1e-7, -2e-7, 3e-7);
        let dtheta = Vector3::new(-2e-7, 1e-7, 4e-7);
        let state = BodyState {
            position: com_a,
            rotation: UnitQuaternion::identity(),
        };
        let moved = state.moved(&dx, &dtheta, 1.0);
        let p_a_moved = moved.position + moved.rotation * (p_a - com_a);
        let phi_moved = normal.dot(&(p_a_moved - p_b));
        let mut dq = Vector6::zeros();
        dq.fixed_rows_mut::<3>(0).copy_from(&dx);
        dq.fixed_rows_mut::<3>(3).copy_from(&dtheta);
        let predicted = row.phi + row.blocks[0].1.dot(&dq);
        assert_relative_eq!(phi_moved, predicted, epsilon = 1e-12);
        assert_relative_eq!(row.phi, -0.3, epsilon = 1e-15);
    }
}
