//! Lemke with the equality block eliminated through a sparse factor
//! (`solver::equality_elimination`), called directly so that the dense
//! pivoted path cannot answer for it: against the brute-force active-set
//! enumeration on small random problems (independent and redundant
//! equality rows), and against clarabel at a tight gap on chains of joints
//! with contacts, whose equality block is banded.

use super::active_set_oracle::brute_force_dq;
use super::equality_rows::{DQ_TOL, push_redundant_rows, random_mixed};
use crate::support::solver_oracle::{constraint_values, relative_metric_distance};
use constraint_stabilization::solver::clarabel_qp::ClarabelSettings;
use constraint_stabilization::solver::equality_elimination;
use constraint_stabilization::solver::kept_analyses::KeptAnalyses;
use constraint_stabilization::solver::lemke::{LemkeSettings, LemkeStatus};
use constraint_stabilization::solver::{
    BodyMetric, JacobianRow, ProjectionQp, SolverChoice, SolverKind, SolverSettings,
    dq_from_lambda, solve_projection,
};
use nalgebra::{DVector, Matrix3, Vector6};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Random problems per shape.
const PROBLEMS: u64 = 12;
/// clarabel's gap for the reference on the chains.
const REFERENCE_GAP: f64 = 1e-12;
/// Agreement with the tight clarabel reference on the chains, relative in
/// the M-norm (measured: at most 4e-13).
const CHAIN_DQ_TOL: f64 = 1e-10;
/// Equality rows hold to this fraction of `||phi - target||_inf`.
const EQUALITY_HOLDS_TOL: f64 = 1e-9;

fn eliminated_dq(qp: &ProjectionQp) -> Result<DVector<f64>, LemkeStatus> {
    eliminated_dq_kept(qp, None)
}

fn eliminated_dq_kept(
    qp: &ProjectionQp,
    kept: Option<&KeptAnalyses>,
) -> Result<DVector<f64>, LemkeStatus> {
    let metric = qp.validate().expect("valid problem");
    equality_elimination::solve(qp, &metric, &LemkeSettings::default(), kept)
        .map(|sol| dq_from_lambda(qp, &metric, &sol.z))
        .map_err(|failure| failure.status)
}

#[test]
fn random_mixed_problems_match_the_enumeration() {
    for (equalities, inequalities) in [(1, 4), (2, 5), (3, 6), (4, 0)] {
        for seed in 0..PROBLEMS {
            let qp = random_mixed(seed, equalities, inequalities);
            let context = format!("E={equalities} I={inequalities} seed {seed}");
            let oracle = brute_force_dq(&qp).unwrap_or_else(|| panic!("{context}: no oracle"));
            let dq = eliminated_dq(&qp).unwrap_or_else(|s| panic!("{context}: {s:?}"));
            let distance = relative_metric_distance(&qp, &dq, &oracle);
            assert!(distance <= DQ_TOL, "{context}: dq off by {distance:e}");
        }
    }
}

/// A copy of an equality row and a combination of two more (consistent
/// values): the dropped pivots leave the feasible set and so `dq` alone.
#[test]
fn redundant_equality_rows_are_dropped() {
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    for seed in 0..PROBLEMS {
        let independent = random_mixed(200 + seed, 3, 4);
        let oracle = brute_force_dq(&independent).expect("independent rows: an oracle");
        let mut qp = independent.clone();
        push_redundant_rows(&mut qp, &mut rng, 0);
        let dq = eliminated_dq(&qp).unwrap_or_else(|s| panic!("seed {seed}: {s:?}"));
        let distance = relative_metric_distance(&qp, &dq, &oracle);
        assert!(distance <= DQ_TOL, "seed {seed}: dq off by {distance:e}");
    }
}

/// The same row twice on a unit body: the second pivot is exactly zero
/// (no rounding to hide behind), and the answer is one row's.
#[test]
fn an_exactly_repeated_row_is_dropped() {
    let x = Vector6::new(1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    let y = Vector6::new(0.0, 1.0, 0.0, 0.0, 0.0, 0.0);
    let qp = ProjectionQp {
        bodies: vec![BodyMetric {
            mass: 1.0,
            inertia_world: Matrix3::identity(),
        }],
        rows: [x, x, y]
            .into_iter()
            .map(|g| JacobianRow {
                blocks: vec![(0, g)],
            })
            .collect(),
        phi: vec![-0.1, -0.1, -0.01],
        target: vec![0.0; 3],
        num_equalities: 2,
        ..ProjectionQp::default()
    };
    let dq = eliminated_dq(&qp).expect("consistent rows");
    let expected = DVector::from_row_slice(&[0.1, 0.01, 0.0, 0.0, 0.0, 0.0]);
    assert!((dq - expected).amax() <= 1e-15);
}

/// Two rows asking one quantity for two values: the typed outcome.
#[test]
fn inconsistent_rows_are_reported() {
    let mut qp = random_mixed(7, 2, 3);
    qp.rows.insert(0, qp.rows[0].clone());
    qp.phi.insert(0, qp.phi[0] + 0.1);
    qp.target.insert(0, 0.0);
    qp.num_equalities += 1;
    match eliminated_dq(&qp) {
        Err(LemkeStatus::InconsistentEqualities { residual }) => assert!(residual > 1e-3),
        other => panic!("{other:?}"),
    }
}

fn random_block(rng: &mut ChaCha8Rng) -> Vector6<f64> {
    Vector6::from_fn(|_, _| rng.random_range(-1.0..1.0))
}

/// A chain of `links` bodies (masses over two decades), five equality rows
/// per joint between neighbours, joint values off by up to a millimetre,
/// and `contacts` penetrating or open rows on random links.
fn chain(seed: u64, links: usize, contacts: usize) -> ProjectionQp {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let bodies = (0..links)
        .map(|_| {
            let mass = 10f64.powf(rng.random_range(-1.0..1.0));
            BodyMetric {
                mass,
                inertia_world: Matrix3::identity() * 0.1 * mass,
            }
        })
        .collect();
    let mut qp = ProjectionQp {
        bodies,
        num_equalities: 5 * (links - 1),
        ..ProjectionQp::default()
    };
    for link in 1..links {
        for _ in 0..5 {
            qp.rows.push(JacobianRow {
                blocks: vec![
                    (link - 1, random_block(&mut rng)),
                    (link, random_block(&mut rng)),
                ],
            });
            qp.phi.push(rng.random_range(-1e-3..1e-3));
            qp.target.push(0.0);
        }
    }
    for _ in 0..contacts {
        let link = rng.random_range(0..links);
        qp.rows.push(JacobianRow {
            blocks: vec![(link, random_block(&mut rng))],
        });
        qp.phi.push(rng.random_range(-2e-3..1e-3));
        qp.target.push(0.0);
    }
    qp
}

/// Chains of 20 and 80 links (95 and 395 equality rows, a banded block)
/// with contacts: the equality rows hold and `dq` is clarabel's at a tight
/// gap. The seeds of one chain share the pattern of `A_EE`, so all but the
/// first solve of each chain reuse the symbolic analysis kept in one store
/// with new values.
#[test]
fn chains_with_contacts_match_clarabel() {
    let reference_settings = SolverSettings {
        choice: SolverChoice::Clarabel,
        fall_back: false,
        clarabel: ClarabelSettings {
            tol_gap: REFERENCE_GAP,
            tol_feas: REFERENCE_GAP,
            ..ClarabelSettings::default()
        },
        ..SolverSettings::default()
    };
    let kept = KeptAnalyses::default();
    for (links, contacts) in [(20, 6), (80, 12), (80, 0)] {
        for seed in 0..3 {
            let qp = chain(seed, links, contacts);
            let context = format!("{links} links, {contacts} contacts, seed {seed}");
            let dq =
                eliminated_dq_kept(&qp, Some(&kept)).unwrap_or_else(|s| panic!("{context}: {s:?}"));
            let w = constraint_values(&qp, &dq);
            let length = constraint_values(&qp, &DVector::zeros(dq.len())).amax();
            for i in 0..qp.num_equalities {
                assert!(
                    w[i].abs() <= EQUALITY_HOLDS_TOL * length,
                    "{context}: equality row {i} off by {:e}",
                    w[i]
                );
            }
            let reference = solve_projection(&qp, &reference_settings)
                .unwrap_or_else(|e| panic!("{context}: clarabel: {e}"));
            let distance = relative_metric_distance(&qp, &dq, &reference.dq);
            assert!(
                distance <= CHAIN_DQ_TOL,
                "{context}: dq off by {distance:e}"
            );
            // `Auto` counts the inequality rows against Lemke's limit: the
            // 80-link chain's 395 equality rows do not send it to clarabel.
            let auto = solve_projection(&qp, &SolverSettings::default())
                .unwrap_or_else(|e| panic!("{context}: auto: {e}"));
            assert_eq!(auto.solver, SolverKind::Lemke, "{context}");
            // One numeric factorization of the equality block, reported.
            assert_eq!(auto.factorizations, 1, "{context}");
            assert!(auto.fallbacks.is_empty(), "{context}: {:?}", auto.fallbacks);
            let distance = relative_metric_distance(&qp, &auto.dq, &reference.dq);
            assert!(
                distance <= CHAIN_DQ_TOL,
                "{context}: auto dq off by {distance:e}"
            );
        }
    }
}

/// A kept analysis skips work, never changes an answer: the multipliers
/// from a store that already holds the pattern are bit for bit those of a
/// solve that makes its own analysis, and the store keeps one analysis per
/// pattern (the equality block's pattern follows the joints, not the
/// contacts or the values).
#[test]
fn a_kept_analysis_changes_no_answer() {
    let kept = KeptAnalyses::default();
    for (links, contacts, patterns) in [(20, 6, 1), (20, 0, 1), (80, 12, 2)] {
        for seed in 0..3 {
            let qp = chain(seed, links, contacts);
            let alone = eliminated_dq(&qp).expect("solved");
            let with_store = eliminated_dq_kept(&qp, Some(&kept)).expect("solved");
            assert_eq!(
                alone.as_slice(),
                with_store.as_slice(),
                "{links} links, seed {seed}"
            );
            assert_eq!(kept.len(), patterns, "{links} links, seed {seed}");
        }
    }
    assert!(kept.bytes() > 0);
    kept.clear();
    assert!(kept.is_empty());
    assert_eq!(kept.bytes(), 0);
}
