//! The linearized non-penetration constraint of one contact point.
//!
//! Two bodies A and B touch or overlap at world points `p_a` (on A) and
//! `p_b` (on B) with unit normal `n` pointing from B towards A. The
//! constraint and its Jacobian (docs/design.md section 3) are
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

use crate::rows::{ConstraintRow, RowFriction, RowKind};

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
        kind: RowKind::Inequality,
        phi: normal.dot(&(p_a - p_b)),
        blocks,
        friction: None,
    }
}

/// The row of [`contact_row`] with Coulomb friction `mu` (`mu > 0`): the
/// Jacobians of the relative displacement at the contact along the two
/// tangents of [`tangent_basis`], by the same formula with `t` for `n`
/// (`d/dq (t . (p_a - p_b))` for points carried by the bodies).
pub fn contact_row_with_friction(
    p_a: &Point3<f64>,
    p_b: &Point3<f64>,
    normal: &Vector3<f64>,
    side_a: ContactSide,
    side_b: ContactSide,
    mu: f64,
) -> ConstraintRow {
    let mut row = contact_row(p_a, p_b, normal, side_a, side_b);
    let [t1, t2] = tangent_basis(normal);
    let tangent = |t: &Vector3<f64>| contact_row(p_a, p_b, t, side_a, side_b).blocks;
    row.friction = Some(RowFriction {
        mu,
        tangents: [tangent(&t1), tangent(&t2)],
    });
    row
}

/// Two unit tangents `t_1, t_2` with `(t_1, t_2, n)` right-handed and
/// orthonormal; `t_1` is `n x e` for the world axis `e` least aligned with
/// `n` (a deterministic choice, far from degenerate).
pub fn tangent_basis(normal: &Vector3<f64>) -> [Vector3<f64>; 2] {
    let abs = normal.abs();
    let axis = if abs.x <= abs.y && abs.x <= abs.z {
        Vector3::x()
    } else if abs.y <= abs.z {
        Vector3::y()
    } else {
        Vector3::z()
    };
    let t1 = normal.cross(&axis).normalize();
    let t2 = normal.cross(&t1);
    [t1, t2]
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
    use crate::rows::BodyState;
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

    /// Size of the finite-difference motion (length units and radians).
    const FD_STEP: f64 = 1e-6;
    /// Allowed disagreement between the first-order prediction and the
    /// moved geometry, relative to the change of `phi`: the neglected term
    /// is second order, about `FD_STEP |r| / |r|` of the change.
    const FD_REL_TOL: f64 = 1e-4;

    /// Body B's block, in a row that has both sides: a small motion of B
    /// (translation and rotation, point `p_b` carried rigidly, normal fixed)
    /// changes `phi = n . (p_a - p_b)` as the block predicts. Moving B along
    /// `n` closes the gap: the linear part is `-n`, and the angular part is
    /// `-(r_b x n)`.
    #[test]
    fn body_b_block_matches_finite_differences() {
        let com_a = Point3::new(0.3, -0.2, 1.0);
        let com_b = Point3::new(-0.4, 0.7, -0.6);
        let p_a = Point3::new(1.0, 0.5, 0.1);
        let p_b = Point3::new(0.9, 0.6, 0.4);
        let normal = Vector3::new(1.0, -2.0, 2.0) / 3.0;
        let row = contact_row(&p_a, &p_b, &normal, Some((0, com_a)), Some((1, com_b)));
        assert_eq!(row.blocks.len(), 2);
        assert_eq!(row.blocks[1].0, 1);
        let block_b = row.blocks[1].1;
        let r_b = p_b - com_b;
        let expected = jacobian_block(&normal, &r_b) * -1.0;
        assert_relative_eq!(block_b, expected, epsilon = 1e-15);
        assert_relative_eq!(block_b.fixed_rows::<3>(0).into_owned(), -normal);

        let state_b = BodyState {
            position: com_b,
            rotation: UnitQuaternion::identity(),
        };
        let motions = [
            (Vector3::new(1.0, 0.0, 0.0), Vector3::zeros()),
            (normal, Vector3::zeros()),
            (Vector3::zeros(), Vector3::new(0.0, 0.0, 1.0)),
            (Vector3::new(0.3, -0.5, 0.2), Vector3::new(-0.7, 0.4, 0.6)),
        ];
        for (dx_dir, dtheta_dir) in motions {
            let (dx, dtheta) = (dx_dir * FD_STEP, dtheta_dir * FD_STEP);
            let moved = state_b.moved(&dx, &dtheta, 1.0);
            let p_b_moved = moved.position + moved.rotation * (p_b - com_b);
            let change = normal.dot(&(p_a - p_b_moved)) - row.phi;
            let mut dq_b = Vector6::zeros();
            dq_b.fixed_rows_mut::<3>(0).copy_from(&dx);
            dq_b.fixed_rows_mut::<3>(3).copy_from(&dtheta);
            let predicted = block_b.dot(&dq_b);
            assert!(
                (change - predicted).abs() <= FD_REL_TOL * change.abs(),
                "motion {dx_dir:?} {dtheta_dir:?}: phi changed by {change:e}, row predicts {predicted:e}"
            );
        }
        // Moving B along n (towards A) closes the gap.
        let moved = state_b.moved(&(normal * FD_STEP), &Vector3::zeros(), 1.0);
        let p_b_moved = moved.position + (p_b - com_b);
        assert!(normal.dot(&(p_a - p_b_moved)) < row.phi);
    }
}
