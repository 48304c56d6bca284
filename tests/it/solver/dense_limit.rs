//! `SolverSettings::dense_max_rows`: above it neither Lemke nor PGS runs,
//! named or as a fallback; clarabel answers instead.

use constraint_stabilization::solver::{
    SolverChoice, SolverKind, SolverSettings, solve_projection,
};
use dev_support::solver::{StackSpec, random_stacks};

#[test]
fn dense_solvers_never_run_above_their_row_limit() {
    let qp = random_stacks(&StackSpec::new(40, 2));
    let limit = qp.num_rows() - 1;
    for (choice, kind) in [
        (SolverChoice::Lemke, SolverKind::Lemke),
        (SolverChoice::Pgs, SolverKind::Pgs),
    ] {
        let settings = SolverSettings {
            choice,
            dense_max_rows: limit,
            ..SolverSettings::default()
        };
        let solution = solve_projection(&qp, &settings).unwrap();
        assert_eq!(solution.solver, SolverKind::Clarabel, "{choice:?}");
        assert!(solution.fallbacks.is_empty(), "{choice:?}");
        // Within the limit the named solver runs (PGS may then stop at its
        // sweep limit and fall back).
        let within = SolverSettings {
            dense_max_rows: qp.num_rows(),
            ..settings
        };
        let solution = solve_projection(&qp, &within).unwrap();
        let ran = solution.solver == kind || solution.fallbacks.iter().any(|f| f.solver == kind);
        assert!(ran, "{choice:?} within the limit");
    }
}
