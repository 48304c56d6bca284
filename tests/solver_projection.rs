//! The projection QP end to end: random contact-like stacks (redundant rows,
//! rank-deficient `A`), extreme scales, clarabel against Lemke.

mod solver_support;

use constraint_stabilization::solver::{
    CrossCheckOutcome, SolverChoice, SolverKind, SolverSettings, cross_check_projection,
    solve_projection,
};
use solver_support::{StackSpec, random_stacks};

fn settings(choice: SolverChoice) -> SolverSettings {
    SolverSettings {
        choice,
        ..SolverSettings::default()
    }
}

#[test]
fn clarabel_and_lemke_agree_on_random_stacks() {
    for rows in [2, 5, 12, 30, 60] {
        for seed in 0..3 {
            let qp = random_stacks(&StackSpec::new(rows, seed));
            let (sol, check) = cross_check_projection(&qp, &SolverSettings::default()).unwrap();
            assert_eq!(sol.solver, SolverKind::Clarabel, "{:?}", sol.fallbacks);
            let CrossCheckOutcome::Compared {
                differences,
                reference_residuals,
            } = check.outcome
            else {
                panic!("lemke failed: {check:?}");
            };
            println!(
                "rows {rows} seed {seed}: {differences:?} {:?} {reference_residuals:?}",
                sol.residuals
            );
            assert!(differences.dq_rel < 1e-8, "{differences:?}");
        }
    }
}

#[test]
fn scaled_problems_agree() {
    for (length_scale, mass_scale) in [
        (1e-8, 1.0),
        (1e8, 1.0),
        (1.0, 1e-8),
        (1.0, 1e8),
        (1e-3, 1e4),
    ] {
        let spec = StackSpec {
            length_scale,
            mass_scale,
            ..StackSpec::new(40, 7)
        };
        let qp = random_stacks(&spec);
        let clarabel = solve_projection(&qp, &settings(SolverChoice::Clarabel)).unwrap();
        let lemke = solve_projection(&qp, &settings(SolverChoice::Lemke)).unwrap();
        println!(
            "{length_scale} {mass_scale}: {:?} {:?}",
            clarabel.residuals, lemke.residuals
        );
        assert_eq!(clarabel.solver, SolverKind::Clarabel);
        assert_eq!(lemke.solver, SolverKind::Lemke);
    }
}
