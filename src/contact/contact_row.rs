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
pub fn jacobian_block(normal: &Vector3<f64>, arm: &Vector3<f64>) -> Vector6<f64> {
    let angular = arm.cross(normal);
    Vector6::new(
        normal.x, normal.y, normal.z, angular.x, angular.y, angular.z,
    )
}
