use approx::assert_relative_eq;
use constraint_stabilization::internals::contact::contact_row::*;
use constraint_stabilization::internals::rows::BodyState;
use nalgebra::UnitQuaternion;
use nalgebra::{Point3, Vector3, Vector6};

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
