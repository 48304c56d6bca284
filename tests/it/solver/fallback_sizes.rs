//! The fallback chain never runs a dense solver (Lemke, PGS, clarabel's
//! dual form) on more rows than `SolverSettings::dense_max_rows`, counting
//! the rows it would solve: a problem with friction cones is solved by them
//! on its pyramid (`K` facets per cone besides the rows), and the
//! cross-check obeys the same limit. Asserted on the report's record of
//! which solvers ran (the answering solver, the fallbacks, the
//! cross-check's reference), on problems just above a tiny limit.

use constraint_stabilization::solver::{
    BodyMetric, CrossCheckOutcome, FailureReason, FrictionCone, JacobianRow, ProjectionQp,
    SolverChoice, SolverKind, SolverSettings, solve_projection,
};
use dev_support::solver::{StackSpec, random_stacks};
use nalgebra::{Matrix3, Vector3, Vector6};

fn is_dense(kind: SolverKind) -> bool {
    matches!(
        kind,
        SolverKind::Lemke | SolverKind::Pgs | SolverKind::ClarabelDual
    )
}

fn translation_row(body: usize, n: Vector3<f64>) -> JacobianRow {
    JacobianRow {
        blocks: vec![(body, Vector6::new(n.x, n.y, n.z, 0.0, 0.0, 0.0))],
    }
}

/// `bodies` unit boxes side by side, each sunk into a fixed ground by 1 mm
/// (one row along z) and pushed sideways by a tilted row, with the
/// ground's friction cone (`mu = 0.5`): `2 * bodies` rows and `bodies`
/// cones, whose pyramid (4 facets a cone) has `6 * bodies` rows.
fn boxes_with_cones(bodies: usize) -> ProjectionQp {
    let mut qp = ProjectionQp {
        cone_facets: 4,
        ..ProjectionQp::default()
    };
    let push = Vector3::new(0.6, 0.0, -0.8);
    for k in 0..bodies {
        qp.bodies.push(BodyMetric {
            mass: 1.0 + k as f64,
            inertia_world: Matrix3::identity() * (1.0 + k as f64) / 6.0,
        });
        for (n, phi) in [(Vector3::z(), -1e-3), (push, -2e-3)] {
            qp.rows.push(translation_row(k, n));
            qp.phi.push(phi);
            qp.target.push(0.0);
        }
        qp.cones.push(FrictionCone {
            normal: translation_row(k, Vector3::z()),
            tangents: [
                translation_row(k, Vector3::x()),
                translation_row(k, Vector3::y()),
            ],
            mu: 0.5,
            phi: -1e-3,
            target: 0.0,
        });
    }
    qp
}

#[test]
fn no_dense_solver_runs_on_a_pyramid_above_the_limit_even_when_its_rows_are_below() {
    let qp = boxes_with_cones(10);
    let (rows, pyramid_rows) = (qp.num_rows(), qp.pyramid().0.num_rows());
    assert_eq!((rows, pyramid_rows), (20, 60));
    for choice in [
        SolverChoice::Lemke,
        SolverChoice::Pgs,
        SolverChoice::ClarabelDual,
    ] {
        let settings = SolverSettings {
            choice,
            dense_max_rows: rows,
            cross_check: true,
            ..SolverSettings::default()
        };
        let solution = solve_projection(&qp, &settings).expect("clarabel solves it");
        assert_eq!(solution.solver, SolverKind::Clarabel, "{choice:?}");
        assert!(
            solution.fallbacks.iter().all(|f| !is_dense(f.solver)),
            "{choice:?}: {:?}",
            solution.fallbacks
        );
        // The cross-check's Lemke on the pyramid is refused, not run.
        let check = solution.cross_check.expect("asked for");
        assert_eq!(check.reference, SolverKind::Lemke);
        assert_eq!(
            check.outcome,
            CrossCheckOutcome::ReferenceFailed(FailureReason::AboveDenseLimit {
                rows: pyramid_rows,
                limit: rows
            })
        );
    }
    // With the limit at the pyramid's rows, Lemke answers it.
    let within = SolverSettings {
        choice: SolverChoice::Lemke,
        dense_max_rows: pyramid_rows,
        ..SolverSettings::default()
    };
    let solution = solve_projection(&qp, &within).expect("Lemke solves the pyramid");
    assert_eq!(solution.solver, SolverKind::Lemke);
    assert!(solution.pyramid_of_cones);
}

#[test]
fn the_cross_check_runs_no_dense_solver_above_the_limit() {
    let qp = random_stacks(&StackSpec::new(60, 11));
    let settings = SolverSettings {
        choice: SolverChoice::Clarabel,
        dense_max_rows: qp.num_rows() - 1,
        cross_check: true,
        ..SolverSettings::default()
    };
    let solution = solve_projection(&qp, &settings).expect("clarabel solves it");
    assert_eq!(solution.solver, SolverKind::Clarabel);
    let check = solution.cross_check.expect("asked for");
    assert_eq!(
        check.outcome,
        CrossCheckOutcome::ReferenceFailed(FailureReason::AboveDenseLimit {
            rows: qp.num_rows(),
            limit: qp.num_rows() - 1
        })
    );
}
