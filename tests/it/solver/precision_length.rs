//! `SolverSettings::precision_length` (`src/solver/solve.rs`): a problem
//! that is a small part of the call's correction (a later pass) is answered
//! by the interior point to a stop target raised by
//! `(precision_length / v)^2 / 100`, at most to `PRECISION_STOP_CAP` of the
//! acceptance tolerance. The answer still passes the acceptance test, its
//! distance to the tight answer stays within what the raised target
//! certifies, it takes no more iterations, and a length no larger than the
//! problem's own violation changes nothing.

use constraint_stabilization::solver::residuals::m_norm;
use constraint_stabilization::solver::{
    PRECISION_STOP_CAP, SolverChoice, SolverKind, SolverSettings, solve_projection,
};
use dev_support::solver::{StackSpec, random_stacks};

/// The interior point alone (no fallback), with `precision_length`.
fn interior_point(precision_length: Option<f64>) -> SolverSettings {
    SolverSettings {
        choice: SolverChoice::InteriorPoint,
        fall_back: false,
        precision_length,
        ..SolverSettings::default()
    }
}

/// The largest violation `max_i max(0, -b_i)` of a problem.
fn violation(b: &[f64]) -> f64 {
    b.iter().map(|&x| (-x).max(0.0)).fold(0.0, f64::max)
}

#[test]
fn a_later_pass_is_answered_to_the_first_pass_precision() {
    let (mut tight_iterations, mut raised_iterations) = (0, 0);
    for (seed, rows) in [(1, 120), (2, 160), (3, 240), (4, 200)] {
        let qp = random_stacks(&StackSpec::new(rows, seed));
        let metric = qp.validate().expect("valid problem");
        let v = violation(qp.b().as_slice());
        assert!(v > 0.0, "seed {seed}: a violated row");
        let tight = solve_projection(&qp, &interior_point(None)).expect("solved");
        // The first pass a thousand times deeper: the target is raised to
        // its cap.
        let raised = solve_projection(&qp, &interior_point(Some(1e3 * v))).expect("solved");
        assert_eq!(raised.solver, SolverKind::InteriorPoint);
        let tolerance = SolverSettings::default().tol_residual;
        let acceptance = raised.residuals.acceptance();
        assert!(acceptance <= tolerance, "seed {seed}: {acceptance:.2e}");
        // Both answers are certified within sqrt(2 acceptance) of the
        // correction's size from the minimizer (`src/solver/residuals.rs`).
        let size = m_norm(&metric, &tight.dq);
        let distance = m_norm(&metric, &(&raised.dq - &tight.dq));
        let bound = ((2.0 * PRECISION_STOP_CAP * tolerance).sqrt()
            + (2.0 * tight.residuals.acceptance()).sqrt())
            * size;
        assert!(
            distance <= bound,
            "seed {seed}: {distance:.3e} from the tight answer, bound {bound:.3e}"
        );
        assert!(raised.iterations <= tight.iterations, "seed {seed}");
        tight_iterations += tight.iterations;
        raised_iterations += raised.iterations;
        // A length no larger than the problem's own violation: unchanged.
        let own = solve_projection(&qp, &interior_point(Some(v))).expect("solved");
        assert_eq!(own.dq.as_slice(), tight.dq.as_slice(), "seed {seed}");
        assert_eq!(own.iterations, tight.iterations, "seed {seed}");
    }
    assert!(
        raised_iterations < tight_iterations,
        "the raised target saves iterations: {raised_iterations} against {tight_iterations}"
    );
}
