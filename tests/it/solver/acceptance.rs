//! The acceptance of an island's answer (`ProjectionResiduals::acceptance`:
//! feasibility of the linearized rows and the duality gap of the QP,
//! measured on `dq`): redundant contacts with non-unique multipliers are
//! accepted when `dq` is right, a wrong `dq` is rejected.

use crate::support::solver_oracle::{constraint_values, metric_norm};
use constraint_stabilization::solver::residuals::projection_residuals;
use constraint_stabilization::solver::{
    BodyMetric, JacobianRow, ProjectionQp, ProjectionSolution, SolverChoice, SolverError,
    SolverSettings, solve_projection,
};
use dev_support::solver::{StackSpec, random_stacks};
use nalgebra::{DVector, Matrix3, Vector3, Vector6};

/// The default acceptance tolerance.
fn tol() -> f64 {
    SolverSettings::default().tol_residual
}

/// A contact row of a vertex at `r` (from the centre of mass) on the
/// ground, normal +z: `J = [n, r x n]`.
fn ground_row(r: Vector3<f64>) -> JacobianRow {
    let n = Vector3::z();
    let rn = r.cross(&n);
    JacobianRow {
        blocks: vec![(0, Vector6::new(n.x, n.y, n.z, rn.x, rn.y, rn.z))],
    }
}

/// A unit box (mass 2, half extent 0.5) resting face-down, sunk by `depth`:
/// four coplanar corner rows, each listed `copies` times (duplicated rows,
/// as two manifolds of one face contact give).
fn box_face_down(depth: f64, copies: usize) -> ProjectionQp {
    let h = 0.5;
    let mass = 2.0;
    let inertia = Matrix3::identity() * (mass * (2.0 * h) * (2.0 * h) / 6.0);
    let mut rows = Vec::new();
    for _ in 0..copies {
        for (sx, sy) in [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)] {
            rows.push(ground_row(Vector3::new(sx * h, sy * h, -h)));
        }
    }
    let n = rows.len();
    ProjectionQp {
        bodies: vec![BodyMetric {
            mass,
            inertia_world: inertia,
        }],
        rows,
        phi: vec![-depth; n],
        target: vec![1e-6; n],
        ..Default::default()
    }
}

/// The pure lift of [`box_face_down`]: `dz = depth + target`.
fn lift(depth: f64) -> DVector<f64> {
    DVector::from_vec(vec![0.0, 0.0, depth + 1e-6, 0.0, 0.0, 0.0])
}

fn solve_with(qp: &ProjectionQp, choice: SolverChoice) -> Result<ProjectionSolution, SolverError> {
    let settings = SolverSettings {
        choice,
        ..SolverSettings::default()
    };
    solve_projection(qp, &settings)
}

fn acceptance(qp: &ProjectionQp, dq: &DVector<f64>, lambda: &DVector<f64>) -> f64 {
    let metric = qp.validate().expect("valid problem");
    projection_residuals(qp, &metric, dq, lambda).acceptance()
}

/// Multipliers that support the lift: total force `m dz` on the ground
/// rows, spread by `weights` (any nonnegative spread with zero moment is
/// optimal: `lambda` is not unique).
fn spread(qp: &ProjectionQp, dz: f64, weights: &[f64]) -> DVector<f64> {
    let total: f64 = weights.iter().sum();
    let force = qp.bodies[0].mass * dz;
    DVector::from_iterator(weights.len(), weights.iter().map(|w| force * w / total))
}

#[test]
fn box_resting_face_down_with_duplicated_rows_any_optimal_multipliers_accepted() {
    let depth = 1e-3;
    let qp = box_face_down(depth, 3);
    let dq = lift(depth);
    let dz = dq[2];
    // Uniform, all on the first copy, and a zero-moment spread over two
    // diagonal corners (rows 0 and 2) of the second copy: all optimal.
    let mut first_copy = vec![0.0; 12];
    first_copy[..4].fill(1.0);
    let mut diagonal = vec![0.0; 12];
    diagonal[4] = 1.0;
    diagonal[6] = 1.0;
    for weights in [vec![1.0; 12], first_copy, diagonal] {
        let lambda = spread(&qp, dz, &weights);
        let a = acceptance(&qp, &dq, &lambda);
        assert!(a <= tol(), "weights {weights:?}: acceptance {a:e}");
    }
}

#[test]
fn box_resting_face_down_every_solver_gives_the_lift() {
    let depth = 1e-3;
    let qp = box_face_down(depth, 2);
    for choice in SolverChoice::ALL {
        let sol = solve_with(&qp, choice).expect("solved");
        let error = metric_norm(&qp, &(&sol.dq - lift(depth)));
        let size = metric_norm(&qp, &lift(depth));
        assert!(
            error <= 1e-3 * size,
            "{choice:?}: dq {} vs the lift, error {error:e}",
            sol.dq
        );
        assert!(sol.residuals.acceptance() <= tol(), "{choice:?}");
    }
}

#[test]
fn wrong_dq_rejected_short_long_or_violating() {
    let depth = 1e-3;
    let qp = box_face_down(depth, 2);
    let dq = lift(depth);
    let lambda = spread(&qp, dq[2], &[1.0; 8]);
    // Short of the target: infeasible by 10% of the depth.
    let short = &dq * 0.9;
    assert!(acceptance(&qp, &short, &lambda) > 1e-2);
    // Past it: feasible but 10% longer than the minimal correction.
    let long = &dq * 1.1;
    assert!(acceptance(&qp, &long, &lambda) > 1e-3);
    // A tilt that leaves one corner below its target.
    let mut tilted = dq.clone();
    tilted[3] = 1e-3;
    assert!(acceptance(&qp, &tilted, &lambda) > 1e-2);
    // Right dq, certified by multipliers pushing the wrong way (a moment):
    // the gap measures the multipliers too, so this is rejected as well.
    let mut uneven = vec![0.0; 8];
    uneven[0] = 1.0;
    let wrong_lambda = spread(&qp, dq[2], &uneven);
    assert!(acceptance(&qp, &dq, &wrong_lambda) > tol());
}

/// Redundant face contacts in stacks (four coplanar rows per face, singular
/// `A`), from 40 to 800 rows: clarabel's answer is feasible and within the
/// duality gap, and `dq` agrees with Lemke's (a vertex solution).
#[test]
fn stacks_with_redundant_face_contacts_accepted_by_clarabel() {
    for (rows, seed) in [(40, 1), (200, 2), (500, 3), (800, 4)] {
        let qp = random_stacks(&StackSpec::new(rows, seed));
        let clarabel = solve_with(&qp, SolverChoice::Clarabel).expect("clarabel or a fallback");
        assert!(
            clarabel.fallbacks.is_empty(),
            "{rows} rows: {:?}",
            clarabel.fallbacks
        );
        let w = constraint_values(&qp, &clarabel.dq);
        let l = qp.b().amax();
        assert!(w.min() >= -tol() * l, "{rows} rows: w {}", w.min());
        let lemke = solve_with(&qp, SolverChoice::Lemke).expect("lemke");
        let difference = metric_norm(&qp, &(&clarabel.dq - &lemke.dq));
        let size = metric_norm(&qp, &lemke.dq);
        // The duality gap bounds the error by sqrt(2 gap) in the M-norm.
        assert!(
            difference <= 2.0 * tol().sqrt() * size,
            "{rows} rows: |dq_clarabel - dq_lemke|_M = {difference:e} of {size:e}"
        );
    }
}

/// Masses over eight decades, lengths of 1e-4, near contacts far from
/// penetration (`phi` up to 100 times the depth): a badly conditioned
/// problem. Every solver's answer passes the acceptance and agrees on `dq`.
#[test]
fn badly_conditioned_stacks_accepted() {
    let spec = StackSpec {
        rows: 120,
        length_scale: 1e-4,
        mass_scale: 1.0,
        mass_decades: 8.0,
        seed: 7,
    };
    let qp = random_stacks(&spec);
    let mut answers = Vec::new();
    for choice in [
        SolverChoice::Clarabel,
        SolverChoice::ClarabelDual,
        SolverChoice::Lemke,
    ] {
        let sol = solve_with(&qp, choice).expect("solved");
        assert!(sol.residuals.acceptance() <= tol(), "{choice:?}");
        answers.push(sol.dq);
    }
    let size = metric_norm(&qp, &answers[2]);
    for dq in &answers[..2] {
        let difference = metric_norm(&qp, &(dq - &answers[2]));
        assert!(difference <= 2.0 * tol().sqrt() * size, "{difference:e}");
    }
}

/// Above `auto_lemke_max_rows` rows the fallbacks are size-aware: the
/// dual active-set method (`Auto`'s first choice for one body), the
/// interior point (in its place from `auto_interior_point_min_rows` rows),
/// clarabel (sparse), then PGS (bounded sweeps), dense Lemke last. A body
/// pushed both ways by `dz >= 1` and `-dz >= 1`, plus separated rows up to
/// the size: infeasible, so every solver is tried and listed in order.
#[test]
fn hundreds_of_rows_try_dense_lemke_last() {
    let mut qp = box_face_down(0.0, 1);
    let size = SolverSettings::default().auto_lemke_max_rows + 40;
    let up = ground_row(Vector3::zeros());
    let mut down = up.clone();
    down.blocks[0].1 = -down.blocks[0].1;
    qp.rows = vec![up.clone(), down];
    qp.phi = vec![-1.0, -1.0];
    qp.target = vec![0.0, 0.0];
    while qp.rows.len() < size {
        qp.rows.push(up.clone());
        qp.phi.push(1.0);
        qp.target.push(0.0);
    }
    let Err(SolverError::AllSolversFailed(fallbacks)) =
        solve_projection(&qp, &SolverSettings::default())
    else {
        panic!("an infeasible problem must fail");
    };
    let order: Vec<_> = fallbacks.iter().map(|f| f.solver).collect();
    use constraint_stabilization::solver::SolverKind;
    assert_eq!(
        order,
        [
            SolverKind::DualActiveSet,
            SolverKind::InteriorPoint,
            SolverKind::Clarabel,
            SolverKind::Pgs,
            SolverKind::Lemke
        ]
    );
}
