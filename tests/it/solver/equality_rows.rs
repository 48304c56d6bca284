//! Equality (bilateral) rows in the projection QP
//! (`ProjectionQp::num_equalities`, the rows of joints): every solver
//! against oracles this project did not write into the library, the
//! brute-force active-set enumeration and the minimum-norm closed form of
//! `super::active_set_oracle`; redundant rows (a closed loop), inconsistent
//! rows, zero rows and validation.

use super::active_set_oracle::{brute_force_dq, minimum_norm_dq};
use crate::support::solver_oracle::{constraint_values, relative_metric_distance};
use constraint_stabilization::solver::clarabel_qp::ClarabelFailure;
use constraint_stabilization::solver::lemke::{self, LemkeSettings, LemkeStatus};
use constraint_stabilization::solver::pgs::{PgsSettings, PgsStatus};
use constraint_stabilization::solver::residuals::projection_residuals;
use constraint_stabilization::solver::{
    BodyMetric, CrossCheckOutcome, FailureReason, FrictionCone, JacobianRow, Lcp, ProjectionQp,
    ProjectionSolution, SolverChoice, SolverError, SolverKind, SolverSettings,
    cross_check_projection, solve_projection,
};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3, Vector6};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Agreement of an exact solver's `dq` with the oracle, relative in the
/// M-norm. The acceptance check certifies much less (`sqrt(1e-6)`); the
/// active-set polish and Lemke's basis re-solve reach rounding (measured:
/// at most 5e-15 over these tests).
pub(super) const DQ_TOL: f64 = 1e-10;
/// PGS stops on its natural map (1e-10 scaled), which bounds `dq` only
/// through the conditioning of the problem (measured: at most 3e-10).
const PGS_DQ_TOL: f64 = 1e-7;
/// The augmented Lagrangian's answers are certified exact (its exact
/// finish verifies the KKT conditions to 1e-9 of the correction).
const AUGMENTED_LAGRANGIAN_DQ_TOL: f64 = 1e-8;
/// Agreement of the closed forms (one row, minimum norm) with the oracle:
/// a few roundings of the data.
const CLOSED_FORM_TOL: f64 = 1e-12;
/// Equality rows hold to this fraction of `||phi - target||_inf`: the
/// default acceptance tolerance, which every answer passes.
const EQUALITY_HOLDS_TOL: f64 = 1e-6;
/// Random problems per shape in the seeded loops.
const RANDOM_PROBLEMS: u64 = 12;
/// PGS sweeps allowed on the small random problems (measured: at most
/// 531; the default 1000 is an engine budget, not a convergence bound).
const PGS_SWEEPS: usize = 20_000;

const EXACT: [SolverChoice; 3] = [
    SolverChoice::Clarabel,
    SolverChoice::ClarabelDual,
    SolverChoice::Lemke,
];

fn settings(choice: SolverChoice) -> SolverSettings {
    SolverSettings {
        choice,
        fall_back: false,
        pgs: PgsSettings {
            max_sweeps: PGS_SWEEPS,
            ..PgsSettings::default()
        },
        ..SolverSettings::default()
    }
}

fn kind_of(choice: SolverChoice) -> SolverKind {
    match choice {
        SolverChoice::Clarabel => SolverKind::Clarabel,
        SolverChoice::ClarabelDual => SolverKind::ClarabelDual,
        SolverChoice::Lemke => SolverKind::Lemke,
        SolverChoice::Pgs => SolverKind::Pgs,
        SolverChoice::AugmentedLagrangian => SolverKind::AugmentedLagrangian,
        SolverChoice::InteriorPoint => SolverKind::InteriorPoint,
        SolverChoice::DualActiveSet => SolverKind::DualActiveSet,
        SolverChoice::Auto => unreachable!("only named choices here"),
    }
}

/// Solves with `choice` alone (no fallback), checks that its own solver
/// answered, that the equality rows hold, the inequality rows' multipliers
/// are nonnegative, and that `dq` is within `tol` of `expected`.
fn assert_solves(
    qp: &ProjectionQp,
    choice: SolverChoice,
    expected: &DVector<f64>,
    tol: f64,
    context: &str,
) -> ProjectionSolution {
    let sol = solve_projection(qp, &settings(choice))
        .unwrap_or_else(|e| panic!("{context} {choice:?}: {e}"));
    if choice != SolverChoice::Auto {
        assert_eq!(sol.solver, kind_of(choice), "{context}");
    }
    let w = constraint_values(qp, &sol.dq);
    // ||phi - target||_inf: the values at dq = 0.
    let length = constraint_values(qp, &DVector::zeros(sol.dq.len()))
        .amax()
        .max(f64::MIN_POSITIVE);
    for i in 0..qp.num_equalities {
        assert!(
            w[i].abs() <= EQUALITY_HOLDS_TOL * length,
            "{context} {choice:?}: equality row {i} off by {:e}",
            w[i]
        );
    }
    for i in qp.num_equalities..qp.rows.len() {
        assert!(
            sol.lambda[i] >= 0.0,
            "{context} {choice:?}: lambda[{i}] < 0"
        );
    }
    let distance = relative_metric_distance(qp, &sol.dq, expected);
    assert!(
        distance <= tol,
        "{context} {choice:?}: dq off the oracle by {distance:e}"
    );
    sol
}

fn body(mass: f64, inertia: Matrix3<f64>) -> BodyMetric {
    BodyMetric {
        mass,
        inertia_world: inertia,
    }
}

fn row(blocks: &[(usize, [f64; 6])]) -> JacobianRow {
    JacobianRow {
        blocks: blocks
            .iter()
            .map(|(k, g)| (*k, Vector6::from_row_slice(g)))
            .collect(),
    }
}

/// A random body: log-uniform mass over a decade, an inertia
/// `m (0.1 I + 0.05 B B^T)` (symmetric positive definite).
fn random_body(rng: &mut ChaCha8Rng) -> BodyMetric {
    let mass = 10f64.powf(rng.random_range(-0.5..0.5));
    let b = Matrix3::from_fn(|_, _| rng.random_range(-1.0..1.0));
    body(
        mass,
        (Matrix3::identity() * 0.1 + b * b.transpose() * 0.05) * mass,
    )
}

/// A random row over one or two of `bodies` bodies, entries in `[-1, 1]`.
fn random_row(rng: &mut ChaCha8Rng, bodies: usize) -> JacobianRow {
    let first = rng.random_range(0..bodies);
    let mut blocks = vec![(first, Vector6::from_fn(|_, _| rng.random_range(-1.0..1.0)))];
    if bodies > 1 && rng.random_bool(0.5) {
        let second = (first + rng.random_range(1..bodies)) % bodies;
        blocks.push((second, Vector6::from_fn(|_, _| rng.random_range(-1.0..1.0))));
    }
    JacobianRow { blocks }
}

/// `equalities` equality rows (values off their target either way), then
/// `inequalities` contact-like rows (some penetrating, some open), over
/// two bodies: independent rows, well conditioned.
pub(super) fn random_mixed(seed: u64, equalities: usize, inequalities: usize) -> ProjectionQp {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let bodies = 2;
    let mut qp = ProjectionQp {
        bodies: (0..bodies).map(|_| random_body(&mut rng)).collect(),
        num_equalities: equalities,
        ..ProjectionQp::default()
    };
    for i in 0..equalities + inequalities {
        qp.rows.push(random_row(&mut rng, bodies));
        if i < equalities {
            qp.phi.push(rng.random_range(-0.05..0.05));
            qp.target.push(0.0);
        } else {
            qp.phi.push(rng.random_range(-0.05..0.03));
            qp.target.push(1e-3);
        }
    }
    qp
}

/// Random problems with equalities and inequalities: clarabel (both
/// forms), Lemke, PGS and `Auto` all give the brute-force oracle's `dq`,
/// hold the equality rows, keep inequality multipliers nonnegative; some
/// equality multiplier comes out negative (the sign is really free).
#[test]
fn random_mixed_problems_match_the_active_set_oracle() {
    let mut negative_equality_multipliers = 0;
    for (equalities, inequalities) in [(1, 4), (2, 5), (3, 6)] {
        for seed in 0..RANDOM_PROBLEMS {
            let qp = random_mixed(seed, equalities, inequalities);
            let context = format!("E={equalities} I={inequalities} seed {seed}");
            let oracle = brute_force_dq(&qp).unwrap_or_else(|| panic!("{context}: no oracle"));
            for choice in EXACT {
                let sol = assert_solves(&qp, choice, &oracle, DQ_TOL, &context);
                negative_equality_multipliers +=
                    (0..equalities).filter(|&i| sol.lambda[i] < 0.0).count();
            }
            assert_solves(&qp, SolverChoice::Pgs, &oracle, PGS_DQ_TOL, &context);
            assert_solves(
                &qp,
                SolverChoice::AugmentedLagrangian,
                &oracle,
                AUGMENTED_LAGRANGIAN_DQ_TOL,
                &context,
            );
            let auto = assert_solves(&qp, SolverChoice::Auto, &oracle, DQ_TOL, &context);
            assert_eq!(auto.solver, SolverKind::Lemke, "{context}: auto");
        }
    }
    assert!(negative_equality_multipliers > 0);
}

fn unit_body() -> BodyMetric {
    body(2.0, Matrix3::from_diagonal(&Vector3::new(0.4, 0.5, 0.6)))
}

/// One equality row, its value above and below the target: `Auto` takes
/// the closed form, whose multiplier `-b / a` has the sign of the needed
/// push (negative when the row must decrease), and every solver agrees
/// with the minimum-norm oracle.
#[test]
fn single_equality_row_closed_form_has_either_sign() {
    for b in [0.02, -0.03] {
        let qp = ProjectionQp {
            bodies: vec![unit_body()],
            rows: vec![row(&[(0, [1.0, 0.5, 0.0, 0.0, 0.3, -0.2])])],
            phi: vec![b + 0.01],
            target: vec![0.01],
            num_equalities: 1,
            ..ProjectionQp::default()
        };
        let oracle = minimum_norm_dq(&qp);
        let closed = solve_projection(&qp, &SolverSettings::default()).unwrap();
        assert_eq!(closed.solver, SolverKind::ClosedForm);
        assert_eq!(closed.lambda[0].signum(), -b.signum(), "b = {b}");
        let distance = relative_metric_distance(&qp, &closed.dq, &oracle);
        assert!(distance <= CLOSED_FORM_TOL, "b = {b}: {distance:e}");
        for choice in EXACT {
            assert_solves(&qp, choice, &oracle, DQ_TOL, &format!("b = {b}"));
        }
        assert_solves(&qp, SolverChoice::Pgs, &oracle, PGS_DQ_TOL, "one row");
    }
}

/// Equality rows only, among them a duplicated row and a row that is the
/// sum of two others (with consistent values: a closed loop lists
/// dependent rows), so `J M^-1 J^T` is singular and the multipliers are
/// not unique: every solver gives the minimum-norm closed form's `dq`.
#[test]
fn equality_only_problem_is_the_minimum_norm_correction() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for redundant in [false, true] {
        let mut qp = random_mixed(3, 4, 0);
        if redundant {
            push_redundant_rows(&mut qp, &mut rng, 0);
        }
        let oracle = minimum_norm_dq(&qp);
        let context = format!("redundant {redundant}");
        for choice in EXACT {
            assert_solves(&qp, choice, &oracle, DQ_TOL, &context);
        }
        assert_solves(&qp, SolverChoice::Pgs, &oracle, PGS_DQ_TOL, &context);
    }
}

/// Inserts, right after the equality rows, a copy of equality row `first`
/// and the sum of equality rows `first + 1` and `first + 2` (values
/// consistent, scaled by a random factor), and counts them as equalities.
pub(super) fn push_redundant_rows(qp: &mut ProjectionQp, rng: &mut ChaCha8Rng, first: usize) {
    let n = qp.num_equalities;
    let c = rng.random_range(0.5..2.0);
    let duplicate = qp.rows[first].clone();
    let (a, b) = (&qp.rows[first + 1], &qp.rows[first + 2]);
    let mut sum = a.clone();
    for (k, g) in &b.blocks {
        match sum.blocks.iter_mut().find(|(j, _)| j == k) {
            Some((_, h)) => *h += g,
            None => sum.blocks.push((*k, *g)),
        }
    }
    sum.blocks.iter_mut().for_each(|(_, g)| *g *= c);
    let sum_b =
        c * (qp.phi[first + 1] - qp.target[first + 1] + qp.phi[first + 2] - qp.target[first + 2]);
    let rows = [
        (duplicate, qp.phi[first], qp.target[first]),
        (sum, sum_b, 0.0),
    ];
    for (offset, (r, phi, target)) in rows.into_iter().enumerate() {
        qp.rows.insert(n + offset, r);
        qp.phi.insert(n + offset, phi);
        qp.target.insert(n + offset, target);
    }
    qp.num_equalities += 2;
}

/// Redundant equality rows among inequalities: the `dq` of every solver is
/// the brute-force oracle's of the problem without the redundant rows
/// (they change the multipliers, not the feasible set).
#[test]
fn redundant_equality_rows_with_inequalities_keep_dq() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for seed in 0..RANDOM_PROBLEMS {
        let independent = random_mixed(100 + seed, 3, 4);
        let oracle = brute_force_dq(&independent).expect("independent rows: an oracle");
        let mut qp = independent.clone();
        push_redundant_rows(&mut qp, &mut rng, 0);
        let context = format!("seed {seed}");
        for choice in EXACT {
            assert_solves(&qp, choice, &oracle, DQ_TOL, &context);
        }
        assert_solves(&qp, SolverChoice::Pgs, &oracle, PGS_DQ_TOL, &context);
    }
}

/// Two equality rows asking for different values of the same quantity
/// (the body's x both 0.1 and -0.1 away), with a contact row: no solver
/// returns an answer, each fails with a typed reason (Lemke's elimination
/// finds them inconsistent), and `solve_projection` returns the chain of
/// failures; no panic, no NaN.
#[test]
fn inconsistent_equalities_fail_with_a_typed_outcome() {
    let x = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    let qp = ProjectionQp {
        bodies: vec![unit_body()],
        rows: vec![
            row(&[(0, x)]),
            row(&[(0, x)]),
            row(&[(0, [0.0, 1.0, 0.0, 0.0, 0.0, 0.0])]),
        ],
        phi: vec![-0.1, 0.1, -0.01],
        target: vec![0.0, 0.0, 0.0],
        num_equalities: 2,
        ..ProjectionQp::default()
    };
    let failure_of = |choice| match solve_projection(&qp, &settings(choice)) {
        Err(SolverError::AllSolversFailed(fallbacks)) => {
            assert_eq!(fallbacks.len(), 1, "{choice:?}");
            assert_eq!(fallbacks[0].solver, kind_of(choice));
            fallbacks[0].reason.clone()
        }
        other => panic!("{choice:?}: {other:?}"),
    };
    let lemke = failure_of(SolverChoice::Lemke);
    assert!(
        matches!(lemke, FailureReason::Lemke(LemkeStatus::InconsistentEqualities { residual }) if residual > 0.1),
        "{lemke:?}"
    );
    assert!(lemke.certifies_infeasibility());
    let clarabel = failure_of(SolverChoice::Clarabel);
    assert_eq!(
        clarabel,
        FailureReason::Clarabel(ClarabelFailure::PrimalInfeasible)
    );
    let dual = failure_of(SolverChoice::ClarabelDual);
    assert_eq!(
        dual,
        FailureReason::Clarabel(ClarabelFailure::DualInfeasible)
    );
    let pgs = failure_of(SolverChoice::Pgs);
    assert!(
        matches!(pgs, FailureReason::Pgs(PgsStatus::MaxSweeps { residual }) if residual.is_finite()),
        "{pgs:?}"
    );
    match solve_projection(&qp, &SolverSettings::default()) {
        Err(SolverError::AllSolversFailed(fallbacks)) => {
            let solvers: Vec<SolverKind> = fallbacks.iter().map(|f| f.solver).collect();
            assert_eq!(
                solvers,
                [SolverKind::Lemke, SolverKind::Clarabel, SolverKind::Pgs]
            );
        }
        other => panic!("default chain: {other:?}"),
    }
}

/// The mixed LCP directly: Lemke's elimination on `A = [[1, 1], [1, 1]]`
/// with both variables free and `q = (1, -1)` (the same row asked to be
/// -1 and 1) reports the inconsistency; with `q = (1, 1)` it solves.
#[test]
fn lemke_eliminates_a_singular_free_block() {
    let m = DMatrix::from_row_slice(2, 2, &[1.0, 1.0, 1.0, 1.0]);
    let bad = Lcp::mixed(m.clone(), DVector::from_row_slice(&[1.0, -1.0]), 2).unwrap();
    let failure = lemke::solve(&bad, &LemkeSettings::default()).unwrap_err();
    assert!(
        matches!(failure.status, LemkeStatus::InconsistentEqualities { .. }),
        "{failure:?}"
    );
    let good = Lcp::mixed(m, DVector::from_row_slice(&[1.0, 1.0]), 2).unwrap();
    let sol = lemke::solve(&good, &LemkeSettings::default()).unwrap();
    assert!(sol.w.amax() <= CLOSED_FORM_TOL, "w = {}", sol.w);
}

/// An equality row that no body moves (zero Jacobian) with
/// `phi != target` is `InfeasibleRow`; with `phi == target` it is
/// harmless and the rest is solved.
#[test]
fn zero_equality_row_with_nonzero_b_is_infeasible() {
    let mut qp = ProjectionQp {
        bodies: vec![unit_body()],
        rows: vec![
            row(&[(0, [0.0; 6])]),
            row(&[(0, [0.0, 1.0, 0.0, 0.0, 0.0, 0.0])]),
        ],
        phi: vec![0.05, -0.01],
        target: vec![0.0, 0.0],
        num_equalities: 1,
        ..ProjectionQp::default()
    };
    assert_eq!(
        solve_projection(&qp, &SolverSettings::default()),
        Err(SolverError::InfeasibleRow { row: 0 })
    );
    qp.phi[0] = 0.0;
    // The contact row alone: the body is lifted by 0.01.
    let expected = DVector::from_row_slice(&[0.0, 0.01, 0.0, 0.0, 0.0, 0.0]);
    for choice in EXACT {
        assert_solves(&qp, choice, &expected, DQ_TOL, "zero row, b = 0");
    }
}

/// One row on the x translation of [`unit_body`] with value `phi` and
/// target 0, with `num_equalities` as given.
fn one_x_row(phi: f64, num_equalities: usize) -> ProjectionQp {
    ProjectionQp {
        bodies: vec![unit_body()],
        rows: vec![row(&[(0, [1.0, 0.0, 0.0, 0.0, 0.0, 0.0])])],
        phi: vec![phi],
        target: vec![0.0],
        num_equalities,
        ..ProjectionQp::default()
    }
}

/// `num_equalities` above the number of rows is rejected before any
/// solver runs; so is a mixed LCP with more free variables than rows.
#[test]
fn too_many_equalities_is_rejected() {
    let qp = one_x_row(0.0, 2);
    let expected = SolverError::TooManyEqualities {
        num_equalities: 2,
        rows: 1,
    };
    assert_eq!(
        solve_projection(&qp, &SolverSettings::default()),
        Err(expected.clone())
    );
    assert_eq!(
        Lcp::mixed(DMatrix::identity(1, 1), DVector::zeros(1), 2),
        Err(expected)
    );
}

/// `Auto` answers trivially only when every equality row already holds
/// within the acceptance feasibility measure; an equality row off by more
/// is solved even though every inequality row holds.
#[test]
fn trivial_only_when_equality_rows_hold() {
    let mut qp = ProjectionQp {
        bodies: vec![unit_body()],
        rows: vec![
            row(&[(0, [1.0, 0.0, 0.0, 0.0, 0.0, 0.0])]),
            row(&[(0, [0.0, 1.0, 0.0, 0.0, 0.0, 0.0])]),
        ],
        phi: vec![1e-9, 0.1],
        target: vec![0.0, 0.0],
        num_equalities: 1,
        ..ProjectionQp::default()
    };
    let defaults = SolverSettings::default();
    // |b_0| / L = 1e-8 <= tol_residual (1e-6).
    let trivial = solve_projection(&qp, &defaults).unwrap();
    assert_eq!(trivial.solver, SolverKind::Trivial);
    assert_eq!(trivial.dq, DVector::zeros(6));
    qp.phi[0] = 1e-3;
    let solved = solve_projection(&qp, &defaults).unwrap();
    assert_eq!(solved.solver, SolverKind::Lemke);
    assert!((solved.dq[0] + 1e-3).abs() <= CLOSED_FORM_TOL);
}

/// The pyramid of a problem with equality rows and a cone keeps the
/// equality rows first (and their count), appending the facets after all
/// rows; Lemke solves it.
#[test]
fn pyramid_keeps_equality_rows_first() {
    let central = |v: [f64; 3]| row(&[(0, [v[0], v[1], v[2], 0.0, 0.0, 0.0])]);
    let qp = ProjectionQp {
        bodies: vec![unit_body()],
        rows: vec![central([1.0, 0.0, 0.0]), central([0.0, 0.0, 1.0])],
        phi: vec![0.02, -0.01],
        target: vec![0.0, 0.0],
        cones: vec![FrictionCone {
            normal: central([0.0, 0.0, 1.0]),
            tangents: [central([1.0, 0.0, 0.0]), central([0.0, 1.0, 0.0])],
            mu: 0.5,
            phi: -0.01,
            target: 0.0,
        }],
        cone_facets: 4,
        num_equalities: 1,
    };
    let (pyramid, origins) = qp.pyramid();
    assert_eq!(pyramid.num_equalities, 1);
    assert_eq!(pyramid.rows[..2], qp.rows[..]);
    assert_eq!(origins, [0, 1, 2, 2, 2, 2]);
    let sol = solve_projection(&qp, &settings(SolverChoice::Lemke)).unwrap();
    assert!(sol.pyramid_of_cones);
    // x is brought to its target (moved by -0.02); the slide of 0.02 needs
    // a normal gap of mu 0.02 = 0.01 under the pyramid's facet
    // `w_0 + w_1 >= 0`, so z is lifted by 0.01 + 0.01.
    assert!((sol.dq[0] + 0.02).abs() <= CLOSED_FORM_TOL, "{}", sol.dq);
    assert!((sol.dq[2] - 0.02).abs() <= CLOSED_FORM_TOL, "{}", sol.dq);
}

/// The acceptance measures count an equality row both ways and leave its
/// multiplier free: the exact answer of one equality row that must
/// decrease (negative multiplier) has a zero duality gap (the certificate
/// holds with the negative multiplier, which clamping would break), and an
/// over-correction, which a `>=` row would accept, is infeasible by its
/// overshoot.
#[test]
fn acceptance_counts_equality_rows_both_ways() {
    let qp = one_x_row(0.02, 1);
    let metric = qp.validate().unwrap();
    // Mass 2: dq_x = -0.02 with lambda = M dq_x = -0.04.
    let dq = DVector::from_row_slice(&[-0.02, 0.0, 0.0, 0.0, 0.0, 0.0]);
    let lambda = DVector::from_element(1, -0.04);
    let exact = projection_residuals(&qp, &metric, &dq, &lambda);
    assert!(exact.acceptance() <= CLOSED_FORM_TOL, "{exact:?}");
    let over = DVector::from_row_slice(&[-0.03, 0.0, 0.0, 0.0, 0.0, 0.0]);
    let overshoot = projection_residuals(&qp, &metric, &over, &(lambda * 1.5));
    // |w| = 0.01 against L = 0.02.
    assert!(
        (overshoot.feasibility - 0.5).abs() <= CLOSED_FORM_TOL,
        "{overshoot:?}"
    );
}

/// The cross-check (clarabel against Lemke) of problems with equality
/// rows compares their `dq`, which agree to the exact solvers' tolerance.
#[test]
fn cross_check_compares_dq_with_equality_rows() {
    for seed in 0..RANDOM_PROBLEMS {
        let qp = random_mixed(200 + seed, 2, 5);
        let (solution, check) = cross_check_projection(&qp, &SolverSettings::default()).unwrap();
        assert_eq!(solution.solver, SolverKind::Clarabel);
        assert_eq!(check.reference, SolverKind::Lemke);
        match check.outcome {
            CrossCheckOutcome::Compared { differences, .. } => {
                assert!(differences.dq_rel <= DQ_TOL, "seed {seed}: {differences:?}");
            }
            other => panic!("seed {seed}: {other:?}"),
        }
    }
}
